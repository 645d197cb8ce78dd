/* Cloth from a mesh file: Assimp reads the file (topology_mesh_file.c) and its vertices are
   welded into particles (topology_mesh_weld.c); this file splits its faces into triangles, lays
   springs along the file's own edges and hands out the topology.

   Everything is decided in file order, so one file always gives the same particles, triangles
   and springs in the same order: particles are the welded vertices once, in order of first
   appearance (meshes in the order Assimp yields them, each mesh's vertices in order, vertices
   no face uses skipped) — for OBJ files, in the order of their "v" lines (obj_vertex_order);
   faces are numbered 0, 1, ... over the faces of three or more corners in the same walk.
   Welding and the degenerate-face checks work in file coordinates; the transform is applied
   last. */
#include "topology/mesh_reader.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/vec3.h"

/* Triangles of less area than this fraction of diagonal² are degenerate. A triangle whose edges
   are at least the weld tolerance (1e-6 · diagonal) long but whose area is below 1e-12 · diagonal²
   is a sliver: with an edge of 1e-3 · diagonal its height is 2e-9 · diagonal, thirty times below
   float resolution there, so its normal and area are rounding noise. */
#define DEGENERATE_AREA 1e-12

/* Faces of more than four corners are fanned from their first corner only when that is safe:
   every corner within this fraction of the face's size from its plane, and the boundary never
   turning against the face's normal by more than this sine (collinear corners are fine). */
#define PLANAR_TOLERANCE 1e-3
#define CONVEX_TOLERANCE 1e-6

/* Why a triangle edge is there: an edge of the file's face, a quad's split diagonal (its shear
   spring), or a diagonal added to fan a larger face (no spring). */
enum { EDGE_FACE = 0, EDGE_QUAD_DIAGONAL = 1, EDGE_FAN_DIAGONAL = 2 };

/* An unordered pair of particles as one key. */
static uint64_t pair_key(uint32_t a, uint32_t b)
{
    return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}

/* ---- faces into triangles -------------------------------------------------------------------- */

static void sub3(const float* a, const float* b, double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = (double)a[k] - b[k];
}


static bool degenerate(const cvk_mesh_reader* r, const uint32_t t[3])
{
    double e1[3], e2[3], c[3];
    sub3(&r->position[3 * (size_t)t[1]], &r->position[3 * (size_t)t[0]], e1);
    sub3(&r->position[3 * (size_t)t[2]], &r->position[3 * (size_t)t[0]], e2);
    cvk_cross3d(e1, e2, c);
    return 0.5 * sqrt(cvk_dot3d(c, c)) < DEGENERATE_AREA * r->diagonal * r->diagonal;
}

/* Whether a face of n > 4 corners is planar and convex, so that a fan from its first corner
   covers it exactly. The normal is Newell's, which any simple polygon has. */
static bool fan_safe(const cvk_mesh_reader* r, const uint32_t* c, size_t n)
{
    double normal[3] = {0.0, 0.0, 0.0}, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3];
    for (int k = 0; k < 3; k++)
        hi[k] = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        const float* p = &r->position[3 * (size_t)c[i]];
        const float* q = &r->position[3 * (size_t)c[(i + 1) % n]];
        normal[0] += ((double)p[1] - q[1]) * ((double)p[2] + q[2]);
        normal[1] += ((double)p[2] - q[2]) * ((double)p[0] + q[0]);
        normal[2] += ((double)p[0] - q[0]) * ((double)p[1] + q[1]);
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], p[k]);
            hi[k] = fmax(hi[k], p[k]);
        }
    }
    double length = sqrt(cvk_dot3d(normal, normal));
    if (length == 0.0)
        return false;
    double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    double size = sqrt(cvk_dot3d(d, d));
    for (int k = 0; k < 3; k++)
        normal[k] /= length;
    for (size_t i = 0; i < n; i++) {
        const float* p0 = &r->position[3 * (size_t)c[i]];
        const float* p1 = &r->position[3 * (size_t)c[(i + 1) % n]];
        const float* p2 = &r->position[3 * (size_t)c[(i + 2) % n]];
        double a[3], b[3], turn[3], off[3];
        sub3(p1, p0, a);
        sub3(p2, p1, b);
        sub3(p0, &r->position[3 * (size_t)c[0]], off);
        cvk_cross3d(a, b, turn);
        if (fabs(cvk_dot3d(off, normal)) > PLANAR_TOLERANCE * size)
            return false;
        if (cvk_dot3d(turn, normal) < -CONVEX_TOLERANCE * sqrt(cvk_dot3d(a, a) * cvk_dot3d(b, b)))
            return false;
    }
    return true;
}

