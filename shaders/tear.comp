#version 450
#extension GL_GOOGLE_include_directive : require
// Tearing (lib/tear.h), once per substep once its positions are final: every spring of a
// tearing cloth whose length passes its breaking length is marked dead and its stiffness
// leaves both ends' adjacency (k, and k·L for projective dynamics, set to 0), so the solver
// forgets it: every projective-dynamics sweep, the diagonal and the divergence watch with no
// test of their own; the implicit and explicit families take k = 0 as no spring (no force, no
// damping). Each
// invocation writes only its own spring's flag and slots: no order between invocations
// matters, and the same springs break for every dispatch shape. Tearing again a spring already
// torn writes the same zeros, so dead springs need no test either.
layout(local_size_x_id = 0) in;

#include "shared/layout.h"

layout(set = 0, binding = CVK_TEAR_BINDING_POSITIONS) uniform samplerBuffer x;
layout(set = 0, binding = CVK_TEAR_BINDING_TABLE) uniform usamplerBuffer table;
layout(std430, set = 0, binding = CVK_TEAR_BINDING_ALIVE) writeonly buffer Alive { uint alive[]; };
layout(std430, set = 0, binding = CVK_TEAR_BINDING_ADJACENCY) writeonly buffer Adjacency {
    uint adjacency[];
};
layout(std430, set = 0, binding = CVK_TEAR_BINDING_ADJACENCY_KL) writeonly buffer AdjacencyKL {
    float adjacency_kl[];
};
CVK_DECLARE_PUSH(CVK_TEAR_PUSH_FIELDS)

// Sets the k of adjacency entry e (slot * stride + particle) to 0 (the bits of 0.0 are 0).
void forget(uint e)
{
    if (e == CVK_TEAR_NONE)
        return;
    if (pc.packing == CVK_TEAR_LAYOUT_UVEC4) {
        adjacency[4u * e + 1u] = 0u;
        return;
    }
    uint p = e % pc.stride, slot = e / pc.stride, q = slot / 4u, j = slot % 4u;
    adjacency[4u * ((2u * q + 1u) * pc.stride + p) + j] = 0u;
    adjacency_kl[4u * (q * pc.stride + p) + j] = 0.0;
}

void main()
{
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += stride) {
        uvec4 spring = texelFetch(table, int(2u * i));
        vec3 d = texelFetch(x, int(spring.x)).xyz - texelFetch(x, int(spring.y)).xyz;
        if (!(dot(d, d) > uintBitsToFloat(spring.w)))
            continue;
        uvec4 entries = texelFetch(table, int(2u * i + 1u));
        alive[spring.z] = 0u;
        forget(entries.x);
        forget(entries.y);
    }
}
