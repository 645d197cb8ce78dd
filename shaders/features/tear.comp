#version 450
#extension GL_GOOGLE_include_directive : require
// Tearing (lib/features/tear.h), once per substep once its positions are final: every spring of a
// tearing cloth whose length passes its breaking length is marked dead and its stiffness
// leaves both ends' adjacency (k set to 0), so the solver forgets it: every
// projective-dynamics sweep, the diagonal and the divergence watch multiply what they read of
// a spring by k (its rest length stays), and the implicit and explicit families take k = 0 as
// no spring (no force, no damping). Each
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
CVK_DECLARE_PUSH(CVK_TEAR_PUSH_FIELDS)

// Sets k of one end's entry to 0: the bits of 0.0 are 0.
void forget(uint k)
{
    if (k != CVK_TEAR_NONE)
        adjacency[k] = 0u;
}

void main()
{
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += stride) {
        uvec4 spring = texelFetch(table, int(2u * i));
        vec3 d = texelFetch(x, int(spring.x)).xyz - texelFetch(x, int(spring.y)).xyz;
        if (!(dot(d, d) > uintBitsToFloat(spring.w)))
            continue;
        // Both families' element indices come ready in the row's second texel: the pass only
        // picks its half (with the indices computed here, a division per torn spring, the
        // pass took twice its share of tear.json's frame on lavapipe: 7 % against 3.5 %).
        uvec4 ends = texelFetch(table, int(2u * i + 1u));
        alive[spring.z] = 0u;
        forget(pc.entries != 0u ? ends.z : ends.x);
        forget(pc.entries != 0u ? ends.w : ends.y);
    }
}
