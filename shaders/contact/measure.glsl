// Detection's first phase (contact_edges.comp phase 1; contact_faces_fused.comp where the plan
// fuses): the edges' midpoints and ends and the triangles' centroids for the hashes, and the
// reach the hashes' cells take from them. Include after contact/collide.glsl.
#ifndef CONTACT_MEASURE_GLSL
#define CONTACT_MEASURE_GLSL

layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_MIDPOINTS) writeonly buffer Midpoints {
    vec4 midpoints[];
};
// MEASURE_COHERENT: the centroids read back in the same dispatch (contact_faces_fused.comp, whose
// hash build hashes them).
#ifdef MEASURE_COHERENT
#define CENTROIDS_ACCESS coherent
#else
#define CENTROIDS_ACCESS writeonly
#endif
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_CENTROIDS) CENTROIDS_ACCESS buffer Centroids {
    vec4 centroids[];
};
// Per edge its ends at detection (two uvec4: each end's position bits and index, read through
// edge_ends_t), then the cell lists' entries, a word each (CELL_POOL_WORD). Declared in uvec4
// so that an edge's ends are two stores: a storage store in a loop is a loop over the lanes on
// lavapipe, and eight word stores an edge were most of phase 1.
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_CELL_POOL) DETECT_WRITEONLY DETECT_COHERENT buffer CellPool {
    uvec4 cell_pool[];
};
#define CELL_POOL_WORD(i) cell_pool[(i) >> 2u][(i) & 3u]
// Word i of the pool as detection reads it.
#define CELL_POOL(i) DETECT_READ(CELL_POOL_WORD(i), imageLoad(cell_pool_t, int(i)).x)

// Phase 1, before detection: the longest edge now, which bounds how far apart the midpoints
// of two near edges are (an atomic maximum on the float's bits, which order as non-negative
// floats do), the midpoints, and each edge's nearest distance reset; and for the faces'
// detection (contact_detect.comp) the triangles' centroids and the farthest a corner is from
// its centroid, which bounds how far from a point the centroid of a triangle within the
// radius of it is. The dispatch covers the edges; its invocations stride over the triangles
// too.
void measure_longest(uint first, uint count, uint index, uint stride)
{
    float longest = 0.0;
    for (uint i = index; i < count; i += stride) {
        uvec2 ab = contact_edge(first + i);
        vec3 xa = contact_x(ab.x), xb = contact_x(ab.y);
        longest = max(longest, distance(xa, xb));
        midpoints[first + i] = vec4(0.5 * (xa + xb), 0.0);
        cell_pool[2u * (first + i)] = uvec4(floatBitsToUint(xa), ab.x);
        cell_pool[2u * (first + i) + 1u] = uvec4(floatBitsToUint(xb), ab.y);
        nearest[contact_u.particle_count + first + i] = 0x7f7f7f7fu; // 3.4e38: none yet
        nearest[contact_u.particle_count + contact_u.edge_count + first + i] = 0u;
    }
    atomicMax(frame.longest, floatBitsToUint(longest));
    float spread = 0.0;
    for (uint t = index; t < contact_u.triangle_count; t += stride) {
        uvec4 tri = contact_triangle(t);
        vec3 a = contact_x(tri.x), b = contact_x(tri.y), c = contact_x(tri.z);
        vec3 g = triangle_centroid(a, b, c);
        spread = max(spread, corner_reach(a, b, c, g));
        centroids[t] = vec4(g, 0.0);
    }
    atomicMax(motion_bounds.spread, floatBitsToUint(spread));
}

#endif
