#version 450
#extension GL_GOOGLE_include_directive : require
// The hash build, clear: the parameters from the push data; with no points, every start zeroed
// so queries find nothing. (The counts are 0 already: zeroed at creation, and every build's
// scatter counts them back down.) A dispatch rather than buffer fills, so the whole build
// orders itself with compute barriers alone (a fill would need the op before it, possibly
// another module's, to wait for transfers too).
#define HASH_BUILD
#include "contact/hash_common.glsl"

void main()
{
    if (gl_GlobalInvocationID.x == 0u) {
        if (pc.cell_size > 0.0) { // 0: written on the device before the build (hash.h)
            hash_params.cell_size = pc.cell_size;
            hash_params.inv_cell = pc.inv_cell;
        }
        hash_params.table_size = pc.slots;
        hash_params.count = pc.points;
        if (pc.points == 0u)
            hash_starts[pc.slots] = 0u;
    }
    if (pc.points == 0u)
        for (uint s = gl_GlobalInvocationID.x; s < pc.slots; s += hash_stride())
            hash_starts[s] = 0u;
}
