#version 450
#extension GL_GOOGLE_include_directive : require
// The hash build, scatter: each point takes a place of its slot's range in the unsorted copy of
// the entries at the end of scratch, counting the slot's count down (atomic); the order within
// a slot depends on timing until the sort pass. Every count ends at 0, ready for the next build
// without a clear (lib/contact/hash.c zeroes them once, at creation).
#define HASH_BUILD
#include "contact/hash_common.glsl"

void main()
{
    uint unsorted = pc.slots + pc.chunks;
    for (uint p = gl_GlobalInvocationID.x; p < pc.points; p += hash_stride()) {
        uint s = hash_keys[p];
        uint e = hash_starts[s] + atomicAdd(hash_scratch[s], 0xffffffffu) - 1u;
        hash_scratch[unsorted + e] = p;
    }
}
