/* Colouring any spring graph: greedy first fit in smallest-last order, then balancing sweeps.

   Why this way: the solver runs one dispatch per colour, so the colour count is the number of
   sequential steps per iteration, and the largest colour sets how long the slowest of them
   takes. Smallest-last ordering (Matula and Beck, 1983) colours a graph of degeneracy d with
   at most d + 1 colours — triangle meshes with structural springs are planar, d ≤ 5 — and
   costs O(V + E) with bucket queues. First fit fills colour 0 first, so the sizes come out
   uneven; the sweeps then move each vertex to a smaller colour its neighbours leave free
   (the "shuffling" balancing of Lu et al., "Balanced coloring for parallel computing
   applications", IPDPS 2015), which keeps the colouring valid and the count unchanged. */
#include "colour.h"

#include <stdlib.h>
#include <string.h>

#include "error.h"

#define NONE UINT32_MAX

/* Colour sets are bit masks in one uint32_t. */
_Static_assert(CVK_MAX_COLOURS == 32, "colour masks hold 32 colours");

/* Sweeps over all vertices; each strictly lowers the sum of squared colour sizes or ends the
   balancing, and two or three usually settle it. */
#define BALANCE_SWEEPS 8

/* Adjacency of the free vertices, compressed rows: the neighbours of v are
   neighbour[start[v] .. start[v + 1]). */
typedef struct graph {
    uint32_t n;
    size_t* start;
    uint32_t* neighbour;
} graph;

static void graph_free(graph* g)
{
    free(g->start);
    free(g->neighbour);
}

static bool is_free(const uint8_t* pinned, uint32_t v)
{
    return !pinned || !pinned[v];
}

static cvk_result graph_build(uint32_t n, const cvk_topo_spring* springs, uint32_t count,
                              const uint8_t* pinned, graph* g, cvk_error* error)
{
    g->n = n;
    g->start = calloc((size_t)n + 1, sizeof *g->start);
    if (!g->start)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory to colour %u particles", n);
    for (uint32_t s = 0; s < count; s++) {
        const cvk_topo_spring* sp = &springs[s];
        if (sp->a == sp->b || !is_free(pinned, sp->a) || !is_free(pinned, sp->b))
            continue;
        g->start[sp->a]++;
        g->start[sp->b]++;
    }
    size_t total = 0;
    for (uint32_t v = 0; v <= n; v++) {
        size_t degree = g->start[v];
        g->start[v] = total;
        total += degree;
    }
    g->neighbour = malloc((total ? total : 1) * sizeof *g->neighbour);
    if (!g->neighbour)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory to colour %u springs", count);
    /* Filling advances start[v] to the end of v's row, which is where v + 1's row begins. */
    for (uint32_t s = 0; s < count; s++) {
        const cvk_topo_spring* sp = &springs[s];
        if (sp->a == sp->b || !is_free(pinned, sp->a) || !is_free(pinned, sp->b))
            continue;
        g->neighbour[g->start[sp->a]++] = sp->b;
        g->neighbour[g->start[sp->b]++] = sp->a;
    }
    for (uint32_t v = n; v > 0; v--)
        g->start[v] = g->start[v - 1];
    g->start[0] = 0;
    return CVK_SUCCESS;
}

/* Degree buckets: doubly linked lists of the vertices still in the graph, by degree. */
typedef struct buckets {
    uint32_t* head;    /* per degree: first vertex, or NONE */
    uint32_t* next;
    uint32_t* prev;
    uint32_t* degree;  /* NONE once removed */
} buckets;

static void bucket_push(buckets* b, uint32_t v)
{
    uint32_t d = b->degree[v];
    b->prev[v] = NONE;
    b->next[v] = b->head[d];
    if (b->head[d] != NONE)
        b->prev[b->head[d]] = v;
    b->head[d] = v;
}

static void bucket_unlink(buckets* b, uint32_t v)
{
    if (b->prev[v] != NONE)
        b->next[b->prev[v]] = b->next[v];
    else
        b->head[b->degree[v]] = b->next[v];
    if (b->next[v] != NONE)
        b->prev[b->next[v]] = b->prev[v];
}

/* Removes a vertex of least remaining degree, again and again; order receives the free
   vertices in reverse removal order, the order greedy colouring takes them in. */
static void remove_smallest(const graph* g, buckets* b, uint32_t* order, uint32_t free_count)
{
    uint32_t d = 0;
    for (uint32_t k = 0; k < free_count; k++) {
        while (b->head[d] == NONE)
            d++;
        uint32_t v = b->head[d];
        bucket_unlink(b, v);
        b->degree[v] = NONE;
        order[free_count - 1 - k] = v;
        for (size_t e = g->start[v]; e < g->start[v + 1]; e++) {
            uint32_t u = g->neighbour[e];
            if (b->degree[u] == NONE)
                continue;
            bucket_unlink(b, u);
            b->degree[u]--;
            bucket_push(b, u);
            if (b->degree[u] < d)
                d = b->degree[u];
        }
    }
}

