#version 450
#extension GL_GOOGLE_include_directive : require
// Picking (lib/features/pick.h, seed 002 §5.3.8): every particle checks whether the ray passes within
// pc.radius of it, in front of the origin, and the hits compete for the smallest distance along
// the ray, t = (x - o).d. Deterministic without float atomics, in three dispatches: stage 0
// takes the atomicMin of t's bits (a non-negative float's bits order like the float), stage 1
// the atomicMin of the user index among the hits at exactly that t (the same code on the same
// input gives the same bits), stage 2 copies the winner's position. Runs outside the frame, as
// a query.
layout(local_size_x = 64) in;

#include "shared/layout.h"

layout(std430, set = 0, binding = CVK_PICK_BINDING_POSITIONS) readonly buffer Positions {
    vec4 x[];
};
layout(std430, set = 0, binding = CVK_PICK_BINDING_USER_OF) readonly buffer UserOf {
    uint user_of[];
};
layout(std430, set = 0, binding = CVK_PICK_BINDING_RESULT) buffer Result { cvk_gpu_pick result; };
CVK_DECLARE_PUSH(CVK_PICK_PUSH_FIELDS)

// The bits of t when the ray passes within the radius of p in front of the origin, else NONE.
uint hit_bits(uint p)
{
    vec3 v = x[p].xyz - pc.origin.xyz;
    float t = dot(v, pc.direction.xyz);
    vec3 w = v - t * pc.direction.xyz;
    if (!(t >= 0.0) || !(dot(w, w) <= pc.radius2))
        return CVK_PICK_NONE;
    return t > 0.0 ? floatBitsToUint(t) : 0u; // -0.0 counts as 0
}

void main()
{
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += stride) {
        if (pc.stage == 2u) {
            if (user_of[p] == result.user)
                result.position = vec4(x[p].xyz, 1.0);
            continue;
        }
        uint bits = hit_bits(p);
        if (bits == CVK_PICK_NONE)
            continue;
        if (pc.stage == 0u)
            atomicMin(result.distance_bits, bits);
        else if (bits == result.distance_bits)
            atomicMin(result.user, user_of[p]);
    }
}
