#version 450
#extension GL_GOOGLE_include_directive : require
// The hash build, count: each point's slot (its cell's, with its salt) into keys, and one
// more in its slot's count (scratch[slot], zeroed by the fill before this pass).
#define HASH_BUILD
#include "contact/hash_common.glsl"

void main()
{
    for (uint p = gl_GlobalInvocationID.x; p < pc.points; p += hash_stride()) {
        uint s = hash_slot(hash_cell(hash_point(p)), hash_salt(p));
        hash_keys[p] = s;
        atomicAdd(hash_scratch[s], 1u);
    }
}
