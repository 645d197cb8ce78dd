/* Topologies: what every cloth is made of before build.c sees it. */
#include "topology/topology.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* Colour patterns for the grid stencils. Each maps a spring offset (di, dj) to a non-zero
   colour difference, so no spring joins two particles of one colour:
   - structural only: (i + j) mod 2, the seed's red-black;
   - with shear:      (i mod 2) + 2 (j mod 2), four colours;
   - with bend:       (i + 2j) mod 3 (offsets ±1, ±2, ±2, ±4 are never 0 mod 3);
   - with both:       (i + 2j) mod 5 (offsets ±1, ±2, ±3, ±1, ±2, ±4 are never 0 mod 5). */
uint32_t cvk_grid_colour(uint32_t i, uint32_t j, bool shear, bool bend)
{
    if (shear && bend)
        return (i + 2u * j) % 5u;
    if (bend)
        return (i + 2u * j) % 3u;
    if (shear)
        return (i & 1u) + 2u * (j & 1u);
    return (i + j) & 1u;
}

uint32_t cvk_grid_colour_count(bool shear, bool bend)
{
    if (shear && bend)
        return 5;
    if (bend)
        return 3;
    if (shear)
        return 4;
    return 2;
}

cvk_result cvk_topology_area_mass(cvk_topology* t, double density, double total_mass,
                                  cvk_error* error)
{
    double* area = calloc(t->vertex_count ? t->vertex_count : 1, sizeof(double));
    if (!area)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %u masses",
                        t->vertex_count);
    double total_area = 0.0;
    for (uint32_t tri = 0; tri < t->triangle_count; tri++) {
        const uint32_t* v = &t->triangles[3 * (size_t)tri];
        const float* p0 = &t->position[3 * (size_t)v[0]];
        const float* p1 = &t->position[3 * (size_t)v[1]];
        const float* p2 = &t->position[3 * (size_t)v[2]];
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = (double)p1[k] - p0[k];
            e2[k] = (double)p2[k] - p0[k];
        }
        double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        double a = 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        total_area += a;
        for (int k = 0; k < 3; k++)
            area[v[k]] += a / 3.0;
    }
    for (uint32_t v = 0; v < t->vertex_count; v++) {
        if (total_area <= 0.0)
            t->mass[v] = (float)(total_mass / t->vertex_count);
        else if (density > 0.0)
            t->mass[v] = (float)(density * area[v]);
        else
            t->mass[v] = (float)(total_mass * area[v] / total_area);
    }
    free(area);
    return CVK_SUCCESS;
}

/* ---- the grid generator ---- */

typedef struct grid_offset {
    int di, dj;
    cvk_spring_type type;
} grid_offset;

/* Forward offsets: each spring is listed once, from its lower-index end [i, j] to
   [i + di, j + dj]. Springs come offset by offset in this order, then row by row (j outer,
   i inner): the order every grid build has used, so spring indices stay the same. */
static const grid_offset grid_offsets[] = {
    {1, 0, CVK_SPRING_STRUCTURAL}, {0, 1, CVK_SPRING_STRUCTURAL},
    {1, 1, CVK_SPRING_SHEAR},      {1, -1, CVK_SPRING_SHEAR},
    {2, 0, CVK_SPRING_BEND},       {0, 2, CVK_SPRING_BEND},
};
#define GRID_OFFSETS (sizeof grid_offsets / sizeof grid_offsets[0])

/* The first four entries of grid_offsets by name; triangles use all but DIAGONAL. */
enum { RIGHT, DOWN, DIAGONAL, ANTI };

typedef struct grid_layout {
    uint32_t w, h;
    /* For each offset, the index of its first spring, or CVK_NO_SPRING when its kind has
       zero stiffness. */
    uint32_t first[GRID_OFFSETS];
} grid_layout;

static float grid_stiffness(const cvk_cloth_desc* c, cvk_spring_type type)
{
    switch (type) {
    case CVK_SPRING_STRUCTURAL: return c->stiffness.structural;
    case CVK_SPRING_SHEAR: return c->stiffness.shear;
    case CVK_SPRING_BEND: return c->stiffness.bend;
    }
    return 0.0f;
}

