/* Triangles of each collider type at rest, for the renderer (collider_mesh.h). Spheres,
   capsules and the funnel are surfaces of revolution built from a profile; boxes and planes
   have flat faces with their own normals; a mesh collider's triangles get normals split at
   sharp edges, so a chair's flat faces stay flat and its rounded parts stay smooth. */
#include "contact/collider_mesh.h"
#include "core/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/motion.h"

#define PI 3.14159265358979323846

/* Segments around a round shape (rings from pole to pole: half as many): at most 64, which keeps
   the silhouette of a sphere filling a 720-pixel image within half a pixel of round (its
   sagitta is r (1 − cos(π/64)) ≈ 0.0012 r, 0.43 pixels of a 360-pixel radius); fewer for a
   radius that spans fewer pixels (round_segments), at least 12. A multiple of 4, so the rings
   meet at an equator. */
#define ROUND_SEGMENTS 64u
#define ROUND_SEGMENTS_MIN 12u
/* The outline's largest distance from the true one (the sagitta), pixels. */
#define ROUND_SAGITTA_PIXELS 0.45
/* Rings along the funnel's profile, which curves more near its narrow end. */
#define FUNNEL_RINGS 48u
/* A mesh collider's faces meeting at more than this angle keep separate normals. */
#define SHARP_COS 0.7071f /* 45° */

/* ---- a growing mesh ----------------------------------------------------------------------- */

typedef struct builder {
    cvk_collider_mesh* mesh;
    uint32_t vertex_capacity, triangle_capacity;
    uint32_t segments; /* around a surface of revolution */
    bool failed;
} builder;

static void reserve(builder* b, uint32_t vertices, uint32_t triangles)
{
    cvk_collider_mesh* m = b->mesh;
    /* + 1: never a zero-byte request */
    m->xyz = malloc(((size_t)vertices * 3 + 1) * sizeof(float));
    m->normals = malloc(((size_t)vertices * 3 + 1) * sizeof(float));
    m->triangles = malloc(((size_t)triangles * 3 + 1) * sizeof(uint32_t));
    b->failed = !m->xyz || !m->normals || !m->triangles;
    b->vertex_capacity = vertices;
    b->triangle_capacity = triangles;
}

static uint32_t add_vertex(builder* b, const float p[3], const float n[3])
{
    cvk_collider_mesh* m = b->mesh;
    if (b->failed || m->vertex_count >= b->vertex_capacity) {
        b->failed = true;
        return 0;
    }
    uint32_t v = m->vertex_count++;
    memcpy(&m->xyz[3 * (size_t)v], p, 3 * sizeof(float));
    memcpy(&m->normals[3 * (size_t)v], n, 3 * sizeof(float));
    return v;
}

/* Counter-clockwise seen from the side the normals point to. */
static void add_triangle(builder* b, uint32_t i, uint32_t j, uint32_t k)
{
    cvk_collider_mesh* m = b->mesh;
    if (b->failed || m->triangle_count >= b->triangle_capacity) {
        b->failed = true;
        return;
    }
    uint32_t* t = &m->triangles[3 * (size_t)m->triangle_count++];
    t[0] = i;
    t[1] = j;
    t[2] = k;
}


/* u, v completing the unit axis w to a right-handed frame (u × v = w). */
static void perpendicular_frame(const float w[3], float u[3], float v[3])
{
    float other[3] = {1.0f, 0.0f, 0.0f};
    if (fabsf(w[0]) > 0.9f) {
        other[0] = 0.0f;
        other[1] = 1.0f;
    }
    cvk_cross3(other, w, u);
    cvk_normalize3(u, NULL);
    cvk_cross3(w, u, v);
}

/* ---- surfaces of revolution --------------------------------------------------------------- */

/* One point of a profile: distance from the axis and height along it (m), and the normal's
   components away from the axis and along it. Radius 0 is a pole (one vertex). */
typedef struct profile_point {
    float radius, height, normal_out, normal_up;
} profile_point;

typedef struct lathe {
    float origin[3], u[3], v[3], axis[3]; /* right-handed: u × v = axis */
} lathe;

static uint32_t lathe_ring(builder* b, const lathe* l, const profile_point* p)
{
    uint32_t first = b->mesh->vertex_count;
    uint32_t count = p->radius > 0.0f ? b->segments : 1u;
    for (uint32_t s = 0; s < count; s++) {
        double phi = 2.0 * PI * s / b->segments;
        float c = (float)cos(phi), sn = (float)sin(phi);
        float x[3], n[3];
        for (int k = 0; k < 3; k++) {
            float out = c * l->u[k] + sn * l->v[k];
            x[k] = l->origin[k] + p->radius * out + p->height * l->axis[k];
            n[k] = p->normal_out * out + p->normal_up * l->axis[k];
        }
        cvk_normalize3(n, NULL);
        add_vertex(b, x, n);
    }
    return first;
}

