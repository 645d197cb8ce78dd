/* Mesh colliders as signed distance fields: the mesh is read by the cloth mesh reader
   (lib/topology/topology_mesh.c, so the same files, welding and messages), checked closed and
   consistently wound, and sampled on a dense grid.

   Every sample's distance is exact: the nearest triangle is found through a bounding volume
   hierarchy and the point–triangle distance computed in double. The sign comes from the
   generalized winding number (the triangles' solid angles summed over 4π: 1 inside, 0
   outside, whatever the mesh's shape; Jacobson et al. 2013), computed only for samples within
   one voxel of the surface and carried from there to the rest: two neighbouring samples
   whose distances add up to more than the voxel have no surface between them (any point of
   the segment joining them is closer than that to one of them), so a sample farther than a
   voxel from the surface has the sign of every neighbour. Nothing here depends on a
   threshold near the surface or on thread timing, so a mesh gives the same field every time.

   OpenVDB's mesh-to-level-set was tried first: its distances are good, but it gave samples
   within a voxel of thin parts and concave corners of a closed manifold (the chair's back
   posts, where the legs meet the seat) the wrong sign, which would pull cloth into the solid.

   Sampling here matches what the device does with the same array. */
#include "contact/sdf.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/intersect.h"
#include "core/error.h"
#include "topology/topology.h"
#include "core/u64_map.h"

/* Samples between the mesh's box and the grid's edge on every side, so that points a few
   voxels off the surface, where contact is decided, are sampled (and differentiated, for
   normals) inside the grid rather than through the bound beyond it. */
#define SDF_MARGIN 3

/* The finest grid asked for: 512 voxels along the diagonal is at most 519³ samples (0.5 GiB
   of values, fewer than 2^32 samples), far beyond what a collider needs; the device holds
   every field at once. */
#define SDF_MAX_RESOLUTION 512

static uint64_t edge_key(uint32_t a, uint32_t b)
{
    return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}

/* Every edge of the welded triangles must be shared by exactly two of them, which run along it
   in opposite directions (the winding number, which gives the sign, needs one orientation
   throughout); otherwise the first such edge (triangles in order, each from its first corner)
   is named. */
static cvk_result check_closed(const cvk_mesh_triangles* mesh, const char* path, const char* key,
                               cvk_error* error)
{
    size_t edges = 3 * (size_t)mesh->triangle_count;
    cvk_u64_map map = {0};
    uint32_t* count = calloc(edges ? edges : 1, sizeof *count);
    uint32_t* forward = calloc(edges ? edges : 1, sizeof *forward); /* runs from low to high */
    uint64_t* order = malloc((edges ? edges : 1) * sizeof *order);
    if (!count || !forward || !order || !cvk_u64_map_init(&map, edges)) {
        free(count);
        free(forward);
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
        forward[map.value[slot]] += a < b;
    }
    cvk_result result = CVK_SUCCESS;
    for (uint32_t e = 0; e < distinct && result == CVK_SUCCESS; e++)
        if (count[e] != 2)
            result = cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s: the mesh is not closed "
                              "(edge between vertices %u and %u has %u triangle%s); a mesh "
                              "collider needs a closed surface", key, path,
                              (uint32_t)(order[e] >> 32), (uint32_t)order[e], count[e],
                              count[e] == 1 ? "" : "s");
        else if (forward[e] != 1)
            result = cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s: the mesh is not wound "
                              "consistently (both triangles on the edge between vertices %u and "
                              "%u run along it the same way); a mesh collider needs its "
                              "triangles counter-clockwise from outside", key, path,
                              (uint32_t)(order[e] >> 32), (uint32_t)order[e]);
    free(count);
    free(forward);
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

/* ---- the field: exact distances through a bounding volume hierarchy ----------------------- */

/* Leaves hold at most this many triangles. */
#define BVH_LEAF 4
/* Below this depth nodes split at the middle of their centroids' box; deeper (meshes whose
   triangles crowd into ever smaller regions) they split by count, which bounds the depth by
   BVH_SPATIAL_DEPTH + log2(triangles) and the traversal stack by BVH_STACK. */
#define BVH_SPATIAL_DEPTH 48
#define BVH_STACK 128

typedef struct bvh_node {
    float lo[3], hi[3];      /* box of its triangles' vertices, m */
    uint32_t first, count;   /* a leaf: order[first .. first + count); count 0: inner node */
    uint32_t child;          /* an inner node: its children are child and child + 1 */
} bvh_node;

typedef struct field_mesh {
    const cvk_mesh_triangles* mesh;
    uint32_t* order;         /* triangles, grouped by leaf */
    float* centroid;         /* 3 per triangle */
    bvh_node* nodes;
    uint32_t node_count;
} field_mesh;