/* Where an offset's springs start: span = {i0, iw, j0, jh}, i in [i0, i0 + iw) and j in
   [j0, j0 + jh). */
static void offset_span(const grid_layout* g, const grid_offset* o, uint32_t span[4])
{
    uint32_t adi = (uint32_t)abs(o->di), adj = (uint32_t)abs(o->dj);
    span[0] = o->di < 0 ? adi : 0;
    span[1] = g->w > adi ? g->w - adi : 0;
    span[2] = o->dj < 0 ? adj : 0;
    span[3] = g->h > adj ? g->h - adj : 0;
}

/* The spring of offset `o` starting at [i, j], which must lie in its span. */
static uint32_t grid_spring(const grid_layout* g, int o, uint32_t i, uint32_t j)
{
    if (g->first[o] == CVK_NO_SPRING)
        return CVK_NO_SPRING;
    uint32_t span[4];
    offset_span(g, &grid_offsets[o], span);
    return g->first[o] + (j - span[2]) * span[1] + (i - span[0]);
}

static cvk_result grid_springs(const cvk_cloth_desc* c, uint32_t index, grid_layout* g,
                               cvk_topology* t, cvk_error* error)
{
    uint64_t count = 0;
    for (size_t o = 0; o < GRID_OFFSETS; o++) {
        uint32_t span[4];
        offset_span(g, &grid_offsets[o], span);
        g->first[o] = CVK_NO_SPRING;
        if (grid_stiffness(c, grid_offsets[o].type) <= 0.0f)
            continue;
        g->first[o] = (uint32_t)count;
        count += (uint64_t)span[1] * span[3];
    }
    if (count > UINT32_MAX)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "cloths.%u.grid: %llu springs are more than clothvk can index (%u)", index,
                        (unsigned long long)count, UINT32_MAX);
    t->springs = malloc((size_t)(count ? count : 1) * sizeof *t->springs);
    if (!t->springs)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %llu springs",
                        (unsigned long long)count);
    t->spring_count = (uint32_t)count;
    cvk_topo_spring* out = t->springs;
    for (size_t o = 0; o < GRID_OFFSETS; o++) {
        const grid_offset* off = &grid_offsets[o];
        uint32_t span[4];
        offset_span(g, off, span);
        if (g->first[o] == CVK_NO_SPRING)
            continue;
        for (uint32_t j = span[2]; j < span[2] + span[3]; j++)
            for (uint32_t i = span[0]; i < span[0] + span[1]; i++)
                *out++ = (cvk_topo_spring){j * g->w + i,
                                           (uint32_t)((int64_t)j + off->dj) * g->w +
                                               (uint32_t)((int64_t)i + off->di),
                                           off->type};
    }
    return CVK_SUCCESS;
}

static void normalised(const float in[3], double out[3])
{
    double len = sqrt((double)in[0] * in[0] + (double)in[1] * in[1] + (double)in[2] * in[2]);
    for (int k = 0; k < 3; k++)
        out[k] = in[k] / len;
}

/* Particle [i, j] at origin + i·du·u + j·dv·v, in double, rounded once to float. */
static void grid_positions(const cvk_cloth_desc* c, float* position)
{
    double u[3], v[3];
    normalised(c->u_axis, u);
    normalised(c->v_axis, v);
    double du = c->grid[0] > 1 ? c->size[0] / (double)(c->grid[0] - 1) : 0.0;
    double dv = c->grid[1] > 1 ? c->size[1] / (double)(c->grid[1] - 1) : 0.0;
    for (uint32_t j = 0; j < c->grid[1]; j++)
        for (uint32_t i = 0; i < c->grid[0]; i++) {
            float* out = &position[3 * ((size_t)j * c->grid[0] + i)];
            for (int k = 0; k < 3; k++)
                out[k] = (float)(c->origin[k] + i * du * u[k] + j * dv * v[k]);
        }
}

