#include "build.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "error.h"

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

static void normalize3(const float in[3], double out[3])
{
    double len = sqrt((double)in[0] * in[0] + (double)in[1] * in[1] + (double)in[2] * in[2]);
    for (int k = 0; k < 3; k++)
        out[k] = in[k] / len;
}

typedef struct grid_info {
    const cvk_cloth_desc* desc;
    uint32_t first_user;
    double u[3], v[3];
    double du, dv;
    bool shear, bend;
} grid_info;

static void grid_position(const grid_info* g, uint32_t i, uint32_t j, float out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = (float)(g->desc->origin[k] + i * g->du * g->u[k] + j * g->dv * g->v[k]);
}

static uint64_t cloth_particles(const cvk_cloth_desc* c)
{
    return (uint64_t)c->grid[0] * c->grid[1];
}

static cvk_result alloc_all(cvk_build* b, cvk_error* error)
{
    uint32_t n = b->particle_count;
    b->position = malloc((size_t)n * 3 * sizeof(float));
    b->mass = malloc((size_t)n * sizeof(float));
    b->user_of = malloc((size_t)n * sizeof(uint32_t));
    b->internal_of = malloc((size_t)n * sizeof(uint32_t));
    b->cloths = calloc(b->cloth_count, sizeof *b->cloths);
    if (!b->position || !b->mass || !b->user_of || !b->internal_of || !b->cloths)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "out of host memory for %u particles", n);
    return CVK_SUCCESS;
}

/* Marks pinned particles (user order). */
static uint8_t* pin_map(const cvk_scene_desc* scene, const grid_info* grids, uint32_t n)
{
    uint8_t* pinned = calloc(n ? n : 1, 1);
    if (!pinned)
        return NULL;
    for (uint32_t c = 0; c < scene->cloth_count; c++) {
        const cvk_cloth_desc* cloth = &scene->cloths[c];
        for (uint32_t p = 0; p < cloth->pin_count; p++) {
            uint32_t i = cloth->pins[p][0], j = cloth->pins[p][1];
            pinned[grids[c].first_user + j * cloth->grid[0] + i] = 1;
        }
    }
    return pinned;
}

/* Assigns internal indices: colour by colour, grid order inside a colour, pinned last. */
static void renumber(cvk_build* b, const cvk_scene_desc* scene, const grid_info* grids,
                     const uint8_t* pinned)
{
    uint32_t next = 0;
    for (uint32_t colour = 0; colour < b->colour_count; colour++) {
        b->colour_start[colour] = next;
        for (uint32_t c = 0; c < scene->cloth_count; c++) {
            const grid_info* g = &grids[c];
            for (uint32_t j = 0; j < g->desc->grid[1]; j++)
                for (uint32_t i = 0; i < g->desc->grid[0]; i++) {
                    uint32_t user = g->first_user + j * g->desc->grid[0] + i;
                    if (pinned[user] || cvk_grid_colour(i, j, g->shear, g->bend) != colour)
                        continue;
                    b->internal_of[user] = next;
                    b->user_of[next++] = user;
                }
        }
    }
    b->colour_start[b->colour_count] = next;
    b->free_count = next;
    for (uint32_t user = 0; user < b->particle_count; user++)
        if (pinned[user]) {
            b->internal_of[user] = next;
            b->user_of[next++] = user;
        }
}

typedef struct offset {
    int di, dj;
    cvk_spring_type type;
} offset;

/* Forward offsets: each spring is listed once, from its lower-index end. */
static const offset spring_offsets[] = {
    {1, 0, CVK_SPRING_STRUCTURAL}, {0, 1, CVK_SPRING_STRUCTURAL},
    {1, 1, CVK_SPRING_SHEAR},      {1, -1, CVK_SPRING_SHEAR},
    {2, 0, CVK_SPRING_BEND},       {0, 2, CVK_SPRING_BEND},
};

static float stiffness_of(const cvk_cloth_desc* c, cvk_spring_type type)
{
    switch (type) {
    case CVK_SPRING_STRUCTURAL: return c->stiffness.structural;
    case CVK_SPRING_SHEAR: return c->stiffness.shear;
    case CVK_SPRING_BEND: return c->stiffness.bend;
    }
    return 0.0f;
}