static void emit_triangle(cvk_mesh_reader* r, uint32_t a, uint32_t b, uint32_t c, uint8_t k0,
                          uint8_t k1, uint8_t k2)
{
    size_t t = r->triangle_count++;
    r->triangles[3 * t] = a;
    r->triangles[3 * t + 1] = b;
    r->triangles[3 * t + 2] = c;
    r->edge_kind[3 * t] = k0;
    r->edge_kind[3 * t + 1] = k1;
    r->edge_kind[3 * t + 2] = k2;
}

/* Quads split along v1–v3 into (v0, v1, v3) and (v1, v2, v3), so that a grid written as quads
   a b d c gives the grid's own triangles (a, b, c), (b, d, c); larger faces are fanned from
   their first corner. Winding is kept. */
static void split_face(cvk_mesh_reader* r, const uint32_t* c, size_t n)
{
    if (n == 3) {
        emit_triangle(r, c[0], c[1], c[2], EDGE_FACE, EDGE_FACE, EDGE_FACE);
    } else if (n == 4) {
        emit_triangle(r, c[0], c[1], c[3], EDGE_FACE, EDGE_QUAD_DIAGONAL, EDGE_FACE);
        emit_triangle(r, c[1], c[2], c[3], EDGE_FACE, EDGE_FACE, EDGE_QUAD_DIAGONAL);
    } else {
        for (size_t k = 1; k + 1 < n; k++)
            emit_triangle(r, c[0], c[k], c[k + 1], k == 1 ? EDGE_FACE : EDGE_FAN_DIAGONAL,
                          EDGE_FACE, k + 2 == n ? EDGE_FACE : EDGE_FAN_DIAGONAL);
    }
}

/* Splits every face, checking on the way that no face repeats a particle (two corners welded
   together), that larger faces can be fanned, and that no triangle has zero area. */
static cvk_result split_faces(cvk_mesh_reader* r)
{
    r->triangles = malloc(3 * r->corner_count * sizeof *r->triangles);
    r->edge_kind = malloc(3 * r->corner_count * sizeof *r->edge_kind);
    size_t* stamp = calloc(r->vertex_count, sizeof *stamp); /* face + 1 that last used a particle */
    cvk_result result = CVK_SUCCESS;
    if (!r->triangles || !r->edge_kind || !stamp)
        result = cvk_mesh_out_of_memory(r, "the triangles");
    for (size_t f = 0; f < r->face_count && result == CVK_SUCCESS; f++) {
        const uint32_t* c = &r->corner[r->face_start[f]];
        size_t n = r->face_start[f + 1] - r->face_start[f];
        bool repeats = false;
        for (size_t i = 0; i < n; i++) {
            repeats = repeats || stamp[c[i]] == f + 1;
            stamp[c[i]] = f + 1;
        }
        if (!repeats && n > 4 && !fan_safe(r, c, n)) {
            result = cvk_mesh_bad(r, "face %zu has %zu corners and is not planar and convex, so it "
                              "cannot be split into triangles; triangulate it", f, n);
            break;
        }
        uint32_t first = r->triangle_count;
        split_face(r, c, n);
        for (uint32_t t = first; t < r->triangle_count; t++)
            repeats = repeats || degenerate(r, &r->triangles[3 * (size_t)t]);
        if (repeats)
            result = cvk_mesh_bad(r, "face %zu is degenerate (zero area)", f);
    }
    free(stamp);
    return result;
}

/* ---- edges and springs ----------------------------------------------------------------------- */

/* Every edge of the file's faces once, in order of first appearance (faces in order, each
   face's edges from its first corner), with the number of faces that have it. */
