/* Exact host-side check of a triangle soup for self-intersection: pairs of triangles that share
   no vertex and intersect (touching counts; coplanar overlaps count). A uniform grid over the
   triangles' boxes keeps it near-linear. Used by cvk_sim_count_intersections, the statistics,
   the tests and the benchmark, and (the first pair) by the clean-start check of cvk_sim_create. */
#ifndef CVK_INTERSECT_H
#define CVK_INTERSECT_H

#include "clothvk.h"

/* Triangles with three equal indices (torn) are skipped. groups (NULL: one group) gives each
   triangle a group, and only pairs of one group are tested (the scene's instances, which never
   touch one another). CVK_ERROR_OUT_OF_MEMORY is the only failure. */
cvk_result cvk_count_intersecting_pairs(const float* xyz, uint32_t vertex_count,
                                        const uint32_t* triangles, const uint32_t* groups,
                                        uint32_t triangle_count,
                                        uint64_t* out_pairs, cvk_error* error);

/* The lowest intersecting pair of the same soup (the same predicate and grid as the count,
   as near-linear): of the pairs that share no vertex and intersect, the one with the smallest
   first index, and of those the smallest second. found is false when there is none. */
typedef struct cvk_intersecting_pair {
    bool found;
    uint32_t first, second;  /* triangle indices, first < second */
    float near[3];           /* m: the midpoint of the two triangles' centroids, within a
                                triangle's size of where they meet */
} cvk_intersecting_pair;

cvk_result cvk_first_intersecting_pair(const float* xyz, uint32_t vertex_count,
                                       const uint32_t* triangles, const uint32_t* groups,
                                       uint32_t triangle_count,
                                       cvk_intersecting_pair* out, cvk_error* error);

/* Every pair of `count` closed boxes (6 floats each: min xyz, max xyz, all finite) that
   overlap, handed once to pair(user, i, j) with i < j, through a uniform grid (near-linear for
   boxes of about one size); with `split` > 0 only the pairs with i < split <= j (two sets of
   boxes, each met against the other alone). `what` begins the message of the only failure,
   CVK_ERROR_OUT_OF_MEMORY. The count below and the contact statistics' particle–triangle
   pairs (lib/sim/sim_contact.c) are its callers. */
typedef void (*cvk_box_pair_fn)(void* user, uint32_t i, uint32_t j);

cvk_result cvk_box_pairs(const float* boxes, uint32_t count, uint32_t split, cvk_box_pair_fn pair,
                         void* user, const char* what, cvk_error* error);

/* Whether two triangles (9 floats each) intersect: the exact predicate the count uses. */
bool cvk_triangles_intersect(const float a[9], const float b[9]);

/* Squared distance from p to the closed triangle (a, b, c), in double: the host's measure of
   cloth contact (the contact statistics, the search's brute-force test). */
double cvk_point_triangle_distance2(const double p[3], const double a[3], const double b[3],
                                    const double c[3]);

#endif