static cvk_result smallest_last(const graph* g, const uint8_t* pinned, uint32_t* order,
                                uint32_t* free_count, cvk_error* error)
{
    uint32_t max_degree = 0;
    for (uint32_t v = 0; v < g->n; v++)
        if (g->start[v + 1] - g->start[v] > max_degree)
            max_degree = (uint32_t)(g->start[v + 1] - g->start[v]);
    buckets b = {
        .head = malloc(((size_t)max_degree + 1) * sizeof(uint32_t)),
        .next = malloc(((size_t)g->n + 1) * sizeof(uint32_t)),
        .prev = malloc(((size_t)g->n + 1) * sizeof(uint32_t)),
        .degree = malloc(((size_t)g->n + 1) * sizeof(uint32_t)),
    };
    cvk_result r = CVK_SUCCESS;
    if (!b.head || !b.next || !b.prev || !b.degree)
        r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory to colour %u particles", g->n);
    if (r == CVK_SUCCESS) {
        memset(b.head, 0xff, ((size_t)max_degree + 1) * sizeof(uint32_t));
        *free_count = 0;
        /* Pushed from the last vertex down, so the lowest index leads each bucket. */
        for (uint32_t v = g->n; v-- > 0;) {
            b.degree[v] = NONE;
            if (!is_free(pinned, v))
                continue;
            b.degree[v] = (uint32_t)(g->start[v + 1] - g->start[v]);
            bucket_push(&b, v);
            ++*free_count;
        }
        remove_smallest(g, &b, order, *free_count);
    }
    free(b.head);
    free(b.next);
    free(b.prev);
    free(b.degree);
    return r;
}

static uint32_t taken_by_neighbours(const graph* g, const uint32_t* colour, uint32_t v)
{
    uint32_t taken = 0;
    for (size_t e = g->start[v]; e < g->start[v + 1]; e++)
        if (colour[g->neighbour[e]] != NONE)
            taken |= 1u << colour[g->neighbour[e]];
    return taken;
}

/* First fit: each vertex takes the lowest colour none of its coloured neighbours has. */
static cvk_result first_fit(const graph* g, const uint32_t* order, uint32_t free_count,
                            uint32_t* colour, uint32_t* colour_count, cvk_error* error)
{
    *colour_count = 0;
    for (uint32_t k = 0; k < free_count; k++) {
        uint32_t v = order[k];
        uint32_t taken = taken_by_neighbours(g, colour, v);
        if (taken == UINT32_MAX)
            return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                            "the springs need more than %d colours (particle %u has %zu springs); "
                            "clothvk supports at most %d",
                            CVK_MAX_COLOURS, v, g->start[v + 1] - g->start[v], CVK_MAX_COLOURS);
        uint32_t c = 0;
        while (taken >> c & 1u)
            c++;
        colour[v] = c;
        if (c + 1 > *colour_count)
            *colour_count = c + 1;
    }
    return CVK_SUCCESS;
}

/* Moves vertices to the smallest colour their neighbours leave free, when that makes the two
   colours' sizes closer; never adds a colour. */
static void balance(const graph* g, const uint32_t* order, uint32_t free_count,
                    uint32_t colour_count, uint32_t* colour)
{
    uint32_t size[CVK_MAX_COLOURS] = {0};
    for (uint32_t k = 0; k < free_count; k++)
        size[colour[order[k]]]++;
    for (int sweep = 0; sweep < BALANCE_SWEEPS; sweep++) {
        uint32_t moved = 0;
        for (uint32_t k = 0; k < free_count; k++) {
            uint32_t v = order[k], own = colour[v];
            uint32_t taken = taken_by_neighbours(g, colour, v);
            uint32_t best = own, best_size = size[own] - 1;
            for (uint32_t c = 0; c < colour_count; c++)
                if (!(taken >> c & 1u) && size[c] < best_size) {
                    best = c;
                    best_size = size[c];
                }
            if (best == own)
                continue;
            size[own]--;
            size[best]++;
            colour[v] = best;
            moved++;
        }
        if (moved == 0)
            return;
    }
}

cvk_result cvk_colour_graph(uint32_t vertex_count, const cvk_topo_spring* springs,
                            uint32_t spring_count, const uint8_t* pinned, uint32_t* colour,
                            uint32_t* colour_count, cvk_error* error)
{
    *colour_count = 0;
    for (uint32_t v = 0; v < vertex_count; v++)
        colour[v] = NONE;
    graph g = {0};
    uint32_t* order = malloc(((size_t)vertex_count + 1) * sizeof *order);
    cvk_result r = order ? graph_build(vertex_count, springs, spring_count, pinned, &g, error)
                         : cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                                    "out of host memory to colour %u particles", vertex_count);
    uint32_t free_count = 0;
    if (r == CVK_SUCCESS)
        r = smallest_last(&g, pinned, order, &free_count, error);
    if (r == CVK_SUCCESS)
        r = first_fit(&g, order, free_count, colour, colour_count, error);
    if (r == CVK_SUCCESS)
        balance(&g, order, free_count, *colour_count, colour);
    graph_free(&g);
    free(order);
    return r;
}
