/* One build path for every cloth: topologies (lib/topology/topology.h) in, particles in solver order,
   springs, adjacency and triangles out. */
#include "topology/build.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "topology/colour.h"
#include "topology/build.h"
#include "core/error.h"
#include "topology/topology.h"

/* A cloth's topology and where its parts land in the build. */
typedef struct cloth_part {
    cvk_topology topology;
    uint32_t first_user;
    uint32_t first_spring;
    uint32_t first_triangle;
    uint32_t* attached_to;  /* per vertex: its attachment (scene order) or UINT32_MAX; NULL
                               when none of the scene's attachments is on this cloth */
} cloth_part;

static void parts_destroy(cloth_part* parts, uint32_t count)
{
    for (uint32_t c = 0; parts && c < count; c++) {
        cvk_topology_destroy(&parts[c].topology);
        free(parts[c].attached_to);
    }
    free(parts);
}

/* A topology without a closed-form colouring (a mesh) is coloured from its springs. Cloths
   share no springs, so each is coloured alone and all of them share the colour ranges. */
static cvk_result colour_topology(cvk_topology* t, uint32_t index, cvk_error* error)
{
    if (t->colour)
        return CVK_SUCCESS;
    t->colour = malloc((t->vertex_count ? t->vertex_count : 1) * sizeof *t->colour);
    if (!t->colour)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory to colour %u particles",
                        t->vertex_count);
    cvk_result r = cvk_colour_graph(t->vertex_count, t->springs, t->spring_count, t->pinned,
                                    t->colour, &t->colour_count, error);
    if (r != CVK_SUCCESS)
        cvk_error_prefix(error, "cloths.%u", index);
    return r;
}

/* Marks the particles of attachment a (on this part's cloth) attached and pinned. */
static cvk_result attach_one(const cvk_scene_desc* scene, uint32_t a, cloth_part* part,
                             uint8_t* mark, cvk_error* error)
{
    const cvk_attachment_desc* desc = &scene->attachments[a];
    cvk_topology* t = &part->topology;
    char base[32];
    snprintf(base, sizeof base, "attachments.%u", a);
    cvk_cloth_desc pins = cvk_attachment_pins_as_cloth(&scene->cloths[desc->cloth], desc);
    memset(mark, 0, t->vertex_count);
    cvk_result r = cvk_topology_select(&pins, base, t, mark, error);
    for (uint32_t v = 0; r == CVK_SUCCESS && v < t->vertex_count; v++) {
        if (!mark[v])
            continue;
        if (part->attached_to[v] != UINT32_MAX)
            return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                            "%s: particle %u of cloth %u is already in attachments.%u", base, v,
                            desc->cloth, part->attached_to[v]);
        part->attached_to[v] = a;
        t->pinned[v] = 1;
    }
    return r;
}

/* The attachments on cloth `cloth`: their particles are pinned, and remembered per vertex. */
static cvk_result attach_part(const cvk_scene_desc* scene, uint32_t cloth, cloth_part* part,
                              cvk_error* error)
{
    uint32_t n = part->topology.vertex_count;
    cvk_result r = CVK_SUCCESS;
    uint8_t* mark = NULL;
    for (uint32_t a = 0; r == CVK_SUCCESS && a < scene->attachment_count; a++) {
        if (scene->attachments[a].cloth != cloth)
            continue;
        if (!part->attached_to) {
            part->attached_to = malloc((n ? n : 1) * sizeof(uint32_t));
            mark = malloc(n ? n : 1);
            if (!part->attached_to || !mark) {
                r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                             "out of host memory for the attachments of %u particles", n);
                break;
            }
            memset(part->attached_to, 0xff, (size_t)n * sizeof(uint32_t));
        }
        r = attach_one(scene, a, part, mark, error);
    }
    free(mark);
    return r;
}

/* The attached particles by internal index, cloth by cloth in user order. */
static cvk_result list_attached(cvk_build* b, const cloth_part* parts, cvk_error* error)
{
    uint32_t count = 0;
    for (uint32_t c = 0; c < b->cloth_count; c++)
        for (uint32_t v = 0; parts[c].attached_to && v < parts[c].topology.vertex_count; v++)
            count += parts[c].attached_to[v] != UINT32_MAX;
    b->attached_count = count;
    b->attached = malloc((count ? count : 1) * sizeof(uint32_t));
    b->attached_to = malloc((count ? count : 1) * sizeof(uint32_t));
    if (!b->attached || !b->attached_to)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "out of host memory for %u attached particles", count);
    uint32_t i = 0;
    for (uint32_t c = 0; c < b->cloth_count; c++)
        for (uint32_t v = 0; parts[c].attached_to && v < parts[c].topology.vertex_count; v++) {
            if (parts[c].attached_to[v] == UINT32_MAX)
                continue;
            b->attached[i] = b->internal_of[parts[c].first_user + v];
            b->attached_to[i++] = parts[c].attached_to[v];
        }
    return CVK_SUCCESS;
}

