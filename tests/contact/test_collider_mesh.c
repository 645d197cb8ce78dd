/* Collider meshes for the renderer (lib/contact/collider_mesh.c): counts, closed and consistently
   wound surfaces, unit normals pointing out of the solid, and the enclosed volume of the
   sphere, box and capsule within 2 % of the analytic value. Host only. */
#include "contact/collider_mesh.h"
#include "harness.h"
#include "scene/motion.h"

#define PI 3.14159265358979323846

static const float focus[3] = {0.3f, 2.0f, -0.4f};

static void sub(const float* a, const float* b, double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = (double)a[k] - (double)b[k];
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static cvk_collider_mesh make(const cvk_collider_desc* c, const cvk_sdf* sdf)
{
    cvk_error err;
    cvk_collider_mesh m;
    REQUIRE_OK(cvk_collider_mesh_make(c, sdf, focus, 10.0f, 0.0, &m, &err), err);
    return m;
}

/* Every normal is unit and every face's winding agrees with its vertices' normals. */
static void check_normals(const char* what, const cvk_collider_mesh* m)
{
    double worst_len = 0.0;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const float* n = &m->normals[3 * v];
        worst_len = fmax(worst_len, fabs(sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1.0));
    }
    CHECK(worst_len < 1e-5, "%s: a normal's length is off 1 by %g", what, worst_len);
    uint32_t against = 0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t* i = &m->triangles[3 * t];
        double e1[3], e2[3], f[3], n[3] = {0, 0, 0};
        sub(&m->xyz[3 * i[1]], &m->xyz[3 * i[0]], e1);
        sub(&m->xyz[3 * i[2]], &m->xyz[3 * i[0]], e2);
        cross(e1, e2, f);
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++)
                n[k] += m->normals[3 * i[c] + k];
        against += dot(f, n) <= 0.0;
    }
    CHECK(against == 0, "%s: %u of %u triangles are wound against their normals", what, against,
          m->triangle_count);
}

/* Closed and outward: the area-weighted normals sum to zero (divergence theorem on a
   constant field), relative to the total area; returns the enclosed volume. */
static double closed_volume(const char* what, const cvk_collider_mesh* m)
{
    double sum[3] = {0, 0, 0}, area = 0.0, volume = 0.0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t* i = &m->triangles[3 * t];
        double a[3], b[3], c[3], e1[3], e2[3], f[3], bc[3];
        for (int k = 0; k < 3; k++) {
            a[k] = m->xyz[3 * i[0] + k];
            b[k] = m->xyz[3 * i[1] + k];
            c[k] = m->xyz[3 * i[2] + k];
            e1[k] = b[k] - a[k];
            e2[k] = c[k] - a[k];
        }
        cross(e1, e2, f);
        for (int k = 0; k < 3; k++)
            sum[k] += 0.5 * f[k];
        area += 0.5 * sqrt(dot(f, f));
        cross(b, c, bc);
        volume += dot(a, bc) / 6.0;
    }
    double gap = sqrt(dot(sum, sum)) / area;
    CHECK(gap < 1e-5, "%s: sum of normal · area is %g of the area, not 0", what, gap);
    return volume;
}

static void check_volume(const char* what, double volume, double expected)
{
    double err = fabs(volume / expected - 1.0);
    CHECK(err < 0.02, "%s: encloses %.6g m^3, %.3g %% off the analytic %.6g", what, volume, 100.0 * err,
          expected);
}

/* Each vertex normal points away from `inside(p)`, the nearest point of the solid's core. */
typedef void (*core_fn)(const cvk_collider_desc* c, const float p[3], double out[3]);

static void check_outward(const char* what, const cvk_collider_mesh* m, const cvk_collider_desc* c,
                          core_fn core, double min_cos)
{
    double worst = 1.0;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        double centre[3], d[3], n[3];
        core(c, &m->xyz[3 * v], centre);
        for (int k = 0; k < 3; k++) {
            d[k] = m->xyz[3 * v + k] - centre[k];
            n[k] = m->normals[3 * v + k];
        }
        worst = fmin(worst, dot(d, n) / sqrt(dot(d, d)));
    }
    CHECK(worst > min_cos, "%s: a normal is at cos %g to the way out, below %g", what, worst, min_cos);
}

static void sphere_core(const cvk_collider_desc* c, const float p[3], double out[3])
{
    (void)p;
    for (int k = 0; k < 3; k++)
        out[k] = c->center[k];
}

static void capsule_core(const cvk_collider_desc* c, const float p[3], double out[3])
{
    double ab[3], ap[3];
    sub(c->b, c->a, ab);
    sub(p, c->a, ap);
    double t = fmin(fmax(dot(ap, ab) / dot(ab, ab), 0.0), 1.0);
    for (int k = 0; k < 3; k++)
        out[k] = c->a[k] + t * ab[k];
}

