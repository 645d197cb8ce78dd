/* Triangle edges keyed by their two vertices (lib/render/edge_key.h). */
#include "render/edge_key.h"

#include <stdlib.h>

int cvk_compare_edge_ends(const void* pa, const void* pb)
{
    const cvk_edge_key *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    return a->hi < b->hi ? -1 : a->hi > b->hi;
}

static int compare_edge_keys(const void* pa, const void* pb)
{
    const cvk_edge_key *a = pa, *b = pb;
    int ends = cvk_compare_edge_ends(a, b);
    if (ends != 0)
        return ends;
    if (a->other != b->other)
        return a->other < b->other ? -1 : 1;
    return a->triangle < b->triangle ? -1 : a->triangle > b->triangle;
}

void cvk_sort_edge_keys(cvk_edge_key* keys, size_t n)
{
    qsort(keys, n, sizeof *keys, compare_edge_keys);
}