/* Texture coordinates of particle [i, j]: its place in the grid times texture_scale. */
static float* grid_uv(const cvk_cloth_desc* c)
{
    float* uv = malloc(2 * (size_t)c->grid[0] * c->grid[1] * sizeof *uv);
    if (!uv)
        return NULL;
    double du = c->grid[0] > 1 ? c->texture_scale[0] / (double)(c->grid[0] - 1) : 0.0;
    double dv = c->grid[1] > 1 ? c->texture_scale[1] / (double)(c->grid[1] - 1) : 0.0;
    for (uint32_t j = 0; j < c->grid[1]; j++)
        for (uint32_t i = 0; i < c->grid[0]; i++) {
            float* out = &uv[2 * ((size_t)j * c->grid[0] + i)];
            out[0] = (float)(i * du);
            out[1] = (float)(j * dv);
        }
    return uv;
}

/* Each cell [i, j]..[i + 1, j + 1] is split along its [i + 1, j] - [i, j + 1] diagonal into
   (a, b, c) and (b, d, c), both wound so their normal is u_axis × v_axis; each edge names the
   structural or anti-diagonal shear spring along it. */
static void grid_triangles(const grid_layout* g, cvk_topology* t)
{
    uint32_t tri = 0;
    for (uint32_t j = 0; j + 1 < g->h; j++)
        for (uint32_t i = 0; i + 1 < g->w; i++) {
            uint32_t a = j * g->w + i, b = a + 1, c = a + g->w, d = c + 1;
            uint32_t corners[2][3] = {{a, b, c}, {b, d, c}};
            uint32_t anti = grid_spring(g, ANTI, i, j + 1);
            uint32_t edges[2][3] = {
                {grid_spring(g, RIGHT, i, j), anti, grid_spring(g, DOWN, i, j)},
                {grid_spring(g, DOWN, i + 1, j), grid_spring(g, RIGHT, i, j + 1), anti}};
            for (int k = 0; k < 2; k++, tri++)
                for (int e = 0; e < 3; e++) {
                    t->triangles[3 * (size_t)tri + e] = corners[k][e];
                    t->triangle_springs[3 * (size_t)tri + e] = edges[k][e];
                }
        }
}

cvk_result cvk_topology_grid(const cvk_cloth_desc* c, uint32_t index, cvk_topology* t,
                             cvk_error* error)
{
    memset(t, 0, sizeof *t);
    grid_layout g = {.w = c->grid[0], .h = c->grid[1]};
    /* Scene validation keeps w·h at most 2^30, so the triangle count fits too. */
    size_t n = (size_t)g.w * g.h;
    size_t tris = g.w > 1 && g.h > 1 ? 2 * (size_t)(g.w - 1) * (g.h - 1) : 0;
    t->vertex_count = (uint32_t)n;
    t->triangle_count = (uint32_t)tris;
    t->position = malloc((n ? n : 1) * 3 * sizeof(float));
    t->colour = malloc((n ? n : 1) * sizeof(uint32_t));
    t->triangles = malloc((tris ? tris : 1) * 3 * sizeof(uint32_t));
    t->triangle_springs = malloc((tris ? tris : 1) * 3 * sizeof(uint32_t));
    if (!t->position || !t->colour || !t->triangles || !t->triangle_springs) {
        cvk_topology_destroy(t);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "out of host memory for a %u x %u grid", g.w, g.h);
    }
    cvk_result r = grid_springs(c, index, &g, t, error);
    if (r != CVK_SUCCESS) {
        cvk_topology_destroy(t);
        return r;
    }
    grid_positions(c, t->position);
    grid_triangles(&g, t);
    if ((c->texture || c->normal_map) && !(t->uv = grid_uv(c))) {
        cvk_topology_destroy(t);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for a %u x %u grid", g.w, g.h);
    }
    bool shear = c->stiffness.shear > 0.0f, bend = c->stiffness.bend > 0.0f;
    for (uint32_t j = 0; j < g.h; j++)
        for (uint32_t i = 0; i < g.w; i++)
            t->colour[(size_t)j * g.w + i] = cvk_grid_colour(i, j, shear, bend);
    t->colour_count = cvk_grid_colour_count(shear, bend);
    return CVK_SUCCESS;
}

