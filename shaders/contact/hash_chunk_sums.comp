#version 450
#extension GL_GOOGLE_include_directive : require
// The hash build, scan 1 of 3: the sum of the counts of each chunk of `chunk` slots, one
// invocation per chunk, into scratch[slots + chunk index]. A serial loop per invocation and no
// shared memory: on lavapipe a workgroup barrier costs more than the loop.
#define HASH_BUILD
#include "contact/hash_common.glsl"

void main()
{
    for (uint c = gl_GlobalInvocationID.x; c < pc.chunks; c += hash_stride()) {
        uint first = c * pc.chunk;
        uint sum = 0u;
        for (uint k = 0u; k < pc.chunk; k++)
            sum += hash_scratch[first + k];
        hash_scratch[pc.slots + c] = sum;
    }
}