static const float* corner_of(const field_mesh* f, uint32_t t, int c)
{
    return &f->mesh->xyz[3 * (size_t)f->mesh->triangles[3 * (size_t)t + c]];
}

static void node_box(field_mesh* f, bvh_node* n)
{
    for (int k = 0; k < 3; k++) {
        n->lo[k] = INFINITY;
        n->hi[k] = -INFINITY;
    }
    for (uint32_t i = n->first; i < n->first + n->count; i++)
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++) {
                n->lo[k] = fminf(n->lo[k], corner_of(f, f->order[i], c)[k]);
                n->hi[k] = fmaxf(n->hi[k], corner_of(f, f->order[i], c)[k]);
            }
}

/* Splits order[first, first + count) in two non-empty parts: by the middle of the centroids'
   longest extent, or in halves by count when that leaves a side empty or the node is deep. */
static uint32_t split_at(field_mesh* f, uint32_t first, uint32_t count, uint32_t depth)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = first; i < first + count; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], f->centroid[3 * (size_t)f->order[i] + k]);
            hi[k] = fmaxf(hi[k], f->centroid[3 * (size_t)f->order[i] + k]);
        }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (hi[k] - lo[k] > hi[axis] - lo[axis])
            axis = k;
    float middle = 0.5f * (lo[axis] + hi[axis]);
    uint32_t left = first;
    for (uint32_t i = first; depth < BVH_SPATIAL_DEPTH && i < first + count; i++)
        if (f->centroid[3 * (size_t)f->order[i] + axis] < middle) {
            uint32_t t = f->order[i];
            f->order[i] = f->order[left];
            f->order[left++] = t;
        }
    if (left == first || left == first + count)
        left = first + count / 2;
    return left - first;
}

static void build_node(field_mesh* f, uint32_t index, uint32_t depth)
{
    bvh_node* n = &f->nodes[index];
    node_box(f, n);
    if (n->count <= BVH_LEAF)
        return;
    uint32_t left = split_at(f, n->first, n->count, depth);
    n->child = f->node_count;
    f->node_count += 2;
    f->nodes[n->child] = (bvh_node){.first = n->first, .count = left};
    f->nodes[n->child + 1] = (bvh_node){.first = n->first + left, .count = n->count - left};
    n->count = 0;
    build_node(f, n->child, depth + 1);
    build_node(f, n->child + 1, depth + 1);
}

static bool build_bvh(field_mesh* f)
{
    uint32_t n = f->mesh->triangle_count;
    f->order = malloc(n * sizeof *f->order);
    f->centroid = malloc(3 * (size_t)n * sizeof *f->centroid);
    f->nodes = malloc(2 * (size_t)n * sizeof *f->nodes); /* a binary tree of n leaves at most */
    if (!f->order || !f->centroid || !f->nodes)
        return false;
    for (uint32_t t = 0; t < n; t++) {
        f->order[t] = t;
        for (int k = 0; k < 3; k++)
            f->centroid[3 * (size_t)t + k] = (corner_of(f, t, 0)[k] + corner_of(f, t, 1)[k] +
                                              corner_of(f, t, 2)[k]) / 3.0f;
    }
    f->nodes[0] = (bvh_node){.first = 0, .count = n};
    f->node_count = 1;
    build_node(f, 0, 0);
    return true;
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Squared distance from p to triangle t, in double (intersect.h). */
static double triangle_distance2(const field_mesh* f, uint32_t t, const double p[3])
{
    double corner[3][3];
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++)
            corner[k][c] = corner_of(f, t, k)[c];
    return cvk_point_triangle_distance2(p, corner[0], corner[1], corner[2]);
}

static double box_distance2(const bvh_node* n, const double p[3])
{
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double d = fmax(fmax(n->lo[k] - p[k], p[k] - n->hi[k]), 0.0);
        d2 += d * d;
    }
    return d2;
}

/* The squared distance from p to the mesh; *nearest is a triangle at that distance. It may
   hold a triangle on entry (the previous sample's), which bounds the search from the start. */
static double mesh_distance2(const field_mesh* f, const double p[3], uint32_t* nearest)
{
    double best = triangle_distance2(f, *nearest, p);
    uint32_t stack[BVH_STACK], top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const bvh_node* n = &f->nodes[stack[--top]];
        if (box_distance2(n, p) >= best)
            continue;
        for (uint32_t i = n->first; i < n->first + n->count; i++) {
            double d2 = triangle_distance2(f, f->order[i], p);
            if (d2 < best) {
                best = d2;
                *nearest = f->order[i];
            }
        }
        if (n->count == 0) { /* the nearer child last, so it is searched first */
            bool left_first = box_distance2(&f->nodes[n->child], p) <=
                              box_distance2(&f->nodes[n->child + 1], p);
            stack[top++] = n->child + (left_first ? 1 : 0);
            stack[top++] = n->child + (left_first ? 0 : 1);
        }
    }
    return best;
}