/* ---- masses and pins, for every generator ---- */

static cvk_result pin_listed(const cvk_cloth_desc* c, const char* base, const cvk_topology* t,
                             uint8_t* mark, cvk_error* error)
{
    /* Scene validation has checked grid pins against the grid. */
    for (uint32_t p = 0; p < c->pin_count && !c->mesh; p++)
        mark[(size_t)c->pins[p][1] * c->grid[0] + c->pins[p][0]] = 1;
    for (uint32_t p = 0; p < c->pin_vertex_count; p++) {
        uint32_t v = c->pin_vertices[p];
        if (v >= t->vertex_count)
            return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                            "%s.pins.%u: vertex %u is out of range; the %s has %u vertices", base,
                            p, v, c->mesh ? "mesh" : "cloth", t->vertex_count);
        mark[v] = 1;
    }
    return CVK_SUCCESS;
}

static cvk_result pin_inside_box(const cvk_cloth_desc* c, const char* base, const cvk_topology* t,
                                 uint8_t* mark, cvk_error* error)
{
    if (!c->use_pin_box)
        return CVK_SUCCESS;
    uint32_t inside = 0;
    for (uint32_t v = 0; v < t->vertex_count; v++) {
        const float* x = &t->position[3 * (size_t)v];
        bool in = true;
        for (int k = 0; k < 3; k++)
            in = in && x[k] >= c->pin_box.min[k] && x[k] <= c->pin_box.max[k];
        if (in) {
            mark[v] = 1;
            inside++;
        }
    }
    if (inside == 0)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s.pin_box: holds none of the cloth's %u vertices", base,
                        t->vertex_count);
    return CVK_SUCCESS;
}

cvk_result cvk_topology_select(const cvk_cloth_desc* pins, const char* base,
                               const cvk_topology* t, uint8_t* mark, cvk_error* error)
{
    cvk_result r = pin_listed(pins, base, t, mark, error);
    return r == CVK_SUCCESS ? pin_inside_box(pins, base, t, mark, error) : r;
}

static cvk_result fill_masses(const cvk_cloth_desc* c, cvk_topology* t, cvk_error* error)
{
    if (c->mesh || c->density > 0.0f)
        return cvk_topology_area_mass(t, c->density, c->mass, error);
    /* A grid by mass alone spreads it evenly, in float, as grids always have. */
    float m = c->mass / (float)t->vertex_count;
    for (uint32_t v = 0; v < t->vertex_count; v++)
        t->mass[v] = m;
    return CVK_SUCCESS;
}

cvk_result cvk_topology_create(const cvk_cloth_desc* cloth, uint32_t index, cvk_topology* out,
                               cvk_error* error)
{
    cvk_result r = cloth->mesh ? cvk_topology_mesh(cloth, index, out, error)
                               : cvk_topology_grid(cloth, index, out, error);
    if (r != CVK_SUCCESS)
        return r;
    size_t n = out->vertex_count ? out->vertex_count : 1;
    if (!out->mass)
        out->mass = malloc(n * sizeof(float));
    if (!out->pinned)
        out->pinned = calloc(n, 1);
    if (!out->mass || !out->pinned)
        r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %u particles",
                     out->vertex_count);
    if (r == CVK_SUCCESS)
        r = fill_masses(cloth, out, error);
    char base[32];
    snprintf(base, sizeof base, "cloths.%u", index);
    if (r == CVK_SUCCESS)
        r = cvk_topology_select(cloth, base, out, out->pinned, error);
    if (r != CVK_SUCCESS)
        cvk_topology_destroy(out);
    return r;
}

void cvk_topology_destroy(cvk_topology* t)
{
    free(t->position);
    free(t->mass);
    free(t->pinned);
    free(t->triangles);
    free(t->triangle_springs);
    free(t->springs);
    free(t->colour);
    free(t->uv);
    memset(t, 0, sizeof *t);
}
