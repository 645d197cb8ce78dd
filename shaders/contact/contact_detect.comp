#version 450
#extension GL_GOOGLE_include_directive : require
// The faces' detection, one item a particle (contact/contact_detect.glsl says what it does).
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#define CONTACT_TYPES_ID 1
#include "contact/collide.glsl"
#define HASH_SET 1
#include "contact/hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)
#include "contact/contact_detect.glsl"

void work()
{
    if (pc.count == 0u)
        return;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
        detect(pc.first + i);
}

void main()
{
    work();
    note_loops_cut(pc.count); // after the work, whatever it returned from (bounds.glsl)
}
