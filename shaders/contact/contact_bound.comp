#version 450
#extension GL_GOOGLE_include_directive : require
// Detection's last pass (lib/contact/collide.h): each particle's bound, gamma times the
// nearest distance from it (from a face around it or from an edge at it to anything not
// adjacent that detection found within the contact radius; the radius where nothing was) less
// the gap floor (shared/layout.h: CVK_GAP_FLOOR_*), and where it is now; its nearest distance
// is cleared for the next detection, its list of the pairs in which it is a feature's corner
// sorted, and a free particle in some pair listed for the cloth contact pass.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#define CONTACT_TYPES_ID 1
#include "contact/collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

#include "contact/contact_bound.glsl"

void main()
{
    if (pc.count == 0u)
        return;
    uint crowded = 0u;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
        crowded += bound_one(pc.first + i, pc.per_group);
    add_crowded(crowded);
}
