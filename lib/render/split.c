/* The other split of quads that can tear along their split diagonal (lib/render/split.h). */
#include "render/split.h"

#include <stdlib.h>
#include <string.h>

#include "features/tear.h"

/* One triangle's edge, keyed by its two vertices, lower first; slot: its place in the
   triangle (from vertex slot to the next). */
typedef struct edge_key {
    uint32_t lo, hi, triangle, slot;
} edge_key;

static int compare_edge_keys(const void* pa, const void* pb)
{
    const edge_key *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return a->triangle < b->triangle ? -1 : a->triangle > b->triangle;
}

/* By the ends alone: the search for the spring across a quad. */
static int compare_ends(const void* pa, const void* pb)
{
    const edge_key *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    return a->hi < b->hi ? -1 : a->hi > b->hi;
}

static bool same_edge(const edge_key* a, const edge_key* b)
{
    return a->lo == b->lo && a->hi == b->hi;
}

/* Pairs the triangles on each edge with two of them and fills the pairs' other splits. */
static void pair_quads(const cvk_build* b, const bool* tearable, const edge_key* keys,
                       const edge_key* shear, uint32_t shear_count, cvk_other_split* out)
{
    size_t n = 3 * (size_t)b->triangle_count;
    const uint32_t* tv = b->triangles;
    const uint32_t* ts = b->triangle_springs;
    for (size_t i = 0; i + 1 < n; i++) {
        const edge_key* h0 = &keys[i];
        const edge_key* h1 = &keys[i + 1];
        if (!same_edge(h0, h1) || (i + 2 < n && same_edge(h0, &keys[i + 2])) ||
            (i > 0 && same_edge(h0, &keys[i - 1])))
            continue; /* two triangles on the edge, no more */
        uint32_t t0 = h0->triangle, t1 = h1->triangle, s0 = h0->slot, s1 = h1->slot;
        uint32_t split = ts[3 * (size_t)t0 + s0];
        if (split == UINT32_MAX || !tearable[split] || b->springs[split].type != CVK_SPRING_SHEAR)
            continue;
        uint32_t p = tv[3 * (size_t)t0 + s0], q = tv[3 * (size_t)t0 + (s0 + 1) % 3];
        if (tv[3 * (size_t)t1 + s1] != q) /* wound against its neighbour */
            continue;
        uint32_t o0 = tv[3 * (size_t)t0 + (s0 + 2) % 3], o1 = tv[3 * (size_t)t1 + (s1 + 2) % 3];
        uint32_t i0 = b->internal_of[o0], i1 = b->internal_of[o1];
        edge_key key = {i0 < i1 ? i0 : i1, i0 < i1 ? i1 : i0, 0, 0};
        const edge_key* across = bsearch(&key, shear, shear_count, sizeof *shear, compare_ends);
        if (!across || o0 == o1 || out[t0].across != UINT32_MAX || out[t1].across != UINT32_MAX)
            continue; /* no spring across, or a triangle already in another quad */
        /* (o0, p, o1): edges o0 − p (t0's), p − o1 (t1's), o1 − o0 (across); (o0, o1, q):
           o0 − o1 (across), o1 − q (t1's), q − o0 (t0's) */
        uint32_t a = across->triangle; /* the spring's index, kept in `triangle` */
        out[t0] = (cvk_other_split){{o0, p, o1},
                                    {ts[3 * (size_t)t0 + (s0 + 2) % 3], ts[3 * (size_t)t1 + (s1 + 1) % 3], a},
                                    split, a};
        out[t1] = (cvk_other_split){{o0, o1, q},
                                    {a, ts[3 * (size_t)t1 + (s1 + 2) % 3], ts[3 * (size_t)t0 + (s0 + 1) % 3]},
                                    split, a};
    }
}

cvk_result cvk_other_splits(const cvk_sim* s, cvk_other_split** out, cvk_error* error)
{
    *out = NULL;
    const cvk_build* b = &s->build;
    const cvk_tear* tear = s->tear;
    if (!tear || tear->count == 0 || b->triangle_count == 0)
        return CVK_SUCCESS;
    uint32_t shear_count = 0;
    for (uint32_t i = 0; i < b->spring_count; i++)
        shear_count += b->springs[i].type == CVK_SPRING_SHEAR;
    if (shear_count == 0)
        return CVK_SUCCESS;
    size_t n = 3 * (size_t)b->triangle_count;
    bool* tearable = calloc(b->spring_count, sizeof *tearable);
    edge_key* shear = malloc(shear_count * sizeof *shear);
    edge_key* keys = malloc(n * sizeof *keys);
    cvk_other_split* splits = malloc(b->triangle_count * sizeof *splits);
    if (!tearable || !shear || !keys || !splits) {
        free(tearable);
        free(shear);
        free(keys);
        free(splits);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the quads' other splits");
    }
    for (uint32_t i = 0; i < tear->count; i++)
        tearable[tear->spring[i]] = true;
    uint32_t k = 0;
    for (uint32_t i = 0; i < b->spring_count; i++) {
        const cvk_spring* sp = &b->springs[i];
        if (sp->type == CVK_SPRING_SHEAR)
            shear[k++] = (edge_key){sp->a < sp->b ? sp->a : sp->b, sp->a < sp->b ? sp->b : sp->a, i, 0};
    }
    qsort(shear, shear_count, sizeof *shear, compare_edge_keys);
    for (uint32_t t = 0; t < b->triangle_count; t++) {
        splits[t].across = UINT32_MAX;
        for (uint32_t e = 0; e < 3; e++) {
            uint32_t a = b->triangles[3 * (size_t)t + e], c = b->triangles[3 * (size_t)t + (e + 1) % 3];
            keys[3 * (size_t)t + e] = (edge_key){a < c ? a : c, a < c ? c : a, t, e};
        }
    }
    qsort(keys, n, sizeof *keys, compare_edge_keys);
    pair_quads(b, tearable, keys, shear, shear_count, splits);
    free(tearable);
    free(shear);
    free(keys);
    bool any = false;
    for (uint32_t t = 0; t < b->triangle_count && !any; t++)
        any = splits[t].across != UINT32_MAX;
    if (!any) {
        free(splits);
        return CVK_SUCCESS;
    }
    *out = splits;
    return CVK_SUCCESS;
}
