#version 450
#extension GL_GOOGLE_include_directive : require
// The hash build, scan 3 of 3: within each chunk, the exclusive prefix sum of the counts from
// the chunk's offset gives each slot's start. The counts stay: the scatter counts them down.
#define HASH_BUILD
#include "contact/hash_common.glsl"

void main()
{
    for (uint c = gl_GlobalInvocationID.x; c < pc.chunks; c += hash_stride()) {
        uint running = hash_scratch[pc.slots + c];
        uint first = c * pc.chunk;
        for (uint k = 0u; k < pc.chunk; k++) {
            uint n = hash_scratch[first + k];
            hash_starts[first + k] = running;
            running += n;
        }
    }
}