static cvk_result find_edges(cvk_mesh_reader* r)
{
    r->edge_ends = malloc(2 * r->corner_count * sizeof *r->edge_ends);
    r->edge_faces = calloc(r->corner_count, sizeof *r->edge_faces);
    r->edge_opposite = malloc(2 * r->corner_count * sizeof *r->edge_opposite);
    if (!r->edge_ends || !r->edge_faces || !r->edge_opposite ||
        !cvk_u64_map_init(&r->edge_map, r->corner_count))
        return cvk_mesh_out_of_memory(r, "the edges");
    for (size_t f = 0; f < r->face_count; f++) {
        const uint32_t* c = &r->corner[r->face_start[f]];
        size_t n = r->face_start[f + 1] - r->face_start[f];
        for (size_t i = 0; i < n; i++) {
            uint32_t a = c[i], b = c[(i + 1) % n];
            size_t slot = cvk_u64_map_slot(&r->edge_map, pair_key(a, b));
            if (r->edge_map.key[slot] == CVK_U64_MAP_EMPTY) {
                r->edge_map.key[slot] = pair_key(a, b);
                r->edge_map.value[slot] = r->edge_count;
                r->edge_ends[2 * (size_t)r->edge_count] = a;
                r->edge_ends[2 * (size_t)r->edge_count + 1] = b;
                r->edge_count++;
            }
            r->edge_faces[r->edge_map.value[slot]]++;
        }
    }
    for (uint32_t e = 0; e < r->edge_count; e++) {
        if (r->edge_faces[e] <= 2)
            continue;
        uint32_t a = r->edge_ends[2 * (size_t)e], b = r->edge_ends[2 * (size_t)e + 1];
        return cvk_mesh_bad(r, "the edge between vertices %u and %u is shared by %u faces "
                        "(non-manifold)", a < b ? a : b, a < b ? b : a, r->edge_faces[e]);
    }
    return CVK_SUCCESS;
}

/* For each face edge, the corner opposite it in the triangle that holds it: the two ends of a
   bend spring across an interior edge. Two triangles on one edge with the same opposite
   corner are one triangle twice (a face the file repeats): each of its edges then has two
   faces, which the non-manifold check cannot see, and it would count its mass twice. */
static cvk_result find_opposites(cvk_mesh_reader* r)
{
    uint32_t* seen = r->edge_faces; /* reused as a count of sides filled */
    memset(seen, 0, r->edge_count * sizeof *seen);
    for (uint32_t t = 0; t < r->triangle_count; t++) {
        const uint32_t* v = &r->triangles[3 * (size_t)t];
        for (int k = 0; k < 3; k++) {
            if (r->edge_kind[3 * (size_t)t + k] != EDGE_FACE)
                continue;
            size_t slot = cvk_u64_map_slot(&r->edge_map, pair_key(v[k], v[(k + 1) % 3]));
            uint32_t e = r->edge_map.value[slot];
            r->edge_opposite[2 * (size_t)e + seen[e]++] = v[(k + 2) % 3];
        }
    }
    for (uint32_t e = 0; e < r->edge_count; e++) {
        const uint32_t* o = &r->edge_opposite[2 * (size_t)e];
        if (seen[e] < 2 || o[0] != o[1])
            continue;
        uint32_t a = r->edge_ends[2 * (size_t)e], b = r->edge_ends[2 * (size_t)e + 1];
        return cvk_mesh_bad(r, "the faces on the edge between vertices %u and %u both have corner "
                        "%u (a face repeated)", a < b ? a : b, a < b ? b : a, o[0]);
    }
    return CVK_SUCCESS;
}

/* Adds spring (a, b) unless the pair already has one. */
static void add_spring(cvk_mesh_reader* r, cvk_topology* out, uint32_t a, uint32_t b, uint32_t type)
{
    if (a == b)
        return;
    size_t slot = cvk_u64_map_slot(&r->spring_map, pair_key(a, b));
    if (r->spring_map.key[slot] != CVK_U64_MAP_EMPTY)
        return;
    r->spring_map.key[slot] = pair_key(a, b);
    r->spring_map.value[slot] = out->spring_count;
    out->springs[out->spring_count++] = (cvk_topo_spring){.a = a, .b = b, .type = type};
}

/* Structural springs on the edges, then shear springs across quads, then bend springs across
   interior edges; each kind only with non-zero stiffness, and the first spring of a pair wins. */