static cvk_result make_parts(const cvk_scene_desc* scene, cloth_part* parts, cvk_error* error)
{
    for (uint32_t c = 0; c < scene->cloth_count; c++) {
        cvk_result r = cvk_topology_create(&scene->cloths[c], c, &parts[c].topology, error);
        if (r == CVK_SUCCESS)
            r = attach_part(scene, c, &parts[c], error);
        if (r == CVK_SUCCESS)
            r = colour_topology(&parts[c].topology, c, error);
        if (r != CVK_SUCCESS)
            return r;
    }
    return CVK_SUCCESS;
}

/* Places each cloth's particles, springs and triangles after the previous cloth's. */
static cvk_result lay_out(cvk_build* b, cloth_part* parts, cvk_error* error)
{
    uint64_t particles = 0, springs = 0, triangles = 0;
    b->colour_count = 1;
    for (uint32_t c = 0; c < b->cloth_count; c++) {
        const cvk_topology* t = &parts[c].topology;
        parts[c].first_user = (uint32_t)particles;
        parts[c].first_spring = (uint32_t)springs;
        parts[c].first_triangle = (uint32_t)triangles;
        particles += t->vertex_count;
        springs += t->spring_count;
        triangles += t->triangle_count;
        if (t->colour_count > b->colour_count)
            b->colour_count = t->colour_count;
        /* Stop before the offsets above can wrap. */
        if (particles > UINT32_MAX / 4)
            break;
    }
    if (particles == 0 || particles > UINT32_MAX / 4)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cloths: %llu particles cannot be built",
                        (unsigned long long)particles);
    if (springs > UINT32_MAX)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT, "cloths: %llu springs are too many",
                        (unsigned long long)springs);
    /* Index counts (3 per triangle) are 32-bit for the renderer and the mesh readback. */
    if (triangles > UINT32_MAX / 3)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT, "cloths: %llu triangles are too many",
                        (unsigned long long)triangles);
    b->particle_count = (uint32_t)particles;
    b->spring_count = (uint32_t)springs;
    b->triangle_count = (uint32_t)triangles;
    return CVK_SUCCESS;
}

static cvk_result alloc_all(cvk_build* b, cvk_error* error)
{
    size_t n = b->particle_count, s = b->spring_count ? b->spring_count : 1;
    size_t tris = b->triangle_count ? b->triangle_count : 1;
    b->position = malloc(n * 3 * sizeof(float));
    b->mass = malloc(n * sizeof(float));
    b->user_of = malloc(n * sizeof(uint32_t));
    b->internal_of = malloc(n * sizeof(uint32_t));
    b->springs = malloc(s * sizeof *b->springs);
    b->triangles = malloc(3 * tris * sizeof(uint32_t));
    b->triangle_springs = malloc(3 * tris * sizeof(uint32_t));
    b->cloths = calloc(b->cloth_count, sizeof *b->cloths);
    if (!b->position || !b->mass || !b->user_of || !b->internal_of || !b->springs ||
        !b->triangles || !b->triangle_springs || !b->cloths)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "out of host memory for %u particles, %u springs and %u triangles",
                        b->particle_count, b->spring_count, b->triangle_count);
    return CVK_SUCCESS;
}

/* Assigns internal indices: colour by colour, user order inside a colour, pinned last. A
   counting sort, so it costs one pass whatever the colour count. */