/* Writes every spring of a cloth to `out` (when not NULL); returns how many there are. */
static uint64_t for_each_spring(cvk_build* b, const grid_info* g, cvk_spring* out)
{
    const cvk_cloth_desc* c = g->desc;
    uint64_t count = 0;
    for (size_t o = 0; o < sizeof spring_offsets / sizeof spring_offsets[0]; o++) {
        const offset* off = &spring_offsets[o];
        float k = stiffness_of(c, off->type);
        if (k <= 0.0f)
            continue;
        for (uint32_t j = 0; j < c->grid[1]; j++)
            for (uint32_t i = 0; i < c->grid[0]; i++) {
                int64_t i2 = (int64_t)i + off->di, j2 = (int64_t)j + off->dj;
                if (i2 < 0 || j2 < 0 || i2 >= c->grid[0] || j2 >= c->grid[1])
                    continue;
                if (out) {
                    uint32_t ua = g->first_user + j * c->grid[0] + i;
                    uint32_t ub = g->first_user + (uint32_t)j2 * c->grid[0] + (uint32_t)i2;
                    uint32_t a = b->internal_of[ua], bb = b->internal_of[ub];
                    const float* pa = &b->position[3 * (size_t)a];
                    const float* pb = &b->position[3 * (size_t)bb];
                    double d[3] = {pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]};
                    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                    out[count] = (cvk_spring){a, bb, (float)(len * c->rest_scale), k, off->type};
                }
                count++;
            }
    }
    return count;
}

static cvk_result build_springs(cvk_build* b, const cvk_scene_desc* scene, const grid_info* grids,
                                cvk_error* error)
{
    uint64_t total = 0;
    for (uint32_t c = 0; c < scene->cloth_count; c++)
        total += for_each_spring(b, &grids[c], NULL);
    if (total > UINT32_MAX)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT, "cloths: %llu springs are too many",
                        (unsigned long long)total);
    b->springs = malloc((size_t)(total ? total : 1) * sizeof *b->springs);
    if (!b->springs)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %llu springs",
                        (unsigned long long)total);
    uint64_t at = 0;
    for (uint32_t c = 0; c < scene->cloth_count; c++)
        at += for_each_spring(b, &grids[c], b->springs + at);
    b->spring_count = (uint32_t)total;
    for (uint32_t s = 0; s < b->spring_count; s++)
        b->springs_by_type[b->springs[s].type]++;
    return CVK_SUCCESS;
}

static cvk_result build_adjacency(cvk_build* b, cvk_error* error)
{
    uint32_t nf = b->free_count;
    b->degree = calloc(nf ? nf : 1, sizeof(uint32_t));
    if (!b->degree)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for adjacency");
    for (uint32_t s = 0; s < b->spring_count; s++) {
        if (b->springs[s].a < nf)
            b->degree[b->springs[s].a]++;
        if (b->springs[s].b < nf)
            b->degree[b->springs[s].b]++;
    }
    b->max_degree = 0;
    for (uint32_t p = 0; p < nf; p++)
        if (b->degree[p] > b->max_degree)
            b->max_degree = b->degree[p];
    size_t entries = (size_t)b->max_degree * nf;
    if (entries == 0)
        entries = 1;
    b->adj_index = calloc(entries, sizeof(uint32_t));
    b->adj_k = calloc(entries, sizeof(float));
    b->adj_rest = calloc(entries, sizeof(float));
    uint32_t* fill = calloc(nf ? nf : 1, sizeof(uint32_t));
    if (!b->adj_index || !b->adj_k || !b->adj_rest || !fill) {
        free(fill);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for adjacency");
    }
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        uint32_t ends[2][2] = {{sp->a, sp->b}, {sp->b, sp->a}};
        for (int e = 0; e < 2; e++) {
            uint32_t p = ends[e][0];
            if (p >= nf)
                continue;
            size_t at = (size_t)fill[p]++ * nf + p;
            b->adj_index[at] = ends[e][1];
            b->adj_k[at] = sp->k;
            b->adj_rest[at] = sp->rest;
        }
    }
    /* Pad to max_degree with zero-stiffness springs to the particle itself, so the GPU
       loop has a fixed length and no degree to fetch. */
    for (uint32_t p = 0; p < nf; p++)
        for (uint32_t s = fill[p]; s < b->max_degree; s++)
            b->adj_index[(size_t)s * nf + p] = p;
    free(fill);
    return CVK_SUCCESS;
}