/* Euler: a closed surface of genus 0 welded at its vertices has F = 2V − 4. */
static void check_sphere(void)
{
    cvk_collider_desc c = cvk_default_collider_desc();
    c.type = CVK_COLLIDER_SPHERE;
    c.center[0] = 1.0f, c.center[1] = 0.5f, c.center[2] = -2.0f;
    c.radius = 0.3f;
    cvk_collider_mesh m = make(&c, NULL);
    CHECK(m.vertex_count >= 1000, "sphere: %u vertices, too few to look round", m.vertex_count);
    CHECK(m.triangle_count == 2 * m.vertex_count - 4, "sphere: %u triangles for %u vertices, not 2V - 4",
          m.triangle_count, m.vertex_count);
    check_normals("sphere", &m);
    check_outward("sphere", &m, &c, sphere_core, 0.9999);
    check_volume("sphere", closed_volume("sphere", &m), 4.0 / 3.0 * PI * 0.027);
    cvk_collider_mesh_destroy(&m);
}

static void check_capsule(void)
{
    cvk_collider_desc c = cvk_default_collider_desc();
    c.type = CVK_COLLIDER_CAPSULE;
    float a[3] = {-0.5f, 0.2f, 0.1f}, b[3] = {0.4f, 0.6f, -0.3f};
    memcpy(c.a, a, sizeof a);
    memcpy(c.b, b, sizeof b);
    c.radius = 0.15f;
    cvk_collider_mesh m = make(&c, NULL);
    CHECK(m.triangle_count == 2 * m.vertex_count - 4, "capsule: %u triangles for %u vertices, not 2V - 4",
          m.triangle_count, m.vertex_count);
    check_normals("capsule", &m);
    check_outward("capsule", &m, &c, capsule_core, 0.9999);
    double length = sqrt(0.81 + 0.16 + 0.16), r = 0.15;
    check_volume("capsule", closed_volume("capsule", &m), PI * r * r * length + 4.0 / 3.0 * PI * r * r * r);
    cvk_collider_mesh_destroy(&m);
}

/* Round shapes tessellated by the pixels their radius spans: a multiple of 4 segments from 12
   to 64, the outline within 0.45 pixels of round (sagitta r (1 − cos(π/n))) unless 64, the
   fewest by the estimate r π² / (2 n²); a sphere of 12 segments has 5 rings of 12 and two poles. */
static void check_round_segments(void)
{
    CHECK(cvk_collider_round_segments(0.0) == 64, "unknown size: %u segments, not 64", cvk_collider_round_segments(0.0));
    CHECK(cvk_collider_round_segments(NAN) == 64, "NaN size: %u segments, not 64", cvk_collider_round_segments(NAN));
    CHECK(cvk_collider_round_segments(1e9) == 64, "huge: %u segments, not 64", cvk_collider_round_segments(1e9));
    CHECK(cvk_collider_round_segments(360.0) == 64, "360 pixels: %u segments, not 64",
          cvk_collider_round_segments(360.0));
    CHECK(cvk_collider_round_segments(1.0) == 12, "1 pixel: %u segments, not 12", cvk_collider_round_segments(1.0));
    CHECK(cvk_collider_round_segments(100.0) == 36, "100 pixels: %u segments, not 36",
          cvk_collider_round_segments(100.0));
    uint32_t bad = 0;
    for (double r = 0.5; r < 2000.0; r *= 1.03) {
        uint32_t n = cvk_collider_round_segments(r);
        bool shape = n % 4 == 0 && n >= 12 && n <= 64;
        bool round_enough = n == 64 || r * (1.0 - cos(PI / n)) <= 0.45;
        bool fewest = n == 12 || r * PI * PI / (2.0 * (n - 4.0) * (n - 4.0)) > 0.45;
        bad += !(shape && round_enough && fewest);
    }
    CHECK(bad == 0, "%u radii get segments off the rule", bad);
    cvk_collider_desc c = cvk_default_collider_desc();
    c.type = CVK_COLLIDER_SPHERE;
    c.radius = 0.01f;
    cvk_error err;
    cvk_collider_mesh m;
    REQUIRE_OK(cvk_collider_mesh_make(&c, NULL, focus, 10.0f, 4.0, &m, &err), err);
    CHECK(m.vertex_count == 62 && m.triangle_count == 120, "sphere of 4 pixels: %u vertices, %u triangles, not 62, 120",
          m.vertex_count, m.triangle_count);
    check_normals("small sphere", &m);
    cvk_collider_mesh_destroy(&m);
}

