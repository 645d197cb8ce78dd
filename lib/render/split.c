/* The other split of quads that can tear along their split diagonal (lib/render/split.h). */
#include "render/split.h"

#include <stdlib.h>
#include <string.h>

#include "features/tear.h"
#include "render/edge_key.h"

/* Pairs the triangles on each edge with two of them and fills the pairs' other splits. */
static void pair_quads(const cvk_build* b, const bool* tearable, const cvk_edge_key* keys,
                       const cvk_edge_key* shear, uint32_t shear_count, cvk_other_split* out)
{
    size_t n = 3 * (size_t)b->triangle_count;
    const uint32_t* tv = b->triangles;
    const uint32_t* ts = b->triangle_springs;
    for (size_t i = 0; i + 1 < n; i++) {
        const cvk_edge_key* h0 = &keys[i];
        const cvk_edge_key* h1 = &keys[i + 1];
        if (!cvk_same_edge(h0, h1) || (i + 2 < n && cvk_same_edge(h0, &keys[i + 2])) ||
            (i > 0 && cvk_same_edge(h0, &keys[i - 1])))
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
        cvk_edge_key key = cvk_edge_key_of(i0, i1, 0, 0, 0);
        const cvk_edge_key* across = bsearch(&key, shear, shear_count, sizeof *shear, cvk_compare_edge_ends);
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
    cvk_edge_key* shear = malloc(shear_count * sizeof *shear);
    cvk_edge_key* keys = malloc(n * sizeof *keys);
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
            shear[k++] = cvk_edge_key_of(sp->a, sp->b, i, 0, 0); /* the spring's index as `triangle` */
    }
    cvk_sort_edge_keys(shear, shear_count);
    for (uint32_t t = 0; t < b->triangle_count; t++) {
        splits[t].across = UINT32_MAX;
        for (uint32_t e = 0; e < 3; e++) {
            uint32_t a = b->triangles[3 * (size_t)t + e], c = b->triangles[3 * (size_t)t + (e + 1) % 3];
            keys[3 * (size_t)t + e] = cvk_edge_key_of(a, c, t, e, 0);
        }
    }
    cvk_sort_edge_keys(keys, n);
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
