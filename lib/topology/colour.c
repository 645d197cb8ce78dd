/* Colouring any spring graph: greedy first fit in smallest-last order, one iterated greedy
   pass, then balancing sweeps.

   Why this way: the solver runs one dispatch per colour, so the colour count is the number of
   sequential steps per iteration, and the largest colour sets how long the slowest of them
   takes. Smallest-last ordering (Matula and Beck, 1983) colours a graph of degeneracy d with
   at most d + 1 colours — triangle meshes with structural springs are planar, d ≤ 5 — and
   costs O(V + E) with bucket queues. One iterated greedy pass (Culberson, 1992) runs first
   fit again class by class, last class first: that can only keep or lower the count, and a
   class only a few vertices needed often disappears (8 colours to 7 on two of the random
   graphs of tests/topology/test_colouring.c; more passes, in this or largest-class-first order,
   lowered no count there). First fit fills colour 0 first, so the sizes come out uneven
   (largest/smallest 1.5 to 1000 on those graphs); the sweeps then move each vertex to a
   smaller colour its neighbours leave free (the "shuffling" balancing of Lu et al., "Balanced
   coloring for parallel computing applications", IPDPS 2015), which keeps the colouring valid
   and the count unchanged: largest/smallest ends within 1.04 on those graphs (the worst is a
   4-colour planar mesh, where many vertices see all three other colours around them). A
   million vertices with five million springs take about half a
   second. */
#include "topology/colour.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"

#define NONE UINT32_MAX

/* Colour sets are bit masks in one uint32_t. */
_Static_assert(CVK_MAX_COLOURS == 32, "colour masks hold 32 colours");

/* Sweeps over all vertices; each move strictly lowers the sum of squared colour sizes, and
   the random graphs and meshes of tests/topology/test_colouring.c settle in two to six sweeps. */
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

/* The free vertices class by class, last colour first, in their old order inside a class. */
static void regroup(const uint32_t* colour, uint32_t colour_count, const uint32_t* order,
                    uint32_t free_count, uint32_t* out)
{
    uint32_t at[CVK_MAX_COLOURS] = {0};
    for (uint32_t k = 0; k < free_count; k++)
        at[colour[order[k]]]++;
    uint32_t next = 0;
    for (uint32_t c = colour_count; c-- > 0;) {
        uint32_t size = at[c];
        at[c] = next;
        next += size;
    }
    for (uint32_t k = 0; k < free_count; k++)
        out[at[colour[order[k]]]++] = order[k];
}

/* First fit in smallest-last order, then once more class by class. */
static cvk_result greedy(const graph* g, const uint32_t* order, uint32_t* regrouped,
                         uint32_t free_count, uint32_t* colour, uint32_t* colour_count,
                         cvk_error* error)
{
    cvk_result r = first_fit(g, order, free_count, colour, colour_count, error);
    if (r != CVK_SUCCESS)
        return r;
    regroup(colour, *colour_count, order, free_count, regrouped);
    for (uint32_t k = 0; k < free_count; k++)
        colour[order[k]] = NONE;
    /* Cannot fail: class by class, first fit needs no more colours than there were. */
    return first_fit(g, regrouped, free_count, colour, colour_count, error);
}

/* Moves vertices to the smallest colour their neighbours leave free, when that makes the two
   colours' sizes closer; never adds a colour. Vertices go in index order, which follows the
   mesh and so reads memory far more locally than the colouring order. */
static void balance(const graph* g, uint32_t colour_count, uint32_t* colour)
{
    uint32_t size[CVK_MAX_COLOURS] = {0};
    for (uint32_t v = 0; v < g->n; v++)
        if (colour[v] != NONE)
            size[colour[v]]++;
    for (int sweep = 0; sweep < BALANCE_SWEEPS; sweep++) {
        uint32_t moved = 0;
        for (uint32_t v = 0; v < g->n; v++) {
            uint32_t own = colour[v];
            if (own == NONE)
                continue;
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
    uint32_t* regrouped = malloc(((size_t)vertex_count + 1) * sizeof *regrouped);
    cvk_result r = CVK_SUCCESS;
    if (!order || !regrouped)
        r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory to colour %u particles",
                     vertex_count);
    if (r == CVK_SUCCESS)
        r = graph_build(vertex_count, springs, spring_count, pinned, &g, error);
    uint32_t free_count = 0;
    if (r == CVK_SUCCESS)
        r = smallest_last(&g, pinned, order, &free_count, error);
    if (r == CVK_SUCCESS)
        r = greedy(&g, order, regrouped, free_count, colour, colour_count, error);
    if (r == CVK_SUCCESS)
        balance(&g, *colour_count, colour);
    graph_free(&g);
    free(order);
    free(regrouped);
    return r;
}