/* A rotated box: 6 faces of 4 vertices with the face's own normal, the rotated axes. */
static void check_box(void)
{
    cvk_collider_desc c = cvk_default_collider_desc();
    c.type = CVK_COLLIDER_BOX;
    c.center[0] = 0.2f, c.center[1] = 1.0f, c.center[2] = 0.0f;
    c.half_extents[0] = 0.5f, c.half_extents[1] = 0.1f, c.half_extents[2] = 0.3f;
    double half = 0.5 * 0.6; /* 36.9° about (1, 2, 2) / 3, unnormalised on purpose */
    c.rotation[0] = (float)(2.0 * cos(half));
    for (int k = 0; k < 3; k++)
        c.rotation[k + 1] = (float)(2.0 * sin(half) * (k == 0 ? 1.0 : 2.0) / 3.0);
    cvk_collider_mesh m = make(&c, NULL);
    CHECK(m.vertex_count == 24 && m.triangle_count == 12, "box: %u vertices and %u triangles, not 24 and 12",
          m.vertex_count, m.triangle_count);
    check_normals("box", &m);
    check_outward("box", &m, &c, sphere_core, 0.1);
    check_volume("box", closed_volume("box", &m), 8.0 * 0.5 * 0.1 * 0.3);
    /* Each face's normal is a rotated axis, and its four vertices lie half an extent along it. */
    float q[4];
    cvk_quat_normalize(c.rotation, q);
    double worst = 0.0;
    for (uint32_t v = 0; v < m.vertex_count; v++) {
        float local[3], n[3], back[3];
        const float* p = &m.xyz[3 * v];
        float d[3] = {p[0] - c.center[0], p[1] - c.center[1], p[2] - c.center[2]};
        float qi[4] = {q[0], -q[1], -q[2], -q[3]};
        cvk_quat_rotate(qi, d, local);
        cvk_quat_rotate(qi, &m.normals[3 * v], n);
        for (int k = 0; k < 3; k++) {
            back[k] = n[k];
            if (fabsf(n[k]) > 0.5f)
                worst = fmax(worst, fabs(fabs(local[k]) - c.half_extents[k]));
        }
        worst = fmax(worst, fabs(fabs(back[0]) + fabs(back[1]) + fabs(back[2]) - 1.0));
    }
    CHECK(worst < 1e-5, "box: a face is %g off its rotated axis", worst);
    cvk_collider_mesh_destroy(&m);
}

/* The funnel: open at both ends, radius e^(y/a) below the apex, normals away from the axis. */
static void check_funnel(void)
{
    cvk_collider_desc c = cvk_default_collider_desc();
    c.type = CVK_COLLIDER_FUNNEL;
    c.apex[0] = 0.5f, c.apex[1] = 2.0f, c.apex[2] = 0.0f;
    c.funnel_a = 0.6f;
    c.height = 1.2f;
    cvk_collider_mesh m = make(&c, NULL);
    check_normals("funnel", &m);
    double worst_radius = 0.0, worst_out = 1.0, lowest = 1e9, highest = -1e9;
    for (uint32_t v = 0; v < m.vertex_count; v++) {
        const float* p = &m.xyz[3 * v];
        const float* n = &m.normals[3 * v];
        double x = p[0] - c.apex[0], y = p[1] - c.apex[1], z = p[2] - c.apex[2];
        double r = sqrt(x * x + z * z);
        worst_radius = fmax(worst_radius, fabs(r - exp(y / c.funnel_a)));
        worst_out = fmin(worst_out, (x * n[0] + z * n[2]) / r);
        lowest = fmin(lowest, y);
        highest = fmax(highest, y);
    }
    CHECK(worst_radius < 1e-5, "funnel: a vertex is %g m off the radius e^(y/a)", worst_radius);
    CHECK(worst_out > 0.0, "funnel: a normal points towards the axis (cos %g)", worst_out);
    CHECK(fabs(lowest + 1.2) < 1e-5 && fabs(highest) < 1e-5,
          "funnel: spans %g .. %g m from the apex, not -1.2 .. 0", lowest, highest);
    cvk_collider_mesh_destroy(&m);
}

