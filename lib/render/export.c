/* The cloths as data for other tools: their particle and triangle ranges, and the mesh
   (positions, normals, triangles) read back for export through an application's own pipeline
   or clothvk-sim --obj.

   The normals follow the definition of shaders/render/mesh.comp (the area-weighted average of the
   live triangles' normals: the plain sum of their cross products (v1 − v0) × (v2 − v0),
   normalised; zero where there is none) but are summed on the host in double, so that an
   export needs no mesh object and its normals do not depend on a device's rounding. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "render/split.h"
#include "sim/sim.h"

static const char call[] = "cvk_sim_read_mesh";

uint32_t cvk_sim_cloth_count(const cvk_sim* s)
{
    return s ? s->build.cloth_count : 0;
}

cvk_cloth_info cvk_sim_get_cloth(const cvk_sim* s, uint32_t cloth)
{
    if (!s || cloth >= s->build.cloth_count)
        return (cvk_cloth_info){0};
    const cvk_cloth_range* c = &s->build.cloths[cloth];
    return (cvk_cloth_info){
        .name = c->name,
        .first_particle = c->first_user,
        .particle_count = c->particle_count,
        .first_triangle = c->first_triangle,
        .triangle_count = c->triangle_count,
        .mesh = c->mesh,
    };
}

uint64_t cvk_sim_triangle_count(const cvk_sim* s)
{
    return s ? s->build.triangle_count : 0;
}

static cvk_result check_counts(const cvk_sim* s, uint64_t vertex_count, uint64_t triangle_count,
                               cvk_error* error)
{
    if (vertex_count != s->build.particle_count)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: the array holds %llu particles; the simulation has %u", call,
                        (unsigned long long)vertex_count, s->build.particle_count);
    if (triangle_count != s->build.triangle_count)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: the array holds %llu triangles; the simulation has %u", call,
                        (unsigned long long)triangle_count, s->build.triangle_count);
    return CVK_SUCCESS;
}

/* The spring flags as the device holds them (tearing writes them there), or NULL with
   *alive_out untouched when no triangle edge has a spring: then no triangle can tear. */
static cvk_result read_spring_flags(cvk_sim* s, uint32_t** alive_out, cvk_error* error)
{
    const cvk_build* b = &s->build;
    bool any = false;
    for (uint64_t e = 0; e < 3ull * b->triangle_count && !any; e++)
        any = b->triangle_springs[e] != UINT32_MAX;
    if (!any || b->spring_count == 0)
        return CVK_SUCCESS;
    size_t bytes = (size_t)b->spring_count * sizeof(uint32_t);
    uint32_t* alive = malloc(bytes);
    if (!alive)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "%s: out of host memory for %u spring flags",
                        call, b->spring_count);
    cvk_result r = cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd, &s->spring_alive,
                                       alive, bytes, error);
    if (r != CVK_SUCCESS) {
        free(alive);
        return r;
    }
    *alive_out = alive;
    return CVK_SUCCESS;
}

/* Triangle t as drawn (shaders/render/mesh.comp): its own vertices, or its quad's other
   split's (lib/render/split.h) while that is taken; whether it exists: while every spring along
   its edges does (an edge without a spring, a kind the scene leaves out, never tears). alive
   NULL: nothing can tear; splits NULL: no triangle has another split. */
static bool drawn_triangle(const cvk_build* b, const cvk_other_split* splits, const uint32_t* alive,
                           uint32_t t, uint32_t v[3])
{
    const uint32_t* vertices = &b->triangles[3 * (size_t)t];
    const uint32_t* springs = &b->triangle_springs[3 * (size_t)t];
    if (splits && cvk_split_taken(&splits[t], alive)) {
        vertices = splits[t].vertices;
        springs = splits[t].springs;
    }
    memcpy(v, vertices, 3 * sizeof *v);
    if (!alive)
        return true;
    for (int e = 0; e < 3; e++)
        if (springs[e] != UINT32_MAX && alive[springs[e]] == 0)
            return false;
    return true;
}

/* Position of particle `user` (user order) from sim->scratch (internal order), in double. */
static void position_of(const cvk_sim* s, uint32_t user, double out[3])
{
    const float* x = &s->scratch[3 * (size_t)s->build.internal_of[user]];
    for (int c = 0; c < 3; c++)
        out[c] = x[c];
}

static cvk_result compute_normals(const cvk_sim* s, const cvk_other_split* splits, const uint32_t* alive,
                                  float* normals, cvk_error* error)
{
    const cvk_build* b = &s->build;
    double* sum = calloc(3 * (size_t)b->particle_count, sizeof(double));
    if (!sum)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "%s: out of host memory for %u normals",
                        call, b->particle_count);
    for (uint32_t t = 0; t < b->triangle_count; t++) {
        uint32_t v[3];
        if (!drawn_triangle(b, splits, alive, t, v))
            continue;
        double p0[3], p1[3], p2[3];
        position_of(s, v[0], p0);
        position_of(s, v[1], p1);
        position_of(s, v[2], p2);
        double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        double e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++)
                sum[3 * (size_t)v[k] + c] += n[c];
    }
    for (size_t p = 0; p < b->particle_count; p++) {
        const double* n = &sum[3 * p];
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int c = 0; c < 3; c++)
            normals[3 * p + c] = len > 0.0 ? (float)(n[c] / len) : 0.0f;
    }
    free(sum);
    return CVK_SUCCESS;
}

static void copy_triangles(const cvk_build* b, const cvk_other_split* splits, const uint32_t* alive,
                           uint32_t* triangles)
{
    for (uint32_t t = 0; t < b->triangle_count; t++) {
        uint32_t v[3];
        bool live = drawn_triangle(b, splits, alive, t, v);
        for (int k = 0; k < 3; k++)
            triangles[3 * (size_t)t + k] = live ? v[k] : v[0];
    }
}

cvk_result cvk_sim_read_mesh(cvk_sim* s, float* xyz, float* normals, uint32_t* triangles,
                             uint64_t vertex_count, uint64_t triangle_count, cvk_error* error)
{
    if (!s)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s needs a simulation", call);
    cvk_result r = check_counts(s, vertex_count, triangle_count, error);
    if (r != CVK_SUCCESS)
        return r;
    const cvk_build* b = &s->build;
    uint32_t* alive = NULL;
    cvk_other_split* splits = NULL;
    if ((normals || triangles) && b->triangle_count > 0)
        r = read_spring_flags(s, &alive, error);
    if (r == CVK_SUCCESS && alive)
        r = cvk_other_splits(s, &splits, error);
    if (r == CVK_SUCCESS && (xyz || normals))
        r = cvk_sim_read_internal(s, error);
    if (r == CVK_SUCCESS && xyz)
        for (uint32_t p = 0; p < b->particle_count; p++)
            memcpy(&xyz[3 * (size_t)b->user_of[p]], &s->scratch[3 * (size_t)p], 3 * sizeof(float));
    if (r == CVK_SUCCESS && normals)
        r = compute_normals(s, splits, alive, normals, error);
    if (r == CVK_SUCCESS && triangles)
        copy_triangles(b, splits, alive, triangles);
    free(splits);
    free(alive);
    return r;
}
