#version 450
#extension GL_GOOGLE_include_directive : require
// Adaptive candidate search, first half (lib/collide.h): how far each particle is from where
// the last search saw it; the farthest goes to the frame state (atomicMax on the bits of a
// non-negative float orders like the float, so the result does not depend on thread timing).
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

void main()
{
    float farthest = 0.0;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint p = pc.first + i;
        farthest = max(farthest, distance(contact_x(p), searched[p].xyz));
    }
    // A non-finite position (a cloth that blew up) searches every substep rather than never.
    if (!(farthest <= 3.0e38))
        farthest = 3.0e38;
    if (farthest > 0.0)
        atomicMax(frame.moved, floatBitsToUint(farthest));
}
