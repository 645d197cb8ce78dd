/* Mesh colliders as signed distance fields: the mesh is read by the cloth mesh reader
   (lib/topology_mesh.c, so the same files, welding and messages), checked closed, and turned
   into a dense grid of distances by OpenVDB (lib/sdf_vdb.cpp). Sampling here matches what the
   device does with the same array. */
#include "sdf.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "error.h"
#include "sdf_vdb.h"
#include "topology.h"
#include "u64_map.h"

/* Samples between the mesh's box and the grid's edge on every side: trilinear sampling and
   the device's finite-difference normals read one sample beyond the point, and a cloth
   particle a few voxels off the surface still samples inside the grid. */
#define SDF_MARGIN 3

/* The finest grid asked for: 512 voxels along the diagonal is at most about 520³ samples
   (0.5 GiB), far beyond what a collider needs; the device holds every field at once. */
#define SDF_MAX_RESOLUTION 512

static uint64_t edge_key(uint32_t a, uint32_t b)
{
    return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}

/* Every edge of the welded triangles must be shared by exactly two of them; otherwise the
   first such edge (triangles in order, each from its first corner) is named. */
static cvk_result check_closed(const cvk_mesh_triangles* mesh, const char* path, const char* key,
                               cvk_error* error)
{
    size_t edges = 3 * (size_t)mesh->triangle_count;
    cvk_u64_map map = {0};
    uint32_t* count = calloc(edges ? edges : 1, sizeof *count);
    uint64_t* order = malloc((edges ? edges : 1) * sizeof *order);
    if (!count || !order || !cvk_u64_map_init(&map, edges)) {
        free(count);
        free(order);
        cvk_u64_map_free(&map);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "%s: %s: out of host memory for the "
                        "edges", key, path);
    }
    uint32_t distinct = 0;
    for (size_t c = 0; c < edges; c++) {
        uint32_t a = mesh->triangles[c], b = mesh->triangles[c - c % 3 + (c + 1) % 3];
        size_t slot = cvk_u64_map_slot(&map, edge_key(a, b));
        if (map.key[slot] == CVK_U64_MAP_EMPTY) {
            map.key[slot] = edge_key(a, b);
            map.value[slot] = distinct;
            order[distinct++] = edge_key(a, b);
        }
        count[map.value[slot]]++;
    }
    cvk_result result = CVK_SUCCESS;
    for (uint32_t e = 0; e < distinct && result == CVK_SUCCESS; e++)
        if (count[e] != 2)
            result = cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s: the mesh is not closed "
                              "(edge between vertices %u and %u has %u triangle%s); a mesh "
                              "collider needs a closed surface", key, path,
                              (uint32_t)(order[e] >> 32), (uint32_t)order[e], count[e],
                              count[e] == 1 ? "" : "s");
    free(count);
    free(order);
    cvk_u64_map_free(&map);
    return result;
}

/* voxel = max(diagonal / resolution, min_voxel); the mesh's box plus SDF_MARGIN voxels. */
static void place_grid(const cvk_mesh_triangles* mesh, uint32_t resolution, float min_voxel,
                       cvk_sdf* out)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], mesh->xyz[3 * (size_t)v + k]);
            hi[k] = fmax(hi[k], mesh->xyz[3 * (size_t)v + k]);
        }
    double d2 = 0.0;
    for (int k = 0; k < 3; k++)
        d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    double voxel = fmax(sqrt(d2) / resolution, (double)min_voxel);
    out->voxel = (float)voxel;
    for (int k = 0; k < 3; k++) {
        out->dims[k] = (uint32_t)ceil((hi[k] - lo[k]) / voxel) + 1 + 2 * SDF_MARGIN;
        out->origin[k] = (float)(lo[k] - SDF_MARGIN * voxel);
    }
}

static cvk_result build_field(const cvk_mesh_triangles* mesh, const char* path, const char* key,
                              cvk_sdf* out, cvk_error* error)
{
    size_t samples = (size_t)out->dims[0] * out->dims[1] * out->dims[2];
    out->values = malloc(samples * sizeof *out->values);
    if (!out->values)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "%s: %s: out of host memory for a "
                        "signed distance field of %u x %u x %u samples", key, path, out->dims[0],
                        out->dims[1], out->dims[2]);
    char why[256] = "";
    cvk_result result = cvk_sdf_vdb_fill(mesh->xyz, mesh->vertex_count, mesh->triangles,
                                         mesh->triangle_count, out->dims, out->origin, out->voxel,
                                         out->values, why, sizeof why);
    if (result != CVK_SUCCESS)
        return cvk_fail(error, result, "%s: %s: %s", key, path, why);
    return CVK_SUCCESS;
}

