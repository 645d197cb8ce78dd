#version 450
#extension GL_GOOGLE_include_directive : require
// Adaptive candidate search, first half (lib/collide.h), in two phases over the particles:
// 0: the bounds of every displacement since the last search (d = x - where the search saw the
// particle), per axis; 1: the farthest any d is from the centre c of those bounds, to the frame
// state. Two particles' displacements differ by at most twice that, whatever c is: a cloth that
// moves as one needs no search. Atomic min and max on order-preserving bits of the floats, so
// the result does not depend on thread timing.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

// Bits of a float that order as the float does (as unsigned integers), and back.
uint ordered(float f)
{
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}

float from_ordered(uint u)
{
    return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7fffffffu : ~u);
}

void main()
{
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (pc.phase == 0u) {
        vec3 low = vec3(3.0e38), high = vec3(-3.0e38);
        for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += stride) {
            uint p = pc.first + i;
            vec3 d = contact_x(p) - texelFetch(searched_t, int(p)).xyz;
            low = min(low, d); // a non-finite d is left to phase 1
            high = max(high, d);
        }
        if (low.x <= high.x) {
            atomicMin(motion_bounds.low_x, ordered(low.x));
            atomicMin(motion_bounds.low_y, ordered(low.y));
            atomicMin(motion_bounds.low_z, ordered(low.z));
            atomicMax(motion_bounds.high_x, ordered(high.x));
            atomicMax(motion_bounds.high_y, ordered(high.y));
            atomicMax(motion_bounds.high_z, ordered(high.z));
        }
        return;
    }
    vec3 centre = vec3(0.0);
    if (motion_bounds.low_x != CVK_MOTION_LOW_EMPTY) {
        vec3 low = vec3(from_ordered(motion_bounds.low_x), from_ordered(motion_bounds.low_y),
                        from_ordered(motion_bounds.low_z));
        vec3 high = vec3(from_ordered(motion_bounds.high_x), from_ordered(motion_bounds.high_y),
                         from_ordered(motion_bounds.high_z));
        centre = 0.5 * low + 0.5 * high;
    }
    float farthest = 0.0;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += stride) {
        uint p = pc.first + i;
        farthest = max(farthest, distance(contact_x(p) - texelFetch(searched_t, int(p)).xyz, centre));
    }
    // A non-finite position (a cloth that blew up) searches every substep rather than never.
    if (!(farthest <= 3.0e38))
        farthest = 3.0e38;
    if (farthest > 0.0)
        atomicMax(frame.moved, floatBitsToUint(farthest));
}
