#version 450
#extension GL_GOOGLE_include_directive : require
// The hash build, scan 2 of 3: one invocation turns the chunk sums into their exclusive prefix
// sums (in place) and writes the total, the end of the last slot, to starts[slots]. Chunks
// are about sqrt(slots), so this serial loop is as short as each chunk's.
#define HASH_BUILD
#include "contact/hash_common.glsl"

void main()
{
    if (gl_GlobalInvocationID.x != 0u)
        return;
    uint running = 0u;
    for (uint c = 0u; c < pc.chunks; c++) {
        uint sum = hash_scratch[pc.slots + c];
        hash_scratch[pc.slots + c] = running;
        running += sum;
    }
    hash_starts[pc.slots] = running;
}