static cvk_result lay_springs(cvk_mesh_reader* r, cvk_topology* out)
{
    size_t most = 2 * (size_t)r->edge_count + r->corner_count;
    out->springs = malloc(most * sizeof *out->springs);
    if (!out->springs || !cvk_u64_map_init(&r->spring_map, most))
        return cvk_mesh_out_of_memory(r, "the springs");
    const cvk_stiffness* k = &r->cloth->stiffness;
    for (uint32_t e = 0; k->structural > 0.0f && e < r->edge_count; e++)
        add_spring(r, out, r->edge_ends[2 * (size_t)e], r->edge_ends[2 * (size_t)e + 1],
                   CVK_SPRING_STRUCTURAL);
    for (size_t f = 0; k->shear > 0.0f && f < r->face_count; f++) {
        const uint32_t* c = &r->corner[r->face_start[f]];
        if (r->face_start[f + 1] - r->face_start[f] != 4)
            continue;
        add_spring(r, out, c[0], c[2], CVK_SPRING_SHEAR);
        add_spring(r, out, c[1], c[3], CVK_SPRING_SHEAR);
    }
    for (uint32_t e = 0; k->bend > 0.0f && e < r->edge_count; e++)
        if (r->edge_faces[e] == 2)
            add_spring(r, out, r->edge_opposite[2 * (size_t)e], r->edge_opposite[2 * (size_t)e + 1],
                       CVK_SPRING_BEND);
    return CVK_SUCCESS;
}

/* Per triangle edge: the spring on a face edge (structural), on a quad's split diagonal (its
   shear spring), none on a fan diagonal. */
static cvk_result link_triangle_springs(cvk_mesh_reader* r, cvk_topology* out)
{
    out->triangle_springs = malloc(3 * (size_t)r->triangle_count * sizeof *out->triangle_springs);
    if (!out->triangle_springs)
        return cvk_mesh_out_of_memory(r, "the triangles' springs");
    const cvk_stiffness* k = &r->cloth->stiffness;
    for (uint32_t t = 0; t < r->triangle_count; t++) {
        const uint32_t* v = &r->triangles[3 * (size_t)t];
        for (int e = 0; e < 3; e++) {
            uint8_t kind = r->edge_kind[3 * (size_t)t + e];
            bool has = (kind == EDGE_FACE && k->structural > 0.0f) ||
                       (kind == EDGE_QUAD_DIAGONAL && k->shear > 0.0f);
            size_t slot = cvk_u64_map_slot(&r->spring_map, pair_key(v[e], v[(e + 1) % 3]));
            out->triangle_springs[3 * (size_t)t + e] =
                has && r->spring_map.key[slot] != CVK_U64_MAP_EMPTY ? r->spring_map.value[slot] : CVK_NO_SPRING;
        }
    }
    return CVK_SUCCESS;
}

/* ---- output ---------------------------------------------------------------------------------- */

/* x' = translation + rotation (scale ⊙ x), the rotation a unit quaternion [w, x, y, z]:
   v' = v + 2w (u × v) + 2 u × (u × v), u its vector part. */
static void transform_positions(const cvk_transform* t, const float* in, float* out, uint32_t n)
{
    double q[4] = {t->rotation[0], t->rotation[1], t->rotation[2], t->rotation[3]};
    double norm = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; k++)
        q[k] = norm > 0.0 && isfinite(norm) ? q[k] / norm : (k == 0); /* scene checks catch 0 */
    const double u[3] = {q[1], q[2], q[3]};
    for (uint32_t i = 0; i < n; i++) {
        double v[3], c[3], cc[3];
        for (int k = 0; k < 3; k++)
            v[k] = (double)in[3 * (size_t)i + k] * t->scale[k];
        cvk_cross3d(u, v, c);
        cvk_cross3d(u, c, cc);
        for (int k = 0; k < 3; k++)
            out[3 * (size_t)i + k] = (float)(v[k] + 2.0 * q[0] * c[k] + 2.0 * cc[k] + t->translation[k]);
    }
}

/* The simulation works in metres in single precision: positions beyond CVK_MAX_COORDINATE (the
   scene keys' bound too, scene/check.h) are rounding noise, and a cloth smaller than MIN_EXTENT
   has springs whose squared lengths approach float's smallest numbers. Either gives garbage,
   not a simulation. */
#define MIN_EXTENT 1e-4

static cvk_result check_extent(cvk_mesh_reader* r, const float* position)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < r->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            double x = position[3 * (size_t)v + k];
            if (!(fabs(x) <= CVK_MAX_COORDINATE))
                return cvk_mesh_bad(r, "vertex %u lies %g m from the origin on axis %c (after the "
                                "transform); positions are single-precision metres, at most "
                                "%g m", v, fabs(x), "xyz"[k], CVK_MAX_COORDINATE);
            lo[k] = fmin(lo[k], x);
            hi[k] = fmax(hi[k], x);
        }
    double d2 = 0.0;
    for (int k = 0; k < 3; k++)
        d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    if (sqrt(d2) < MIN_EXTENT)
        return cvk_mesh_bad(r, "the mesh is %g m across (after the transform); positions are "
                        "single-precision metres, at least %g m across", sqrt(d2), MIN_EXTENT);
    return CVK_SUCCESS;
}

