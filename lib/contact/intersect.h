/* Exact host-side check of a triangle soup for self-intersection: pairs of triangles that share
   no vertex and intersect (touching counts; coplanar overlaps count). A uniform grid over the
   triangles' boxes keeps it near-linear. Used by cvk_sim_count_intersections, the statistics,
   the tests and the benchmark. */
#ifndef CVK_INTERSECT_H
#define CVK_INTERSECT_H

#include "clothvk.h"

/* Triangles with three equal indices (torn) are skipped. CVK_ERROR_OUT_OF_MEMORY is the only
   failure. */
cvk_result cvk_count_intersecting_pairs(const float* xyz, uint32_t vertex_count,
                                        const uint32_t* triangles, uint32_t triangle_count,
                                        uint64_t* out_pairs, cvk_error* error);

/* Whether two triangles (9 floats each) intersect: the exact predicate the count uses. */
bool cvk_triangles_intersect(const float a[9], const float b[9]);

/* Squared distance from p to the closed triangle (a, b, c), in double: the host's measure of
   cloth contact (the contact statistics, the search's brute-force test). */
double cvk_point_triangle_distance2(const double p[3], const double a[3], const double b[3],
                                    const double c[3]);

#endif