/* Joins consecutive profile points (in increasing height) into rings of quads, or fans at a
   pole: outward winding, since the frame is right-handed. */
static void lathe_build(builder* b, const lathe* l, const profile_point* profile, uint32_t count)
{
    uint32_t lower = lathe_ring(b, l, &profile[0]);
    for (uint32_t i = 1; i < count; i++) {
        uint32_t upper = lathe_ring(b, l, &profile[i]);
        bool lower_pole = profile[i - 1].radius <= 0.0f, upper_pole = profile[i].radius <= 0.0f;
        for (uint32_t s = 0; s < b->segments; s++) {
            uint32_t t = (s + 1) % b->segments;
            if (lower_pole) {
                add_triangle(b, lower, upper + t, upper + s);
                continue;
            }
            if (upper_pole) {
                add_triangle(b, lower + s, lower + t, upper);
                continue;
            }
            add_triangle(b, lower + s, lower + t, upper + t);
            add_triangle(b, lower + s, upper + t, upper + s);
        }
        lower = upper;
    }
}

static void lathe_reserve(builder* b, const profile_point* profile, uint32_t count)
{
    uint32_t vertices = 0;
    for (uint32_t i = 0; i < count; i++)
        vertices += profile[i].radius > 0.0f ? b->segments : 1u;
    reserve(b, vertices, 2u * b->segments * (count - 1));
}

/* A sphere (length 0) or a capsule: the lower half-sphere around the origin, the upper one
   `length` further along the axis; the equator appears twice for a capsule (the cylinder). */
static void make_round(builder* b, const lathe* l, float radius, float length)
{
    profile_point profile[ROUND_SEGMENTS / 2 + 2];
    uint32_t rings = b->segments / 2;
    uint32_t count = 0;
    for (uint32_t i = 0; i <= rings; i++) {
        double theta = PI * i / rings - 0.5 * PI; /* latitude, −π/2 .. π/2 */
        float c = (float)cos(theta), s = (float)sin(theta);
        if (i == 0 || i == rings)
            c = 0.0f;
        profile_point p = {radius * c, radius * s, c, s};
        bool equator = 2u * i == rings;
        if (length > 0.0f && equator)
            profile[count++] = p;
        if (2u * i >= rings)
            p.height += length;
        profile[count++] = p;
    }
    lathe_reserve(b, profile, count);
    lathe_build(b, l, profile, count);
}

static void make_sphere(builder* b, const cvk_collider_desc* c)
{
    lathe l = {.axis = {0.0f, 1.0f, 0.0f}};
    memcpy(l.origin, c->center, sizeof l.origin);
    perpendicular_frame(l.axis, l.u, l.v);
    make_round(b, &l, c->radius, 0.0f);
}

static void make_capsule(builder* b, const cvk_collider_desc* c)
{
    float d[3] = {c->b[0] - c->a[0], c->b[1] - c->a[1], c->b[2] - c->a[2]};
    float length = sqrtf(cvk_dot3(d, d));
    lathe l = {.axis = {0.0f, 1.0f, 0.0f}};
    if (length > 0.0f)
        for (int k = 0; k < 3; k++)
            l.axis[k] = d[k] / length;
    memcpy(l.origin, c->a, sizeof l.origin);
    perpendicular_frame(l.axis, l.u, l.v);
    make_round(b, &l, c->radius, length);
}

/* Radius e^(y/a) for −height ≤ y ≤ 0 around +y through the apex (clothvk.h); the normal is the
   gradient of r − e^(y/a), away from the axis. */
static void make_funnel(builder* b, const cvk_collider_desc* c)
{
    lathe l = {.axis = {0.0f, 1.0f, 0.0f}, .u = {0.0f, 0.0f, 1.0f}, .v = {1.0f, 0.0f, 0.0f}};
    memcpy(l.origin, c->apex, sizeof l.origin);
    profile_point profile[FUNNEL_RINGS + 1];
    for (uint32_t i = 0; i <= FUNNEL_RINGS; i++) {
        float y = -c->height + c->height * (float)i / FUNNEL_RINGS;
        float r = expf(y / c->funnel_a);
        profile[i] = (profile_point){r, y, 1.0f, -r / c->funnel_a};
    }
    lathe_reserve(b, profile, FUNNEL_RINGS + 1);
    lathe_build(b, &l, profile, FUNNEL_RINGS + 1);
}

/* ---- flat faces ------------------------------------------------------------------------------ */