static cvk_result fill_output(cvk_mesh_reader* r, cvk_topology* out)
{
    out->vertex_count = r->vertex_count;
    out->position = malloc(3 * (size_t)r->vertex_count * sizeof *out->position);
    out->mass = calloc(r->vertex_count, sizeof *out->mass);
    out->pinned = calloc(r->vertex_count, sizeof *out->pinned);
    if (!out->position || !out->mass || !out->pinned)
        return cvk_mesh_out_of_memory(r, "the particles");
    transform_positions(&r->cloth->transform, r->position, out->position, r->vertex_count);
    cvk_result result = check_extent(r, out->position);
    if (result != CVK_SUCCESS)
        return result;
    out->triangle_count = r->triangle_count;
    out->triangles = r->triangles;
    r->triangles = NULL;
    return r->cloth->texture || r->cloth->normal_map ? cvk_mesh_fill_uv(r, out) : CVK_SUCCESS;
}

static cvk_result read_mesh(cvk_mesh_reader* r, cvk_topology* out)
{
    cvk_result result = cvk_mesh_open(r);
    if (result == CVK_SUCCESS)
        result = cvk_mesh_weld(r);
    if (result == CVK_SUCCESS)
        result = cvk_mesh_gather_faces(r);
    if (result == CVK_SUCCESS)
        result = split_faces(r);
    if (result == CVK_SUCCESS)
        result = find_edges(r);
    if (result == CVK_SUCCESS)
        result = find_opposites(r);
    if (result == CVK_SUCCESS)
        result = lay_springs(r, out);
    if (result == CVK_SUCCESS)
        result = link_triangle_springs(r, out);
    if (result == CVK_SUCCESS)
        result = fill_output(r, out);
    return result;
}

/* The same reader up to the triangles (welded, checked, no springs), then the transform. */
cvk_result cvk_topology_mesh_triangles(const char* path, const cvk_transform* transform,
                                       const char* key, cvk_mesh_triangles* out, cvk_error* error)
{
    memset(out, 0, sizeof *out);
    cvk_mesh_reader r = {.path = path, .error = error};
    snprintf(r.key, sizeof r.key, "%s", key);
    cvk_result result = cvk_mesh_open(&r);
    if (result == CVK_SUCCESS)
        result = cvk_mesh_weld(&r);
    if (result == CVK_SUCCESS)
        result = cvk_mesh_gather_faces(&r);
    if (result == CVK_SUCCESS)
        result = split_faces(&r);
    if (result == CVK_SUCCESS)
        result = find_edges(&r);
    if (result == CVK_SUCCESS)
        result = find_opposites(&r);
    if (result == CVK_SUCCESS) {
        out->xyz = malloc(3 * (size_t)r.vertex_count * sizeof *out->xyz);
        result = out->xyz ? CVK_SUCCESS : cvk_mesh_out_of_memory(&r, "the vertices");
    }
    if (result == CVK_SUCCESS) {
        out->vertex_count = r.vertex_count;
        transform_positions(transform, r.position, out->xyz, r.vertex_count);
        result = check_extent(&r, out->xyz);
    }
    if (result == CVK_SUCCESS) {
        out->triangle_count = r.triangle_count;
        out->triangles = r.triangles;
        r.triangles = NULL;
    }
    cvk_mesh_reader_free(&r);
    if (result != CVK_SUCCESS)
        cvk_mesh_triangles_free(out);
    return result;
}

void cvk_mesh_triangles_free(cvk_mesh_triangles* mesh)
{
    free(mesh->xyz);
    free(mesh->triangles);
    memset(mesh, 0, sizeof *mesh);
}

cvk_result cvk_topology_mesh(const cvk_cloth_desc* cloth, uint32_t index, cvk_topology* out,
                             cvk_error* error)
{
    memset(out, 0, sizeof *out);
    cvk_mesh_reader r = {.cloth = cloth, .path = cloth->mesh, .error = error};
    cvk_key_path(r.key, "cloths.%u.mesh", index);
    cvk_result result = read_mesh(&r, out);
    cvk_mesh_reader_free(&r);
    if (result != CVK_SUCCESS)
        cvk_topology_destroy(out);
    return result;
}
