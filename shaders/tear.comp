#version 450
#extension GL_GOOGLE_include_directive : require
// Tearing (lib/tear.h), once per substep after finalize: every spring of a tearing cloth whose
// length in the substep's final positions passes its breaking length is marked dead and its
// stiffness leaves both ends' adjacency (k and k·L set to 0), so every projective-dynamics
// sweep, the diagonal and the divergence watch forget it with no test of their own. Each
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

void main()
{
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += stride) {
        uvec4 spring = texelFetch(table, int(2u * i));
        vec3 d = texelFetch(x, int(spring.x)).xyz - texelFetch(x, int(spring.y)).xyz;
        if (!(dot(d, d) > uintBitsToFloat(spring.w)))
            continue;
        uvec4 slots = texelFetch(table, int(2u * i + 1u));
        alive[spring.z] = 0u;
        if (slots.x != CVK_TEAR_NONE) {
            adjacency[slots.x] = 0u; // the bits of k = 0.0
            adjacency_kl[slots.y] = 0.0;
        }
        if (slots.z != CVK_TEAR_NONE) {
            adjacency[slots.z] = 0u;
            adjacency_kl[slots.w] = 0.0;
        }
    }
}