/* A square or rectangle: centre, half-sides along u and v, normal u × v (unit). */
static void add_quad(builder* b, const float center[3], const float u[3], const float v[3], const float n[3])
{
    static const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    uint32_t first = b->mesh->vertex_count;
    for (int i = 0; i < 4; i++) {
        float p[3];
        for (int k = 0; k < 3; k++)
            p[k] = center[k] + corners[i][0] * u[k] + corners[i][1] * v[k];
        add_vertex(b, p, n);
    }
    add_triangle(b, first, first + 1, first + 2);
    add_triangle(b, first, first + 2, first + 3);
}

static void make_box(builder* b, const cvk_collider_desc* c)
{
    float q[4];
    cvk_quat_normalize(c->rotation, q);
    reserve(b, 24, 12);
    for (int axis = 0; axis < 3; axis++) {
        int i = (axis + 1) % 3, j = (axis + 2) % 3;
        for (int sign = -1; sign <= 1; sign += 2) {
            /* e_i × e_j = e_axis: swapping u's direction on the negative face flips the normal */
            float n[3] = {0}, u[3] = {0}, v[3] = {0}, offset[3] = {0};
            n[axis] = (float)sign;
            u[i] = (float)sign * c->half_extents[i];
            v[j] = c->half_extents[j];
            offset[axis] = (float)sign * c->half_extents[axis];
            float rn[3], ru[3], rv[3], center[3];
            cvk_quat_rotate(q, n, rn);
            cvk_quat_rotate(q, u, ru);
            cvk_quat_rotate(q, v, rv);
            cvk_quat_rotate(q, offset, center);
            for (int k = 0; k < 3; k++)
                center[k] += c->center[k];
            add_quad(b, center, ru, rv, rn);
        }
    }
}

static void make_plane(builder* b, const cvk_collider_desc* c, const float focus[3], float extent)
{
    float n[3] = {c->normal[0], c->normal[1], c->normal[2]};
    cvk_normalize3(n, NULL);
    float u[3], v[3], center[3];
    perpendicular_frame(n, u, v);
    float d[3] = {focus[0] - c->point[0], focus[1] - c->point[1], focus[2] - c->point[2]};
    float above = cvk_dot3(d, n);
    for (int k = 0; k < 3; k++) {
        center[k] = focus[k] - above * n[k];
        u[k] *= 0.5f * extent;
        v[k] *= 0.5f * extent;
    }
    reserve(b, 4, 2);
    add_quad(b, center, u, v, n);
}

/* ---- a mesh collider's own triangles ------------------------------------------------------- */

/* Faces around each vertex, as offsets into one list (CSR). */
static bool faces_by_vertex(const cvk_sdf* sdf, uint32_t** out_start, uint32_t** out_faces)
{
    uint32_t* start = calloc((size_t)sdf->vertex_count + 1, sizeof *start);
    uint32_t* faces = malloc((size_t)sdf->triangle_count * 3 * sizeof *faces);
    uint32_t* cursor = calloc((size_t)sdf->vertex_count + 1, sizeof *cursor);
    if (!start || !faces || !cursor) {
        free(start);
        free(faces);
        free(cursor);
        return false;
    }
    for (size_t i = 0; i < 3 * (size_t)sdf->triangle_count; i++)
        start[sdf->triangles[i] + 1]++;
    for (uint32_t v = 0; v < sdf->vertex_count; v++)
        start[v + 1] += start[v];
    for (size_t i = 0; i < 3 * (size_t)sdf->triangle_count; i++) {
        uint32_t v = sdf->triangles[i];
        faces[start[v] + cursor[v]++] = (uint32_t)(i / 3);
    }
    free(cursor);
    *out_start = start;
    *out_faces = faces;
    return true;
}

/* Twice the area times the unit normal of triangle t. */
static void face_normal(const cvk_sdf* sdf, uint32_t t, float out[3])
{
    const uint32_t* tri = &sdf->triangles[3 * (size_t)t];
    const float* a = &sdf->xyz[3 * (size_t)tri[0]];
    const float* b = &sdf->xyz[3 * (size_t)tri[1]];
    const float* c = &sdf->xyz[3 * (size_t)tri[2]];
    float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    cvk_cross3(e1, e2, out);
}

/* One vertex per triangle corner; its normal is the area-weighted mean of the faces around
   the vertex that meet this corner's face at less than 45°: smooth across gentle folds, a
   crease at sharp edges. */
