#version 450
#extension GL_GOOGLE_include_directive : require
// The hash build, scatter: each point takes the next entry of its slot's range (an atomic
// cursor per slot). The order within a slot depends on timing until the sort pass.
#define HASH_BUILD
#include "hash_common.glsl"

void main()
{
    for (uint p = gl_GlobalInvocationID.x; p < pc.points; p += hash_stride()) {
        uint s = hash_keys[p];
        uint e = hash_starts[s] + atomicAdd(hash_scratch[s], 1u);
        hash_entries[e] = p;
    }
}