static void renumber(cvk_build* b, const cloth_part* parts)
{
    uint32_t at[CVK_MAX_COLOURS] = {0};
    for (uint32_t c = 0; c < b->cloth_count; c++) {
        const cvk_topology* t = &parts[c].topology;
        for (uint32_t v = 0; v < t->vertex_count; v++)
            if (!t->pinned[v])
                at[t->colour[v]]++;
    }
    uint32_t next = 0;
    for (uint32_t colour = 0; colour < b->colour_count; colour++) {
        uint32_t size = at[colour];
        b->colour_start[colour] = at[colour] = next;
        next += size;
    }
    b->colour_start[b->colour_count] = next;
    b->free_count = next;
    for (uint32_t c = 0; c < b->cloth_count; c++) {
        const cvk_topology* t = &parts[c].topology;
        for (uint32_t v = 0; v < t->vertex_count; v++) {
            uint32_t user = parts[c].first_user + v;
            uint32_t internal = t->pinned[v] ? next++ : at[t->colour[v]]++;
            b->internal_of[user] = internal;
            b->user_of[internal] = user;
        }
    }
}

static float stiffness_of(const cvk_cloth_desc* c, cvk_spring_type type)
{
    switch (type) {
    case CVK_SPRING_STRUCTURAL: return c->stiffness.structural;
    case CVK_SPRING_SHEAR: return c->stiffness.shear;
    case CVK_SPRING_BEND: return c->stiffness.bend;
    }
    return 0.0f;
}

/* Positions, masses and springs of one cloth in internal order. A rest length is the
   distance between the float positions, taken in double and scaled once. */
static void add_particles(cvk_build* b, const cvk_cloth_desc* desc, const cloth_part* part)
{
    const cvk_topology* t = &part->topology;
    for (uint32_t v = 0; v < t->vertex_count; v++) {
        uint32_t p = b->internal_of[part->first_user + v];
        memcpy(&b->position[3 * (size_t)p], &t->position[3 * (size_t)v], 3 * sizeof(float));
        b->mass[p] = t->mass[v];
    }
    for (uint32_t s = 0; s < t->spring_count; s++) {
        const cvk_topo_spring* ts = &t->springs[s];
        uint32_t a = b->internal_of[part->first_user + ts->a];
        uint32_t bb = b->internal_of[part->first_user + ts->b];
        const float* pa = &b->position[3 * (size_t)a];
        const float* pb = &b->position[3 * (size_t)bb];
        double d[3] = {pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]};
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        b->springs[part->first_spring + s] = (cvk_spring){
            a, bb, (float)(len * desc->rest_scale), stiffness_of(desc, ts->type), ts->type};
        b->springs_by_type[ts->type]++;
    }
}

static void add_triangles(cvk_build* b, const cloth_part* part)
{
    const cvk_topology* t = &part->topology;
    size_t first = 3 * (size_t)part->first_triangle;
    for (size_t e = 0; e < 3 * (size_t)t->triangle_count; e++) {
        uint32_t spring = t->triangle_springs[e];
        b->triangles[first + e] = part->first_user + t->triangles[e];
        b->triangle_springs[first + e] =
            spring == CVK_NO_SPRING ? UINT32_MAX : part->first_spring + spring;
    }
}

static void describe_cloth(cvk_build* b, const cvk_cloth_desc* desc, uint32_t index,
                           const cloth_part* part)
{
    cvk_cloth_range* r = &b->cloths[index];
    *r = (cvk_cloth_range){
        .first_user = part->first_user,
        .particle_count = part->topology.vertex_count,
        .first_triangle = part->first_triangle,
        .triangle_count = part->topology.triangle_count,
        .mesh = desc->mesh != NULL,
        .rest_scale = desc->rest_scale,
        .color = {desc->color[0], desc->color[1], desc->color[2]},
        .back_color = {desc->back_color[0], desc->back_color[1], desc->back_color[2]},
        .sheen = desc->sheen,
        .roughness = desc->roughness,
        .thickness = desc->thickness,
        .normal_strength = desc->normal_strength,
        .material_texture = desc->material_texture,
    };
    if (!desc->mesh) {
        r->grid[0] = desc->grid[0];
        r->grid[1] = desc->grid[1];
    }
    if (desc->name)
        snprintf(r->name, sizeof r->name, "%s", desc->name);
    else
        snprintf(r->name, sizeof r->name, "cloth%u", index);
}

/* The textured cloths' paths and texture coordinates, for the renderer. */
static cvk_result copy_textures(cvk_build* b, const cvk_scene_desc* scene, const cloth_part* parts,
                                cvk_error* error)
{
    for (uint32_t c = 0; c < scene->cloth_count; c++) {
        const cvk_topology* t = &parts[c].topology;
        if (!(scene->cloths[c].texture || scene->cloths[c].normal_map) || !t->uv)
            continue;
        if (!b->uv && !(b->uv = calloc(2 * (size_t)b->particle_count, sizeof *b->uv)))
            return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for texture coordinates");
        memcpy(&b->uv[2 * (size_t)parts[c].first_user], t->uv, 2 * (size_t)t->vertex_count * sizeof *t->uv);
        const char* texture = scene->cloths[c].texture;
        const char* normal_map = scene->cloths[c].normal_map;
        if ((texture && !(b->cloths[c].texture = strdup(texture))) ||
            (normal_map && !(b->cloths[c].normal_map = strdup(normal_map))))
            return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for texture paths");
    }
    return CVK_SUCCESS;
}