static void make_from_sdf(builder* b, const cvk_sdf* sdf, const uint32_t* start, const uint32_t* faces,
                          const float* unit)
{
    for (uint32_t t = 0; t < sdf->triangle_count && !b->failed; t++) {
        const float* own = &unit[3 * (size_t)t];
        uint32_t corner[3];
        for (int c = 0; c < 3; c++) {
            uint32_t v = sdf->triangles[3 * (size_t)t + c];
            float n[3] = {0.0f, 0.0f, 0.0f};
            for (uint32_t f = start[v]; f < start[v + 1]; f++) {
                float w[3];
                face_normal(sdf, faces[f], w);
                if (cvk_dot3(&unit[3 * (size_t)faces[f]], own) < SHARP_COS)
                    continue;
                for (int k = 0; k < 3; k++)
                    n[k] += w[k];
            }
            cvk_normalize3(n, NULL);
            if (cvk_dot3(n, n) == 0.0f)
                memcpy(n, own, sizeof n);
            corner[c] = add_vertex(b, &sdf->xyz[3 * (size_t)v], n);
        }
        add_triangle(b, corner[0], corner[1], corner[2]);
    }
}

static cvk_result make_mesh(builder* b, const cvk_sdf* sdf, cvk_error* error)
{
    if (!sdf || !sdf->xyz || !sdf->triangles)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_collider_mesh_make needs the distance field of a mesh collider");
    if (sdf->triangle_count > UINT32_MAX / 3)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "a mesh collider of %u triangles is more than 32-bit indices can draw",
                        sdf->triangle_count);
    for (size_t i = 0; i < 3 * (size_t)sdf->triangle_count; i++)
        if (sdf->triangles[i] >= sdf->vertex_count)
            return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                            "a mesh collider's triangle %zu names vertex %u of %u", i / 3,
                            sdf->triangles[i], sdf->vertex_count);
    uint32_t *start = NULL, *faces = NULL;
    float* unit = malloc((size_t)sdf->triangle_count * 3 * sizeof *unit + 1);
    if (unit && faces_by_vertex(sdf, &start, &faces)) {
        for (uint32_t t = 0; t < sdf->triangle_count; t++) {
            face_normal(sdf, t, &unit[3 * (size_t)t]);
            cvk_normalize3(&unit[3 * (size_t)t], NULL);
        }
        reserve(b, 3 * sdf->triangle_count, sdf->triangle_count);
        make_from_sdf(b, sdf, start, faces, unit);
    } else {
        b->failed = true;
    }
    free(unit);
    free(start);
    free(faces);
    return CVK_SUCCESS;
}

/* ---- the interface ----------------------------------------------------------------------- */

uint32_t cvk_collider_round_segments(double radius_pixels)
{
    /* sagitta r (1 − cos(π/n)) ≈ r π² / (2 n²) ≤ ROUND_SAGITTA_PIXELS */
    if (!(radius_pixels > 0.0) || radius_pixels > 1e6)
        return ROUND_SEGMENTS;
    double n = PI * sqrt(radius_pixels / (2.0 * ROUND_SAGITTA_PIXELS));
    uint32_t segments = 4u * (uint32_t)ceil(n / 4.0);
    return segments < ROUND_SEGMENTS_MIN ? ROUND_SEGMENTS_MIN : (segments > ROUND_SEGMENTS ? ROUND_SEGMENTS : segments);
}

cvk_result cvk_collider_mesh_make(const cvk_collider_desc* collider, const cvk_sdf* sdf,
                                  const float focus[3], float plane_extent, double radius_pixels,
                                  cvk_collider_mesh* out, cvk_error* error)
{
    if (!collider || !focus || !out)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_collider_mesh_make needs a collider, a focus and an output mesh");
    *out = (cvk_collider_mesh){0};
    bool round = collider->type == CVK_COLLIDER_SPHERE || collider->type == CVK_COLLIDER_CAPSULE;
    builder b = {.mesh = out, .segments = round ? cvk_collider_round_segments(radius_pixels) : ROUND_SEGMENTS};
    cvk_result r = CVK_SUCCESS;
    switch (collider->type) {
    case CVK_COLLIDER_PLANE:
        make_plane(&b, collider, focus, plane_extent);
        break;
    case CVK_COLLIDER_SPHERE:
        make_sphere(&b, collider);
        break;
    case CVK_COLLIDER_BOX:
        make_box(&b, collider);
        break;
    case CVK_COLLIDER_CAPSULE:
        make_capsule(&b, collider);
        break;
    case CVK_COLLIDER_FUNNEL:
        make_funnel(&b, collider);
        break;
    case CVK_COLLIDER_MESH:
        r = make_mesh(&b, sdf, error);
        break;
    default:
        r = cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "collider type %d has no shape to draw",
                     (int)collider->type);
        break;
    }
    if (r == CVK_SUCCESS && b.failed)
        r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for a %s collider's triangles",
                     cvk_collider_type_name(collider->type));
    if (r != CVK_SUCCESS)
        cvk_collider_mesh_destroy(out);
    return r;
}

void cvk_collider_mesh_destroy(cvk_collider_mesh* mesh)
{
    if (!mesh)
        return;
    free(mesh->xyz);
    free(mesh->normals);
    free(mesh->triangles);
    *mesh = (cvk_collider_mesh){0};
}
