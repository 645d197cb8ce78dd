/* Mesh colliders as signed distance fields (lib/contact/sdf.c): an icosphere and a box against their
   analytic distances, the sign inside and far outside, sampling beyond the grid, the chair
   asset, and the messages for open and missing meshes. Meshes are written into a temporary
   folder. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "contact/sdf.h"

static const cvk_transform identity = {{1, 1, 1}, {1, 0, 0, 0}, {0, 0, 0}};

static char folder[64];

static void path_in(char out[256], const char* name)
{
    snprintf(out, 256, "%s/%s", folder, name);
}

static void write_obj(const char* path, const float* xyz, int vertices, const int* faces,
                      int corners_per_face, int face_count)
{
    FILE* f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "FAILED: cannot write %s\n", path);
        exit(1);
    }
    for (int v = 0; v < vertices; v++)
        fprintf(f, "v %.9g %.9g %.9g\n", xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
    for (int t = 0; t < face_count; t++) {
        fputc('f', f);
        for (int k = 0; k < corners_per_face; k++)
            fprintf(f, " %d", faces[corners_per_face * t + k] + 1);
        fputc('\n', f);
    }
    fclose(f);
}

/* ---- an icosphere of radius 1: the icosahedron, each triangle split in four `levels` times,
   new vertices pushed onto the sphere. Counter-clockwise from outside. ---- */

#define ICO_MAX_VERTICES 2562
#define ICO_MAX_TRIANGLES 5120

typedef struct icosphere {
    float xyz[3 * ICO_MAX_VERTICES];
    int tri[3 * ICO_MAX_TRIANGLES];
    int vertices, triangles;
} icosphere;

static int ico_vertex(icosphere* s, double x, double y, double z)
{
    double n = sqrt(x * x + y * y + z * z);
    for (int v = 0; v < s->vertices; v++)
        if (fabs(s->xyz[3 * v] - x / n) < 1e-6 && fabs(s->xyz[3 * v + 1] - y / n) < 1e-6 &&
            fabs(s->xyz[3 * v + 2] - z / n) < 1e-6)
            return v;
    s->xyz[3 * s->vertices] = (float)(x / n);
    s->xyz[3 * s->vertices + 1] = (float)(y / n);
    s->xyz[3 * s->vertices + 2] = (float)(z / n);
    return s->vertices++;
}

static int ico_mid(icosphere* s, int a, int b)
{
    const float* p = &s->xyz[3 * a];
    const float* q = &s->xyz[3 * b];
    return ico_vertex(s, p[0] + q[0], p[1] + q[1], p[2] + q[2]);
}

