#version 450
#extension GL_GOOGLE_include_directive : require
// The neighbour query over the spatial hash (set 1): for each point, how many other points lie
// within the radius and the sum of their indices (mod 2^32), over the 27 cells around it. Tests
// compare both with a brute force; the benchmark times it; contact detection follows the same
// pattern (hash_common.glsl).
#define HASH_SET 1
#include "contact/hash_common.glsl"

layout(local_size_x_id = 0) in;

layout(std430, set = 0, binding = 0) writeonly buffer Found { uvec2 found[]; };

CVK_DECLARE_PUSH(CVK_HASH_QUERY_PUSH_FIELDS)

void main()
{
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += stride) {
        vec3 x = hash_point(p);
        ivec3 home = hash_cell(x);
        uvec2 result = uvec2(0u);
        for (uint n = 0u; n < 27u; n++) {
            ivec3 cell = hash_neighbour_cell(home, n);
            uvec2 range = hash_range(cell);
            for (uint e = range.x; e < range.y; e++) {
                uint q = hash_entry_point(e).w;
                if (q == p || !hash_in_cell(q, cell))
                    continue;
                vec3 d = hash_point(q) - x;
                if (dot(d, d) <= pc.radius2)
                    result += uvec2(1u, q);
            }
        }
        found[p] = result;
    }
}
