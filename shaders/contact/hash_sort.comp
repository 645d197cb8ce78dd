#version 450
#extension GL_GOOGLE_include_directive : require
// The hash build, sort: the scatter left each slot's points in the order its atomics happened
// (in scratch); each point's place in its slot is the number of the slot's points with a
// smaller index, so entries come out in ascending point order whatever the timing (and with
// them, a copy of each point with its index, for queries). One point
// per invocation (lib/contact/hash.c): the loop is as long as the point's slot is full, and lavapipe
// ends a shader's loops after 65535 iterations in all.
#define HASH_BUILD
#include "contact/hash_common.glsl"

void main()
{
    uint unsorted = pc.slots + pc.chunks;
    for (uint p = gl_GlobalInvocationID.x; p < pc.points; p += hash_stride()) {
        uint s = hash_keys[p];
        uint first = hash_starts[s];
        uint end = hash_starts[s + 1u];
        uint rank = 0u;
        for (uint e = first; e < end; e++)
            rank += hash_scratch[unsorted + e] < p ? 1u : 0u;
        hash_entries[first + rank] = p;
        hash_sorted[first + rank] = uvec4(floatBitsToUint(hash_point(p)), p);
    }
}
