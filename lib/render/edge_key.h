/* Triangle edges keyed by their two vertices and sorted so that the keys of one edge lie
   together: lib/render/split.c pairs the triangles on an edge into quads, lib/render/mesh.c
   finds the edges of the cloth's border and its rims. */
#ifndef CVK_EDGE_KEY_H
#define CVK_EDGE_KEY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* One triangle's edge, keyed by its two vertices, lower first; slot: its place in the
   triangle (from vertex slot to the next); other: 1 where it is from the triangle's other
   split's row (lib/render/split.h), else 0. */
typedef struct cvk_edge_key {
    uint32_t lo, hi, triangle, slot, other;
} cvk_edge_key;

/* The key of the edge from vertex a to b. */
static inline cvk_edge_key cvk_edge_key_of(uint32_t a, uint32_t b, uint32_t triangle, uint32_t slot,
                                           uint32_t other)
{
    return (cvk_edge_key){a < b ? a : b, a < b ? b : a, triangle, slot, other};
}

static inline bool cvk_same_edge(const cvk_edge_key* a, const cvk_edge_key* b)
{
    return a->lo == b->lo && a->hi == b->hi;
}

/* qsort/bsearch order of two keys by their ends alone: the search for an edge. */
int cvk_compare_edge_ends(const void* a, const void* b);

/* Sorts n keys by their ends, then on one edge the triangles' own rows before the other
   splits' rows, then by triangle. */
void cvk_sort_edge_keys(cvk_edge_key* keys, size_t n);

#endif