/* A plane: a square of side plane_extent centred on the point nearest the focus. */
static void check_plane(void)
{
    cvk_collider_desc c = cvk_default_collider_desc();
    c.type = CVK_COLLIDER_PLANE;
    c.point[0] = 0.0f, c.point[1] = 0.5f, c.point[2] = 0.0f;
    c.normal[0] = 0.0f, c.normal[1] = 2.0f, c.normal[2] = 2.0f;
    cvk_collider_mesh m = make(&c, NULL);
    CHECK(m.vertex_count == 4 && m.triangle_count == 2, "plane: %u vertices and %u triangles, not 4 and 2",
          m.vertex_count, m.triangle_count);
    check_normals("plane", &m);
    double centre[3] = {0, 0, 0}, worst = 0.0, s = sqrt(0.5);
    for (uint32_t v = 0; v < m.vertex_count; v++) {
        const float* p = &m.xyz[3 * v];
        worst = fmax(worst, fabs((p[1] - 0.5) * s + p[2] * s)); /* on the plane */
        worst = fmax(worst, fabs(m.normals[3 * v + 1] - s) + fabs(m.normals[3 * v + 2] - s));
        for (int k = 0; k < 3; k++)
            centre[k] += 0.25 * p[k];
    }
    CHECK(worst < 1e-5, "plane: a vertex is %g off the plane or its normal", worst);
    /* The focus minus its height above the plane along the normal. */
    double above = ((focus[1] - 0.5) * s + focus[2] * s);
    double expected[3] = {focus[0], focus[1] - above * s, focus[2] - above * s};
    double gap = fabs(centre[0] - expected[0]) + fabs(centre[1] - expected[1]) + fabs(centre[2] - expected[2]);
    CHECK(gap < 1e-5, "plane: centred %g m from the point nearest the focus", gap);
    double side[3];
    sub(&m.xyz[3], &m.xyz[0], side);
    CHECK(fabs(sqrt(dot(side, side)) - 10.0) < 1e-4, "plane: side %g m, not the extent 10", sqrt(dot(side, side)));
    cvk_collider_mesh_destroy(&m);
}

/* A mesh collider: a cube's 12 triangles keep their face normals (its edges are sharp), and
   a finely tessellated sphere's normals come out smooth (close to radial). */
static void check_mesh(void)
{
    static float cube[8][3];
    for (int i = 0; i < 8; i++)
        for (int k = 0; k < 3; k++)
            cube[i][k] = (i >> k) & 1 ? 1.0f : -1.0f;
    /* Counter-clockwise from outside: per face, two triangles. */
    static uint32_t tris[12][3] = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                                   {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
    cvk_sdf sdf = {.xyz = &cube[0][0], .vertex_count = 8, .triangles = &tris[0][0], .triangle_count = 12};
    cvk_collider_desc c = cvk_default_collider_desc();
    c.type = CVK_COLLIDER_MESH;
    cvk_collider_mesh m = make(&c, &sdf);
    CHECK(m.vertex_count == 36 && m.triangle_count == 12,
          "mesh (cube): %u vertices and %u triangles, not 36 (one per corner) and 12", m.vertex_count,
          m.triangle_count);
    check_normals("mesh (cube)", &m);
    check_volume("mesh (cube)", closed_volume("mesh (cube)", &m), 8.0);
    double worst = 0.0;
    for (uint32_t v = 0; v < m.vertex_count; v++) {
        const float* n = &m.normals[3 * v];
        double largest = fmax(fabs(n[0]), fmax(fabs(n[1]), fabs(n[2])));
        worst = fmax(worst, 1.0 - largest);
    }
    CHECK(worst < 1e-6, "mesh (cube): a corner's normal is %g off its face's axis (sharp edges blended)",
          worst);
    cvk_collider_mesh_destroy(&m);

    cvk_collider_desc s = cvk_default_collider_desc();
    s.type = CVK_COLLIDER_SPHERE;
    s.radius = 1.0f;
    cvk_collider_mesh round = make(&s, NULL);
    cvk_sdf round_sdf = {.xyz = round.xyz, .vertex_count = round.vertex_count, .triangles = round.triangles,
                         .triangle_count = round.triangle_count};
    m = make(&c, &round_sdf);
    check_normals("mesh (sphere)", &m);
    check_outward("mesh (sphere)", &m, &s, sphere_core, 0.999);
    cvk_collider_mesh_destroy(&m);
    cvk_collider_mesh_destroy(&round);

    cvk_error err;
    cvk_result r = cvk_collider_mesh_make(&c, NULL, focus, 1.0f, 0.0, &m, &err);
    const char* why = "cvk_collider_mesh_make needs the distance field of a mesh collider";
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT && strcmp(err.message, why) == 0,
          "mesh without its field: %s (%s), expected CVK_ERROR_INVALID_ARGUMENT (%s)",
          cvk_result_name(r), err.message, why);
}

int main(void)
{
    check_sphere();
    check_capsule();
    check_round_segments();
    check_box();
    check_funnel();
    check_plane();
    check_mesh();
    return harness_finish(NULL);
}
