#version 450
#extension GL_GOOGLE_include_directive : require
// The hash build, sort: each slot's entries into ascending point order (insertion sort, one
// invocation per slot), so queries visit points in an order that does not depend on timing.
// Slots hold about one point on average (table_size ≥ 2 · capacity) and the scatter leaves
// them nearly sorted, so the quadratic worst case is rare.
#define HASH_BUILD
#include "hash_common.glsl"

void main()
{
    for (uint s = gl_GlobalInvocationID.x; s < pc.slots; s += hash_stride()) {
        uint first = hash_starts[s];
        uint end = hash_starts[s + 1u];
        for (uint i = first + 1u; i < end; i++) {
            uint v = hash_entries[i];
            uint j = i;
            while (j > first && hash_entries[j - 1u] > v) {
                hash_entries[j] = hash_entries[j - 1u];
                j--;
            }
            hash_entries[j] = v;
        }
    }
}