cvk_result cvk_build_create(const cvk_scene_desc* scene, cvk_build* out, cvk_error* error)
{
    memset(out, 0, sizeof *out);
    uint64_t total = 0;
    for (uint32_t c = 0; c < scene->cloth_count; c++)
        total += cloth_particles(&scene->cloths[c]);
    if (total == 0 || total > UINT32_MAX / 4)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cloths: %llu particles cannot be built", (unsigned long long)total);

    cvk_build* b = out;
    b->particle_count = (uint32_t)total;
    b->cloth_count = scene->cloth_count;
    grid_info* grids = calloc(scene->cloth_count, sizeof *grids);
    if (!grids)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for cloths");
    cvk_result r = alloc_all(b, error);

    uint32_t first = 0;
    b->colour_count = 1;
    for (uint32_t c = 0; c < scene->cloth_count && r == CVK_SUCCESS; c++) {
        const cvk_cloth_desc* cloth = &scene->cloths[c];
        grid_info* g = &grids[c];
        g->desc = cloth;
        g->first_user = first;
        normalize3(cloth->u_axis, g->u);
        normalize3(cloth->v_axis, g->v);
        g->du = cloth->grid[0] > 1 ? cloth->size[0] / (double)(cloth->grid[0] - 1) : 0.0;
        g->dv = cloth->grid[1] > 1 ? cloth->size[1] / (double)(cloth->grid[1] - 1) : 0.0;
        g->shear = cloth->stiffness.shear > 0.0f;
        g->bend = cloth->stiffness.bend > 0.0f;
        uint32_t colours = cvk_grid_colour_count(g->shear, g->bend);
        if (colours > b->colour_count)
            b->colour_count = colours;
        b->cloths[c] = (cvk_cloth_range){
            .first_user = first,
            .particle_count = (uint32_t)cloth_particles(cloth),
            .grid = {cloth->grid[0], cloth->grid[1]},
            .rest_scale = cloth->rest_scale,
            .color = {cloth->color[0], cloth->color[1], cloth->color[2]},
        };
        first += (uint32_t)cloth_particles(cloth);
    }

    uint8_t* pinned = r == CVK_SUCCESS ? pin_map(scene, grids, b->particle_count) : NULL;
    if (r == CVK_SUCCESS && !pinned)
        r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for pins");
    if (r == CVK_SUCCESS) {
        renumber(b, scene, grids, pinned);
        for (uint32_t c = 0; c < scene->cloth_count; c++) {
            const grid_info* g = &grids[c];
            float m = g->desc->mass / (float)cloth_particles(g->desc);
            for (uint32_t j = 0; j < g->desc->grid[1]; j++)
                for (uint32_t i = 0; i < g->desc->grid[0]; i++) {
                    uint32_t p = b->internal_of[g->first_user + j * g->desc->grid[0] + i];
                    grid_position(g, i, j, &b->position[3 * (size_t)p]);
                    b->mass[p] = m;
                }
        }
        r = build_springs(b, scene, grids, error);
    }
    if (r == CVK_SUCCESS)
        r = build_adjacency(b, error);
    free(pinned);
    free(grids);
    if (r != CVK_SUCCESS)
        cvk_build_destroy(b);
    return r;
}

void cvk_build_destroy(cvk_build* b)
{
    free(b->position);
    free(b->mass);
    free(b->user_of);
    free(b->internal_of);
    free(b->springs);
    free(b->degree);
    free(b->adj_index);
    free(b->adj_k);
    free(b->adj_rest);
    free(b->cloths);
    memset(b, 0, sizeof *b);
}

uint32_t cvk_build_colour_of(const cvk_build* b, uint32_t particle)
{
    for (uint32_t c = 0; c < b->colour_count; c++)
        if (particle < b->colour_start[c + 1])
            return c;
    return UINT32_MAX; /* pinned: no colour */
}

int64_t cvk_build_find_colour_conflict(const cvk_build* b)
{
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        if (sp->a >= b->free_count || sp->b >= b->free_count)
            continue;
        if (cvk_build_colour_of(b, sp->a) == cvk_build_colour_of(b, sp->b))
            return s;
    }
    return -1;
}