/* The generalized winding number of the mesh at p: the triangles' signed solid angles
   (Van Oosterom and Strackee's formula) over 4π. */
static double winding_number(const field_mesh* f, const double p[3])
{
    double sum = 0.0;
    for (uint32_t t = 0; t < f->mesh->triangle_count; t++) {
        double a[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            a[k] = corner_of(f, t, 0)[k] - p[k];
            b[k] = corner_of(f, t, 1)[k] - p[k];
            c[k] = corner_of(f, t, 2)[k] - p[k];
        }
        double la = sqrt(dot(a, a)), lb = sqrt(dot(b, b)), lc = sqrt(dot(c, c));
        double bc[3] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]};
        double below = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
        sum += 2.0 * atan2(dot(a, bc), below);
    }
    return sum / (4.0 * 3.14159265358979323846);
}

/* The point of sample s. */
static void sample_point(const cvk_sdf* out, size_t s, double p[3])
{
    const uint32_t* d = out->dims;
    p[0] = out->origin[0] + out->voxel * (double)(s % d[0]);
    p[1] = out->origin[1] + out->voxel * (double)(s / d[0] % d[1]);
    p[2] = out->origin[2] + out->voxel * (double)(s / d[0] / d[1]);
}

/* Signs for the unsigned distances in out->values, breadth first: a neighbour whose distance
   and this sample's add up to more than the voxel has this sample's sign (the 1e-4 covers the
   distances' rounding to float); a sample no known neighbour decides gets the sign of its
   winding number (by magnitude, so a mesh wound inside out is still solid inside) and starts a
   new search. A winding number is computed for about one sample per connected region and
   for samples squeezed between close surfaces, not for every sample near the surface. */
static void fill_signs(const field_mesh* f, cvk_sdf* out, int8_t* sign, uint32_t* queue)
{
    const uint32_t* d = out->dims;
    const size_t samples = (size_t)d[0] * d[1] * d[2], step[3] = {1, d[0], (size_t)d[0] * d[1]};
    const float apart = out->voxel * 1.0001f;
    size_t unknown = 0;
    uint32_t head = 0, tail = 0;
    for (;;) {
        if (head == tail) {
            while (unknown < samples && sign[unknown])
                unknown++;
            if (unknown == samples)
                return;
            double p[3];
            sample_point(out, unknown, p);
            sign[unknown] = fabs(winding_number(f, p)) > 0.5 ? -1 : 1;
            queue[tail++] = (uint32_t)unknown;
        }
        size_t s = queue[head++];
        const uint32_t at[3] = {(uint32_t)(s % d[0]), (uint32_t)(s / d[0] % d[1]),
                                (uint32_t)(s / step[2])};
        for (int k = 0; k < 6; k++) {
            int axis = k / 2;
            bool up = k % 2;
            if (up ? at[axis] + 1 >= d[axis] : at[axis] == 0)
                continue;
            size_t n = up ? s + step[axis] : s - step[axis];
            if (!sign[n] && out->values[s] + out->values[n] > apart) {
                sign[n] = sign[s];
                queue[tail++] = (uint32_t)n;
            }
        }
    }
}

/* Exact unsigned distances at every sample, then their signs. */
static bool fill_field(const cvk_mesh_triangles* mesh, cvk_sdf* out)
{
    field_mesh f = {.mesh = mesh};
    size_t samples = (size_t)out->dims[0] * out->dims[1] * out->dims[2];
    int8_t* sign = calloc(samples, sizeof *sign);
    uint32_t* queue = malloc(samples * sizeof *queue); /* samples < 2^32: SDF_MAX_RESOLUTION */
    bool ok = sign && queue && build_bvh(&f);
    uint32_t nearest = 0;
    for (size_t s = 0; ok && s < samples; s++) {
        double p[3];
        sample_point(out, s, p);
        out->values[s] = (float)sqrt(mesh_distance2(&f, p, &nearest));
    }
    if (ok)
        fill_signs(&f, out, sign, queue);
    for (size_t s = 0; ok && s < samples; s++)
        out->values[s] *= sign[s];
    free(sign);
    free(queue);
    free(f.order);
    free(f.centroid);
    free(f.nodes);
    return ok;
}

static cvk_result build_field(const cvk_mesh_triangles* mesh, const char* path, const char* key,
                              cvk_sdf* out, cvk_error* error)
{
    size_t samples = (size_t)out->dims[0] * out->dims[1] * out->dims[2];
    out->values = malloc(samples * sizeof *out->values);
    if (!out->values || !fill_field(mesh, out))
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "%s: %s: out of host memory for a "
                        "signed distance field of %u x %u x %u samples", key, path, out->dims[0],
                        out->dims[1], out->dims[2]);
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
                        "%g m; it must be a finite number, 0 or more", key, (double)min_voxel);
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