static void make_icosphere(icosphere* s, int levels)
{
    const double t = (1.0 + sqrt(5.0)) / 2.0;
    const double v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                             {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    static const int f[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                 {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                 {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                 {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    s->vertices = s->triangles = 0;
    for (int k = 0; k < 12; k++)
        ico_vertex(s, v[k][0], v[k][1], v[k][2]);
    for (int k = 0; k < 20; k++, s->triangles++)
        memcpy(&s->tri[3 * k], f[k], sizeof f[k]);
    for (int level = 0; level < levels; level++) {
        int old = s->triangles;
        static int next[3 * ICO_MAX_TRIANGLES];
        for (int k = 0; k < old; k++) {
            int a = s->tri[3 * k], b = s->tri[3 * k + 1], c = s->tri[3 * k + 2];
            int ab = ico_mid(s, a, b), bc = ico_mid(s, b, c), ca = ico_mid(s, c, a);
            const int four[12] = {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca};
            memcpy(&next[12 * k], four, sizeof four);
        }
        s->triangles = 4 * old;
        memcpy(s->tri, next, 3 * (size_t)s->triangles * sizeof *next);
    }
}

/* ---- the sphere ---- */

/* Radius 0.5 m centred on (0.1, 0.2, -0.3) by the transform, 1280 triangles. The inscribed
   polyhedron lies up to 2 mm inside the sphere (its faces' sagitta), 0.04 voxels here. */
#define SPHERE_R 0.5
static const double sphere_c[3] = {0.1, 0.2, -0.3};

/* At the grid's samples the field is exact for the mesh, which lies up to 0.04 voxels inside
   the sphere. Between samples trilinear interpolation of a field that bends (the distance to
   a sphere, curvature 1 / r) adds up to voxel² / (8 r) at distance r from the centre, plus
   where the field has a crease: held to 0.15 voxels at r ≥ 0.2 m. */
#define SPHERE_TOLERANCE_VOXELS 0.1
#define SPHERE_BETWEEN_VOXELS 0.15

static double sphere_distance(const float p[3])
{
    double d[3] = {p[0] - sphere_c[0], p[1] - sphere_c[1], p[2] - sphere_c[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - SPHERE_R;
}

static void grid_point(const cvk_sdf* sdf, uint32_t i, uint32_t j, uint32_t k, float p[3])
{
    p[0] = sdf->origin[0] + sdf->voxel * (float)i;
    p[1] = sdf->origin[1] + sdf->voxel * (float)j;
    p[2] = sdf->origin[2] + sdf->voxel * (float)k;
}

static void test_sphere(void)
{
    static icosphere s;
    make_icosphere(&s, 3);
    char path[256];
    path_in(path, "sphere.obj");
    write_obj(path, s.xyz, s.vertices, s.tri, 3, s.triangles);
    cvk_transform t = identity;
    for (int k = 0; k < 3; k++) {
        t.scale[k] = (float)SPHERE_R;
        t.translation[k] = (float)sphere_c[k];
    }
    cvk_sdf sdf;
    cvk_error err;
    REQUIRE_OK(cvk_sdf_from_mesh_file(path, &t, 32, 0.0f, "colliders.0.file", &sdf, &err), err);
    CHECK(sdf.vertex_count == 642 && sdf.triangle_count == 1280, "%u vertices, %u triangles; "
          "expected 642 and 1280", sdf.vertex_count, sdf.triangle_count);
    /* The diagonal of the sphere's box is 2 √3 R; 32 voxels along it. */
    double voxel = 2.0 * sqrt(3.0) * SPHERE_R / 32.0;
    CHECK(fabs(sdf.voxel - voxel) < 1e-6, "voxel %.6f m, expected %.6f m", sdf.voxel, voxel);
    double worst_node = 0.0, worst_between = 0.0;
    for (uint32_t k = 0; k < sdf.dims[2]; k++)
        for (uint32_t j = 0; j < sdf.dims[1]; j++)
            for (uint32_t i = 0; i < sdf.dims[0]; i++) {
                float p[3];
                grid_point(&sdf, i, j, k, p);
                float v = sdf.values[i + (size_t)sdf.dims[0] * (j + (size_t)sdf.dims[1] * k)];
                worst_node = fmax(worst_node, fabs(v - sphere_distance(p)) / sdf.voxel);
                /* Between nodes: shifted by a fraction of a voxel on each axis. */
                const float q[3] = {p[0] + 0.37f * sdf.voxel, p[1] + 0.61f * sdf.voxel,
                                    p[2] + 0.23f * sdf.voxel};
                if (sphere_distance(q) + SPHERE_R >= 0.2 && i + 1 < sdf.dims[0] &&
                    j + 1 < sdf.dims[1] && k + 1 < sdf.dims[2])
                    worst_between = fmax(worst_between,
                                         fabs(cvk_sdf_sample(&sdf, q) - sphere_distance(q)) / sdf.voxel);
            }
    CHECK(worst_node <= SPHERE_TOLERANCE_VOXELS, "the sphere's field is %.3f voxels off at a "
          "grid sample (tolerance %.2f)", worst_node, SPHERE_TOLERANCE_VOXELS);
    CHECK(worst_between <= SPHERE_BETWEEN_VOXELS, "the sphere's field is %.3f voxels off "
          "between samples (tolerance %.2f)", worst_between, SPHERE_BETWEEN_VOXELS);
    printf("sphere: worst error %.3f voxels at samples, %.3f between\n", worst_node, worst_between);

    /* The sign: the centre is half a radius deep (within a voxel: the field is a cone's tip
       there, which trilinear interpolation rounds off); 10 m away along +x the bound beyond the grid
       is exact (the nearest point of the grid's box lies on the same ray). */
    const float centre[3] = {(float)sphere_c[0], (float)sphere_c[1], (float)sphere_c[2]};
    float d = cvk_sdf_sample(&sdf, centre);
    CHECK(d < 0.0f && fabs(d + SPHERE_R) < sdf.voxel, "at the centre %.4f m, expected "
          "%.4f m", d, -SPHERE_R);
    const float far[3] = {(float)sphere_c[0] + 10.0f, (float)sphere_c[1], (float)sphere_c[2]};
    d = cvk_sdf_sample(&sdf, far);
    CHECK(fabs(d - sphere_distance(far)) < SPHERE_TOLERANCE_VOXELS * sdf.voxel,
          "10 m out along +x %.4f m, expected %.4f m", d, sphere_distance(far));
    /* Off the axes: at least the distance to the grid's box (never inside), and an upper bound
       of the true distance. */
    const float corner[3] = {-7.0f, 5.0f, 9.0f};
    d = cvk_sdf_sample(&sdf, corner);
    CHECK(d >= sphere_distance(corner) - SPHERE_TOLERANCE_VOXELS * sdf.voxel && d < 1.5 * sphere_distance(corner),
          "at (-7, 5, 9) %.4f m, true distance %.4f m", d, sphere_distance(corner));
    const float nan_point[3] = {NAN, 0.0f, 0.0f};
    CHECK(isnan(cvk_sdf_sample(&sdf, nan_point)), "a NaN point gave a number");
    cvk_sdf_destroy(&sdf);
}

/* ---- boxes ---- */

/* The cube [-1, 1]³: corner k has x = +1 when bit 0 is set, y bit 1, z bit 2; six quads,
   counter-clockwise from outside. */
static const float cube_xyz[24] = {-1, -1, -1, 1, -1, -1, -1, 1, -1, 1, 1, -1,
                                   -1, -1, 1,  1, -1, 1,  -1, 1, 1,  1, 1, 1};
static const int cube_quads[24] = {0, 4, 6, 2, 1, 3, 7, 5, 0, 1, 5, 4,
                                   2, 6, 7, 3, 0, 2, 3, 1, 4, 5, 7, 6};

/* Half extents 0.3 × 0.2 × 0.1 m by the transform. */
static const double box_h[3] = {0.3, 0.2, 0.1};

static double box_distance(const float p[3])
{
    double q[3], out2 = 0.0, in = -INFINITY;
    for (int k = 0; k < 3; k++) {
        q[k] = fabs(p[k]) - box_h[k];
        out2 += q[k] > 0.0 ? q[k] * q[k] : 0.0;
        in = fmax(in, q[k]);
    }
    return in > 0.0 ? sqrt(out2) : in;
}

/* A box's faces are exact in the mesh and its distances are computed exactly: what remains is
   float rounding of the vertices and the stored values. */
#define BOX_TOLERANCE_VOXELS 0.001

static void test_box(void)
{
    char path[256];
    path_in(path, "box.obj");
    write_obj(path, cube_xyz, 8, cube_quads, 4, 6);
    cvk_transform t = identity;
    for (int k = 0; k < 3; k++)
        t.scale[k] = (float)box_h[k];
    cvk_sdf sdf;
    cvk_error err;
    REQUIRE_OK(cvk_sdf_from_mesh_file(path, &t, 32, 0.0f, "colliders.1.file", &sdf, &err), err);
    CHECK(sdf.vertex_count == 8 && sdf.triangle_count == 12, "%u vertices, %u triangles; "
          "expected 8 and 12", sdf.vertex_count, sdf.triangle_count);
    double worst = 0.0;
    float at[3] = {0, 0, 0};
    uint32_t wrong_sign = 0;
    for (uint32_t k = 0; k < sdf.dims[2]; k++)
        for (uint32_t j = 0; j < sdf.dims[1]; j++)
            for (uint32_t i = 0; i < sdf.dims[0]; i++) {
                float p[3];
                grid_point(&sdf, i, j, k, p);
                float v = sdf.values[i + (size_t)sdf.dims[0] * (j + (size_t)sdf.dims[1] * k)];
                double e = fabs(v - box_distance(p)) / sdf.voxel;
                if (e > worst) {
                    worst = e;
                    memcpy(at, p, sizeof at);
                }
                wrong_sign += fabs(box_distance(p)) > 0.1 * sdf.voxel &&
                              (v < 0.0f) != (box_distance(p) < 0.0);
            }
    CHECK(worst <= BOX_TOLERANCE_VOXELS, "the box's field is %.3f voxels off at (%.3f, %.3f, "
          "%.3f) (tolerance %.2f)", worst, at[0], at[1], at[2], BOX_TOLERANCE_VOXELS);
    CHECK(wrong_sign == 0, "%u samples have the wrong sign", wrong_sign);
    printf("box: worst error %.3f voxels at the samples\n", worst);
    /* Inside where the +z face is nearest to every surrounding sample (the field is linear
       there, so interpolation is exact), and far below. */
    const float inside[3] = {0.05f, 0.02f, 0.03f}, far[3] = {0, -20, 0};
    float d = cvk_sdf_sample(&sdf, inside);
    CHECK(fabs(d + 0.07) < BOX_TOLERANCE_VOXELS * sdf.voxel, "at (0.05, 0.02, 0.03) %.5f m, "
          "expected -0.07 m", d);
    d = cvk_sdf_sample(&sdf, far);
    CHECK(fabs(d - 19.8) < BOX_TOLERANCE_VOXELS * sdf.voxel, "20 m below %.4f m, expected "
          "19.8 m", d);
    cvk_sdf_destroy(&sdf);
}

/* The cube without its +z face: the first edge of the triangles with one triangle is (4, 6),
   in face 0's second triangle (quads split along v1–v3: (0, 4, 2), (4, 6, 2)). */
static void test_open(void)
{
    char path[256];
    path_in(path, "open.obj");
    write_obj(path, cube_xyz, 8, cube_quads, 4, 5);
    cvk_sdf sdf;
    cvk_error err = {0};
    cvk_result r = cvk_sdf_from_mesh_file(path, &identity, 32, 0.0f, "colliders.2.file", &sdf, &err);
    char expected[512];
    snprintf(expected, sizeof expected, "colliders.2.file: %s: the mesh is not closed (edge "
             "between vertices 4 and 6 has 1 triangle); a mesh collider needs a closed surface",
             path);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT, "an open mesh gave %s", cvk_result_name(r));
    CHECK(strcmp(err.message, expected) == 0, "an open mesh said \"%s\", expected \"%s\"",
          err.message, expected);
    CHECK(!sdf.values && !sdf.xyz && !sdf.triangles, "a failure left memory in the field");
}

/* The cube with its +z face turned inside out: the first edge both of whose triangles run the
   same way is (4, 6), in face 0's second triangle and the turned face. */
static void test_inconsistent(void)
{
    char path[256];
    path_in(path, "turned.obj");
    int quads[24];
    memcpy(quads, cube_quads, sizeof quads);
    for (int k = 0; k < 4; k++)
        quads[20 + k] = cube_quads[23 - k];
    write_obj(path, cube_xyz, 8, quads, 4, 6);
    cvk_sdf sdf;
    cvk_error err = {0};
    cvk_result r = cvk_sdf_from_mesh_file(path, &identity, 32, 0.0f, "colliders.4.file", &sdf, &err);
    char expected[512];
    snprintf(expected, sizeof expected, "colliders.4.file: %s: the mesh is not wound "
             "consistently (both triangles on the edge between vertices 4 and 6 run along it the "
             "same way); a mesh collider needs its triangles counter-clockwise from outside", path);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT, "a mesh wound both ways gave %s", cvk_result_name(r));
    CHECK(strcmp(err.message, expected) == 0, "a mesh wound both ways said \"%s\", expected "
          "\"%s\"", err.message, expected);
}

/* The whole cube turned inside out is one orientation throughout: still solid inside. */
static void test_inside_out(void)
{
    char path[256];
    path_in(path, "inside-out.obj");
    int quads[24];
    for (int f = 0; f < 6; f++)
        for (int k = 0; k < 4; k++)
            quads[4 * f + k] = cube_quads[4 * f + 3 - k];
    write_obj(path, cube_xyz, 8, quads, 4, 6);
    cvk_sdf sdf;
    cvk_error err;
    REQUIRE_OK(cvk_sdf_from_mesh_file(path, &identity, 32, 0.0f, "colliders.5.file", &sdf, &err),
               err);
    const float inside[3] = {0.1f, 0.2f, 0.3f}, outside[3] = {1.5f, 0.0f, 0.0f};
    float a = cvk_sdf_sample(&sdf, inside), b = cvk_sdf_sample(&sdf, outside);
    CHECK(fabsf(a + 0.7f) < 1e-5f && fabsf(b - 0.5f) < 1e-5f, "an inside-out cube gave %.5f m "
          "inside (expected -0.7) and %.5f m outside (expected 0.5)", a, b);
    cvk_sdf_destroy(&sdf);
}

/* Two cubes in one file, 1 m apart: each region of the grid gets its sign (the centres deep
   inside, the gap between them outside). */
static void test_two_parts(void)
{
    char path[256];
    path_in(path, "two.obj");
    float xyz[48];
    int quads[48];
    for (int v = 0; v < 8; v++)
        for (int k = 0; k < 3; k++) {
            xyz[3 * v + k] = 0.25f * cube_xyz[3 * v + k];
            xyz[24 + 3 * v + k] = 0.25f * cube_xyz[3 * v + k] + (k == 0 ? 1.5f : 0.0f);
        }
    for (int i = 0; i < 24; i++) {
        quads[i] = cube_quads[i];
        quads[24 + i] = cube_quads[i] + 8;
    }
    write_obj(path, xyz, 16, quads, 4, 12);
    cvk_sdf sdf;
    cvk_error err;
    REQUIRE_OK(cvk_sdf_from_mesh_file(path, &identity, 32, 0.0f, "colliders.8.file", &sdf, &err),
               err);
    const float a[3] = {0.05f, 0.0f, 0.0f}, b[3] = {1.45f, 0.0f, 0.0f}, gap[3] = {0.75f, 0.0f, 0.0f};
    float da = cvk_sdf_sample(&sdf, a), db = cvk_sdf_sample(&sdf, b), dg = cvk_sdf_sample(&sdf, gap);
    /* Within half a voxel: each point lies where the field has a crease (equally far from two
       faces), which interpolation rounds off. */
    float tolerance = 0.5f * sdf.voxel;
    CHECK(fabsf(da + 0.2f) < tolerance && fabsf(db + 0.2f) < tolerance &&
          fabsf(dg - 0.5f) < tolerance, "two cubes: %.5f m and %.5f m inside (expected -0.2), "
          "%.5f m between (expected 0.5), tolerance %.4f m", da, db, dg, tolerance);
    cvk_sdf_destroy(&sdf);
}

static void test_missing(void)
{
    char path[256];
    path_in(path, "missing.obj");
    cvk_sdf sdf;
    cvk_error err = {0};
    cvk_result r = cvk_sdf_from_mesh_file(path, &identity, 32, 0.0f, "colliders.3.file", &sdf, &err);
    char expected[512];
    snprintf(expected, sizeof expected, "colliders.3.file: cannot read %s: No such file or "
             "directory", path);
    CHECK(r == CVK_ERROR_IO, "a missing file gave %s", cvk_result_name(r));
    CHECK(strcmp(err.message, expected) == 0, "a missing file said \"%s\", expected \"%s\"",
          err.message, expected);
    CHECK(!sdf.values && !sdf.xyz && !sdf.triangles, "a failure left memory in the field");
}

/* A grid of one voxel along the diagonal is refused before the file is read. */
static void test_resolution(void)
{
    cvk_sdf sdf;
    cvk_error err = {0};
    cvk_result r = cvk_sdf_from_mesh_file("chair.obj", &identity, 1, 0.0f, "colliders.7.file",
                                          &sdf, &err);
    const char* expected = "colliders.7.file: signed distance resolution 1; it must be 2 to 512 "
                           "voxels along the mesh's diagonal";
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT && strcmp(err.message, expected) == 0, "resolution 1 "
          "gave %s: \"%s\", expected \"%s\"", cvk_result_name(r), err.message, expected);
}

/* A file Assimp cannot read: its reason after the reader's prefix, as for cloth meshes. */
static void test_garbage(void)
{
    char path[256];
    path_in(path, "garbage.obj");
    FILE* f = fopen(path, "wb");
    if (!f) {
        fprintf(stderr, "FAILED: cannot write %s\n", path);
        exit(1);
    }
    fputs("\x01\x02 this is not a mesh\n", f);
    fclose(f);
    cvk_sdf sdf;
    cvk_error err = {0};
    cvk_result r = cvk_sdf_from_mesh_file(path, &identity, 32, 0.0f, "colliders.6.file", &sdf, &err);
    char prefix[512];
    snprintf(prefix, sizeof prefix, "colliders.6.file: ");
    CHECK(r != CVK_SUCCESS && strncmp(err.message, prefix, strlen(prefix)) == 0 &&
          strstr(err.message, path) != NULL, "a garbage file gave %s: \"%s\"; expected a "
          "failure naming the key and the file", cvk_result_name(r), err.message);
    CHECK(!sdf.values && !sdf.xyz && !sdf.triangles, "a failure left memory in the field");
}

/* ---- the chair asset: the surface of a union of boxes (scripts/make_meshes.py) ---- */

static const float chair_boxes[8][6] = {
    {-0.225f, 0.40f, -0.225f, 0.225f, 0.45f, 0.225f},  /* seat */
    {-0.21f, 0.0f, 0.165f, -0.17f, 0.42f, 0.205f},     /* legs */
    {0.17f, 0.0f, 0.165f, 0.21f, 0.42f, 0.205f},
    {-0.21f, 0.0f, -0.205f, -0.17f, 0.42f, -0.165f},
    {0.17f, 0.0f, -0.205f, 0.21f, 0.42f, -0.165f},
    {-0.21f, 0.43f, -0.215f, -0.17f, 0.9f, -0.175f},   /* back posts */
    {0.17f, 0.43f, -0.215f, 0.21f, 0.9f, -0.175f},
    {-0.185f, 0.6f, -0.21f, 0.185f, 0.88f, -0.185f},   /* back panel */
};

/* Outside the union its distance is the least of the boxes' (exact); inside, that least value
   is negative (the depth itself differs where boxes join). */
static double chair_union_distance(const float p[3])
{
    double best = INFINITY;
    for (int b = 0; b < 8; b++) {
        double q[3], out2 = 0.0, in = -INFINITY;
        for (int k = 0; k < 3; k++) {
            double c = 0.5 * ((double)chair_boxes[b][k] + chair_boxes[b][k + 3]);
            double h = 0.5 * ((double)chair_boxes[b][k + 3] - chair_boxes[b][k]);
            q[k] = fabs(p[k] - c) - h;
            out2 += q[k] > 0.0 ? q[k] * q[k] : 0.0;
            in = fmax(in, q[k]);
        }
        best = fmin(best, in > 0.0 ? sqrt(out2) : in);
    }
    return best;
}

/* Every sample: outside, the exact distance (float rounding: 0.001 voxels); inside, negative.
   The posts and the panel are 1.5 to 2.3 voxels thick at resolution 64, where a sign taken
   from anything but the exact geometry goes wrong. */
static void check_chair_samples(const cvk_sdf* sdf)
{
    double worst = 0.0;
    uint32_t wrong_sign = 0;
    for (uint32_t k = 0; k < sdf->dims[2]; k++)
        for (uint32_t j = 0; j < sdf->dims[1]; j++)
            for (uint32_t i = 0; i < sdf->dims[0]; i++) {
                float p[3];
                grid_point(sdf, i, j, k, p);
                float v = sdf->values[i + (size_t)sdf->dims[0] * (j + (size_t)sdf->dims[1] * k)];
                double m = chair_union_distance(p);
                if (m > 0.0)
                    worst = fmax(worst, fabs(v - m) / sdf->voxel);
                wrong_sign += fabs(m) > 1e-3 * sdf->voxel && (v < 0.0f) != (m < 0.0);
            }
    CHECK(worst <= 1e-3, "the chair's field is %.4f voxels off outside (tolerance 0.001)", worst);
    CHECK(wrong_sign == 0, "%u of the chair's samples have the wrong sign", wrong_sign);
}

static void test_chair(void)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    char path[512];
    snprintf(path, sizeof path, "%s/assets/meshes/chair.obj", root ? root : ".");
    cvk_sdf sdf;
    cvk_error err;
    REQUIRE_OK(cvk_sdf_from_mesh_file(path, &identity, 64, 0.0f, "colliders.0.file", &sdf, &err),
               err);
    CHECK(sdf.vertex_count == 328 && sdf.triangle_count == 656, "the chair has %u vertices and "
          "%u triangles; expected 328 and 656 (328 quads)", sdf.vertex_count, sdf.triangle_count);
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < sdf.vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], sdf.xyz[3 * v + k]);
            hi[k] = fmaxf(hi[k], sdf.xyz[3 * v + k]);
        }
    CHECK(lo[1] == 0.0f && hi[1] == 0.9f && lo[0] == -hi[0] && lo[2] == -hi[2],
          "the chair spans y %g to %g m, x %g to %g, z %g to %g; expected y 0 to 0.9, centred",
          lo[1], hi[1], lo[0], hi[0], lo[2], hi[2]);
    check_chair_samples(&sdf);
    /* Between samples: above the seat, under it, inside it, inside it where a leg reaches up
       into it (the seat's top is 0.01 m away; the leg's top, inside the solid, is not
       surface), and 5 mm beside a back post. */
    const struct { float p[3]; float d; } known[] = {
        {{0.0f, 0.55f, 0.05f}, 0.1f},
        {{0.0f, 0.25f, 0.05f}, 0.15f},
        {{0.0f, 0.44f, 0.05f}, -0.01f},
        {{0.19f, 0.44f, 0.185f}, -0.01f},
        {{0.215f, 0.7f, -0.195f}, 0.005f},
    };
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++) {
        float d = cvk_sdf_sample(&sdf, known[i].p);
        CHECK(fabsf(d - known[i].d) <= 0.1f * sdf.voxel, "the chair's field at (%g, %g, %g) is "
              "%.4f m, expected %.4f m (tolerance 0.1 voxel, %.4f m)", known[i].p[0],
              known[i].p[1], known[i].p[2], d, known[i].d, 0.1f * sdf.voxel);
    }
    cvk_sdf_destroy(&sdf);
}

int main(void)
{
    snprintf(folder, sizeof folder, "/tmp/clothvk-sdf-XXXXXX");
    if (!mkdtemp(folder)) {
        fprintf(stderr, "FAILED: cannot make a temporary folder\n");
        return 1;
    }
    cvk_sdf zero;
    memset(&zero, 0, sizeof zero);
    cvk_sdf_destroy(&zero);
    cvk_sdf_destroy(&zero);
    test_sphere();
    test_box();
    test_open();
    test_inconsistent();
    test_inside_out();
    test_two_parts();
    test_missing();
    test_garbage();
    test_resolution();
    test_chair();
    const char* names[] = {"sphere.obj", "box.obj", "open.obj", "turned.obj", "inside-out.obj",
                           "garbage.obj", "two.obj"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[256];
        path_in(path, names[i]);
        remove(path);
    }
    rmdir(folder);
    return harness_finish(NULL);
}