static cvk_result check_arguments(const char* path, uint32_t resolution, float min_voxel,
                                  const char* key, cvk_error* error)
{
    if (!path)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: no mesh file given", key);
    if (resolution < 2 || resolution > SDF_MAX_RESOLUTION)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: signed distance resolution %u; "
                        "it must be 2 to %u voxels along the mesh's diagonal", key, resolution,
                        SDF_MAX_RESOLUTION);
    if (!(min_voxel >= 0.0f) || !isfinite(min_voxel))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: smallest signed distance voxel "
                        "%g m; it must be a finite number ≥ 0", key, (double)min_voxel);
    return CVK_SUCCESS;
}

cvk_result cvk_sdf_from_mesh_file(const char* path, const cvk_transform* transform,
                                  uint32_t resolution, float min_voxel, const char* key,
                                  cvk_sdf* out, cvk_error* error)
{
    memset(out, 0, sizeof *out);
    key = key ? key : "mesh";
    cvk_result result = check_arguments(path, resolution, min_voxel, key, error);
    if (result != CVK_SUCCESS)
        return result;
    const cvk_transform identity = {{1, 1, 1}, {1, 0, 0, 0}, {0, 0, 0}};
    cvk_mesh_triangles mesh;
    result = cvk_topology_mesh_triangles(path, transform ? transform : &identity, key, &mesh,
                                         error);
    if (result != CVK_SUCCESS)
        return result;
    result = check_closed(&mesh, path, key, error);
    if (result == CVK_SUCCESS) {
        place_grid(&mesh, resolution, min_voxel, out);
        result = build_field(&mesh, path, key, out, error);
    }
    if (result == CVK_SUCCESS) {
        out->xyz = mesh.xyz;
        out->vertex_count = mesh.vertex_count;
        out->triangles = mesh.triangles;
        out->triangle_count = mesh.triangle_count;
        return CVK_SUCCESS;
    }
    cvk_mesh_triangles_free(&mesh);
    cvk_sdf_destroy(out);
    return result;
}

void cvk_sdf_destroy(cvk_sdf* sdf)
{
    if (!sdf)
        return;
    free(sdf->values);
    free(sdf->xyz);
    free(sdf->triangles);
    memset(sdf, 0, sizeof *sdf);
}

static float value_at(const cvk_sdf* sdf, uint32_t i, uint32_t j, uint32_t k)
{
    return sdf->values[i + (size_t)sdf->dims[0] * (j + (size_t)sdf->dims[1] * k)];
}

/* p is clamped to the grid's box; the clamped point q is sampled trilinearly and |p − q| added.
   Inside the box that is plain trilinear interpolation. Outside, the distance to the mesh is
   at least |p − q| (the mesh lies inside the box) and at most value(q) + |p − q|: the field
   runs on continuously across the box's faces. NaN coordinates give NaN, never an index out
   of range (fmaxf(NaN, 0) is 0). */
float cvk_sdf_sample(const cvk_sdf* sdf, const float p[3])
{
    float t[3], outside2 = 0.0f;
    uint32_t base[3];
    for (int k = 0; k < 3; k++) {
        float top = (float)(sdf->dims[k] - 1);
        float g = (p[k] - sdf->origin[k]) / sdf->voxel;
        float c = fminf(fmaxf(g, 0.0f), top);
        float off = (g - c) * sdf->voxel;
        outside2 += off * off;
        base[k] = (uint32_t)fminf(floorf(c), top - 1.0f);
        t[k] = c - (float)base[k];
    }
    float v = 0.0f;
    for (int corner = 0; corner < 8; corner++) {
        uint32_t dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
        float w = (dx ? t[0] : 1.0f - t[0]) * (dy ? t[1] : 1.0f - t[1]) * (dz ? t[2] : 1.0f - t[2]);
        v += w * value_at(sdf, base[0] + dx, base[1] + dy, base[2] + dz);
    }
    return v + sqrtf(outside2);
}
