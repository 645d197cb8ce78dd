#version 450
#extension GL_GOOGLE_include_directive : require
// Detection's last pass (lib/contact/collide.h): each particle's bound, gamma times the
// nearest distance from it, from a face around it or from an edge at it to anything not
// adjacent that detection found within the contact radius (the radius where nothing was), and
// where it is now; its nearest distance is cleared for the next detection.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

void main()
{
    if (pc.count == 0u)
        return;
    uint base = contact_u.particle_count + 1u;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint p = pc.first + i;
        float d = min(contact_u.radius, uintBitsToFloat(nearest[p]));
        for (uint o = particle_edge(p); o < particle_edge(p + 1u); o++)
            d = min(d, uintBitsToFloat(nearest[contact_u.particle_count + particle_edge(base + o)]));
        searched[p] = vec4(contact_x(p), contact_u.gamma * d);
        nearest[p] = 0x7f7f7f7fu; // 3.4e38: none yet (as lib/contact/collide.c fills it)
    }
}
