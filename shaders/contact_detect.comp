#version 450
#extension GL_GOOGLE_include_directive : require
// Placeholder until the spatial hash lands: no particle–triangle candidates.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
        for (uint k = 0u; k < uint(CVK_CONTACTS_PER_PARTICLE); k++)
            contacts[(pc.first + i) * uint(CVK_CONTACTS_PER_PARTICLE) + k] = CVK_NO_CONTACT;
}
