/* Tethers: each free particle's nearest pins and its rest distance to them (see tether.h).

   The nearest pins come from one multi-source Dijkstra over the springs (rest lengths as edge
   lengths) in which every particle keeps up to CVK_TETHER_SLOTS labels, one per pin: a label
   (distance, particle, pin) taken from the queue is final when the particle has fewer labels
   and none from that pin. Ties are broken by particle and pin index, so the result depends on
   nothing but the build. */
#include "topology/build.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

typedef struct label {
    double distance;
    uint32_t particle, pin;
} label;

typedef struct heap {
    label* items;
    size_t count, capacity;
} heap;

static bool before(const label* a, const label* b)
{
    if (a->distance != b->distance)
        return a->distance < b->distance;
    if (a->particle != b->particle)
        return a->particle < b->particle;
    return a->pin < b->pin;
}

static bool heap_push(heap* h, label item)
{
    if (h->count == h->capacity) {
        size_t capacity = h->capacity ? 2 * h->capacity : 1024;
        label* items = realloc(h->items, capacity * sizeof *items);
        if (!items)
            return false;
        h->items = items;
        h->capacity = capacity;
    }
    size_t i = h->count++;
    while (i > 0 && before(&item, &h->items[(i - 1) / 2])) {
        h->items[i] = h->items[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->items[i] = item;
    return true;
}

static label heap_pop(heap* h)
{
    label top = h->items[0], last = h->items[--h->count];
    size_t i = 0;
    for (;;) {
        size_t child = 2 * i + 1;
        if (child >= h->count)
            break;
        if (child + 1 < h->count && before(&h->items[child + 1], &h->items[child]))
            child++;
        if (!before(&h->items[child], &last))
            break;
        h->items[i] = h->items[child];
        i = child;
    }
    if (h->count > 0)
        h->items[i] = last;
    return top;
}

/* Every spring as two directed edges, grouped by source particle (CSR). */
typedef struct graph {
    uint32_t* first; /* particle_count + 1 */
    uint32_t* to;
    float* length;
} graph;

static bool graph_create(const cvk_build* b, graph* g)
{
    uint32_t n = b->particle_count;
    g->first = calloc((size_t)n + 1, sizeof *g->first);
    g->to = malloc(2 * (size_t)b->spring_count * sizeof *g->to);
    g->length = malloc(2 * (size_t)b->spring_count * sizeof *g->length);
    if (!g->first || (b->spring_count && (!g->to || !g->length)))
        return false;
    for (uint32_t s = 0; s < b->spring_count; s++) {
        g->first[b->springs[s].a + 1]++;
        g->first[b->springs[s].b + 1]++;
    }
    for (uint32_t p = 0; p < n; p++)
        g->first[p + 1] += g->first[p];
    uint32_t* fill = malloc((size_t)n * sizeof *fill);
    if (!fill)
        return false;
    memcpy(fill, g->first, (size_t)n * sizeof *fill);
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        uint32_t i = fill[sp->a]++, j = fill[sp->b]++;
        g->to[i] = sp->b;
        g->to[j] = sp->a;
        g->length[i] = g->length[j] = sp->rest;
    }
    free(fill);
    return true;
}

static void graph_destroy(graph* g)
{
    free(g->first);
    free(g->to);
    free(g->length);
}

/* The cloth of each internal particle, and the tether scale of each (0: none). */
static float* particle_scales(const cvk_scene_desc* scene, const cvk_build* b)
{
    float* scale = calloc(b->particle_count ? b->particle_count : 1, sizeof *scale);
    if (!scale)
        return NULL;
    for (uint32_t c = 0; c < b->cloth_count; c++) {
        const cvk_cloth_range* range = &b->cloths[c];
        for (uint32_t i = 0; i < range->particle_count; i++)
            scale[b->internal_of[range->first_user + i]] = scene->cloths[c].tethers;
    }
    return scale;
}

static bool has_label(const uint32_t* anchor, uint32_t p, uint32_t pin)
{
    for (uint32_t k = 0; k < CVK_TETHER_SLOTS; k++)
        if (anchor[CVK_TETHER_SLOTS * (size_t)p + k] == pin)
            return true;
    return false;
}

/* The search itself: labels of free particles into anchor / distance (pinned particles keep
   labels too while the search runs, so that paths may pass them; only free ones are kept). */
static bool search(const cvk_build* b, const graph* g, const float* scale, uint32_t* anchor,
                   double* distance, uint8_t* count)
{
    heap h = {0};
    bool ok = true;
    for (uint32_t p = b->free_count; p < b->particle_count && ok; p++)
        if (scale[p] > 0.0f)
            ok = heap_push(&h, (label){0.0, p, p});
    while (ok && h.count > 0) {
        label l = heap_pop(&h);
        if (count[l.particle] == CVK_TETHER_SLOTS || has_label(anchor, l.particle, l.pin))
            continue;
        size_t slot = CVK_TETHER_SLOTS * (size_t)l.particle + count[l.particle]++;
        anchor[slot] = l.pin;
        distance[slot] = l.distance;
        for (uint32_t e = g->first[l.particle]; e < g->first[l.particle + 1] && ok; e++) {
            uint32_t w = g->to[e];
            if (count[w] < CVK_TETHER_SLOTS && !has_label(anchor, w, l.pin))
                ok = heap_push(&h, (label){l.distance + g->length[e], w, l.pin});
        }
    }
    free(h.items);
    return ok;
}

/* Grids: the straight rest distance (see tether.h). */
static double rest_distance(const cvk_build* b, const cvk_cloth_range* const* cloth_of,
                            uint32_t p, uint32_t pin, double path)
{
    const cvk_cloth_range* range = cloth_of[p];
    if (!range || range->mesh)
        return path;
    const float* a = &b->position[3 * (size_t)p];
    const float* c = &b->position[3 * (size_t)pin];
    double d[3] = {a[0] - c[0], a[1] - c[1], a[2] - c[2]};
    return range->rest_scale * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

static bool any_tethers(const cvk_scene_desc* scene)
{
    for (uint32_t c = 0; c < scene->cloth_count; c++)
        if (scene->cloths[c].tethers > 0.0f)
            return true;
    return false;
}

cvk_result cvk_build_tethers(const cvk_scene_desc* scene, cvk_build* b, cvk_error* error)
{
    b->tether_anchor = NULL;
    b->tether_length = NULL;
    b->tether_slots = 0;
    if (!any_tethers(scene) || b->free_count == b->particle_count || b->free_count == 0)
        return CVK_SUCCESS;
    size_t slots = CVK_TETHER_SLOTS * (size_t)b->particle_count;
    graph g = {0};
    float* scale = particle_scales(scene, b);
    uint32_t* anchor = malloc(slots * sizeof *anchor);
    double* distance = malloc(slots * sizeof *distance);
    uint8_t* count = calloc(b->particle_count, 1);
    const cvk_cloth_range** cloth_of = calloc(b->particle_count, sizeof *cloth_of);
    bool ok = scale && anchor && distance && count && cloth_of && graph_create(b, &g);
    if (ok) {
        for (size_t i = 0; i < slots; i++)
            anchor[i] = CVK_TETHER_NONE;
        for (uint32_t c = 0; c < b->cloth_count; c++)
            for (uint32_t i = 0; i < b->cloths[c].particle_count; i++)
                cloth_of[b->internal_of[b->cloths[c].first_user + i]] = &b->cloths[c];
        ok = search(b, &g, scale, anchor, distance, count);
    }
    size_t kept = CVK_TETHER_SLOTS * (size_t)b->free_count;
    if (ok) {
        b->tether_anchor = malloc(kept * sizeof *b->tether_anchor);
        b->tether_length = malloc(kept * sizeof *b->tether_length);
        ok = b->tether_anchor && b->tether_length;
    }
    b->tether_slots = 0;
    for (size_t i = 0; ok && i < kept; i++) {
        uint32_t p = (uint32_t)(i / CVK_TETHER_SLOTS);
        uint32_t slot = (uint32_t)(i % CVK_TETHER_SLOTS);
        if (anchor[i] != CVK_TETHER_NONE && slot + 1 > b->tether_slots)
            b->tether_slots = slot + 1;
        b->tether_anchor[i] = anchor[i];
        b->tether_length[i] =
            anchor[i] == CVK_TETHER_NONE
                ? 0.0f
                : (float)(scale[p] * rest_distance(b, cloth_of, p, anchor[i], distance[i]));
    }
    graph_destroy(&g);
    free(scale);
    free(anchor);
    free(distance);
    free(count);
    free(cloth_of);
    if (ok)
        return CVK_SUCCESS;
    free(b->tether_anchor);
    free(b->tether_length);
    b->tether_anchor = NULL;
    b->tether_length = NULL;
    return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the tethers");
}