static cvk_result build_adjacency(cvk_build* b, cvk_build_check check, void* check_user,
                                  cvk_error* error)
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
    cvk_result r = check ? check(check_user, b->particle_count, b->max_degree, error)
                         : CVK_SUCCESS;
    if (r != CVK_SUCCESS)
        return r;
    size_t entries = (size_t)b->max_degree * nf;
    if (entries == 0)
        entries = 1;
    b->adj_index = calloc(entries, sizeof(uint32_t));
    b->adj_k = calloc(entries, sizeof(float));
    b->adj_rest = calloc(entries, sizeof(float));
    b->adj_spring = malloc(entries * sizeof(uint32_t));
    uint32_t* fill = calloc(nf ? nf : 1, sizeof(uint32_t));
    if (!b->adj_index || !b->adj_k || !b->adj_rest || !b->adj_spring || !fill) {
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
            b->adj_spring[at] = s;
        }
    }
    /* Pad to max_degree with zero-stiffness springs to the particle itself, so the GPU
       loop has a fixed length and no degree to fetch. */
    for (uint32_t p = 0; p < nf; p++)
        for (uint32_t s = fill[p]; s < b->max_degree; s++) {
            b->adj_index[(size_t)s * nf + p] = p;
            b->adj_spring[(size_t)s * nf + p] = UINT32_MAX;
        }
    free(fill);
    return CVK_SUCCESS;
}

cvk_result cvk_build_create(const cvk_scene_desc* scene, cvk_build* out, cvk_error* error)
{
    return cvk_build_create_checked(scene, NULL, NULL, out, error);
}

cvk_result cvk_build_create_checked(const cvk_scene_desc* scene, cvk_build_check check,
                                    void* check_user, cvk_build* out, cvk_error* error)
{
    memset(out, 0, sizeof *out);
    cvk_build* b = out;
    b->cloth_count = scene->cloth_count;
    cloth_part* parts = calloc(scene->cloth_count ? scene->cloth_count : 1, sizeof *parts);
    if (!parts)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %u cloths",
                        scene->cloth_count);
    cvk_result r = make_parts(scene, parts, error);
    if (r == CVK_SUCCESS)
        r = lay_out(b, parts, error);
    if (r == CVK_SUCCESS)
        r = alloc_all(b, error);
    if (r == CVK_SUCCESS) {
        renumber(b, parts);
        for (uint32_t c = 0; c < scene->cloth_count; c++) {
            add_particles(b, &scene->cloths[c], &parts[c]);
            add_triangles(b, &parts[c]);
            describe_cloth(b, &scene->cloths[c], c, &parts[c]);
        }
        r = list_attached(b, parts, error);
        if (r == CVK_SUCCESS)
            r = copy_textures(b, scene, parts, error);
        if (r == CVK_SUCCESS)
            r = build_adjacency(b, check, check_user, error);
    }
    if (r == CVK_SUCCESS)
        r = cvk_build_tethers(scene, b, error);
    parts_destroy(parts, scene->cloth_count);
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
    free(b->adj_spring);
    free(b->triangles);
    free(b->triangle_springs);
    for (uint32_t c = 0; b->cloths && c < b->cloth_count; c++) {
        free(b->cloths[c].texture);
        free(b->cloths[c].normal_map);
    }
    free(b->cloths);
    free(b->tether_anchor);
    free(b->tether_length);
    free(b->attached);
    free(b->attached_to);
    free(b->uv);
    memset(b, 0, sizeof *b);
}

uint32_t cvk_build_cloth_of_user(const cvk_build* b, uint32_t user)
{
    uint32_t cloth = 0;
    while (cloth + 1 < b->cloth_count && user >= b->cloths[cloth + 1].first_user)
        cloth++;
    return cloth;
}

uint32_t cvk_build_cloth_of(const cvk_build* b, uint32_t particle)
{
    return cvk_build_cloth_of_user(b, b->user_of[particle]);
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
