/* The grid generator and what cvk_topology_create adds for every generator: counts, triangles
   whose edge springs join their own corners and whose winding faces u_axis × v_axis, masses,
   and pins by grid coordinate, by vertex index and by box, with their exact errors. */
#include "topology/build.h"
#include "harness.h"
#include "topology/metrics.h"
#include "topology/topology.h"

static cvk_cloth_desc grid_cloth(uint32_t w, uint32_t h, bool structural, bool shear, bool bend)
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = w;
    c.grid[1] = h;
    c.size[0] = 1.2f;
    c.size[1] = 0.8f;
    c.stiffness.structural = structural ? 1e4f : 0.0f;
    c.stiffness.shear = shear ? 1e3f : 0.0f;
    c.stiffness.bend = bend ? 1e2f : 0.0f;
    /* Hanging in the xy plane from the origin: u × v = −z. */
    c.origin[0] = c.origin[1] = c.origin[2] = 0.0f;
    c.u_axis[0] = 1.0f, c.u_axis[1] = 0.0f, c.u_axis[2] = 0.0f;
    c.v_axis[0] = 0.0f, c.v_axis[1] = -1.0f, c.v_axis[2] = 0.0f;
    return c;
}

static void cross_sub(const float* o, const float* a, const float* b, double out[3])
{
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)a[k] - o[k];
        e2[k] = (double)b[k] - o[k];
    }
    out[0] = e1[1] * e2[2] - e1[2] * e2[1];
    out[1] = e1[2] * e2[0] - e1[0] * e2[2];
    out[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

static void check_grid(uint32_t w, uint32_t h, bool structural, bool shear, bool bend)
{
    char label[96];
    snprintf(label, sizeof label, "%ux%u structural=%d shear=%d bend=%d", w, h, structural, shear, bend);
    cvk_cloth_desc c = grid_cloth(w, h, structural, shear, bend);
    cvk_topology t;
    cvk_error err;
    REQUIRE_OK(cvk_topology_create(&c, 0, &t, &err), err);
    uint64_t cells = (uint64_t)(w - 1) * (h - 1);
    uint64_t springs = (structural ? (uint64_t)(w - 1) * h + (uint64_t)w * (h - 1) : 0) +
                       (shear ? 2 * cells : 0) +
                       (bend ? (uint64_t)(w > 2 ? w - 2 : 0) * h + (uint64_t)w * (h > 2 ? h - 2 : 0) : 0);
    CHECK(t.vertex_count == w * h, "%s: %u vertices", label, t.vertex_count);
    CHECK(t.triangle_count == 2 * cells, "%s: %u triangles, expected %llu", label, t.triangle_count,
          (unsigned long long)(2 * cells));
    CHECK(t.spring_count == springs, "%s: %u springs, expected %llu", label, t.spring_count,
          (unsigned long long)springs);

    /* Every edge spring joins the edge's own corners and is structural or shear; an edge has
       none only when its kind has no stiffness. Every normal points along u × v = −z. */
    uint32_t wrong_spring = 0, missing = 0, flipped = 0;
    for (uint32_t tri = 0; tri < t.triangle_count; tri++) {
        const uint32_t* v = &t.triangles[3 * tri];
        double n[3];
        cross_sub(&t.position[3 * v[0]], &t.position[3 * v[1]], &t.position[3 * v[2]], n);
        flipped += !(n[2] < 0.0 && fabs(n[0]) < 1e-9 && fabs(n[1]) < 1e-9);
        for (int e = 0; e < 3; e++) {
            uint32_t s = t.triangle_springs[3 * tri + e], a = v[e], b = v[(e + 1) % 3];
            if (s == CVK_NO_SPRING) {
                /* The cell diagonal is shear, the other two edges structural. */
                bool diagonal = a % w != b % w && a / w != b / w;
                missing += diagonal ? shear : structural;
                continue;
            }
            const cvk_topo_spring* sp = &t.springs[s];
            bool joins = (sp->a == a && sp->b == b) || (sp->a == b && sp->b == a);
            wrong_spring += !joins || sp->type == CVK_SPRING_BEND;
        }
    }
    CHECK(wrong_spring == 0, "%s: %u triangle edges name a spring that does not lie along them", label,
          wrong_spring);
    CHECK(missing == 0, "%s: %u triangle edges name no spring though their kind is stiff", label, missing);
    CHECK(flipped == 0, "%s: %u triangles do not face u_axis x v_axis", label, flipped);

    float m = c.mass / (float)(w * h);
    uint32_t uneven = 0;
    for (uint32_t v = 0; v < t.vertex_count; v++)
        uneven += t.mass[v] != m;
    CHECK(uneven == 0, "%s: %u particles without the even share %g kg", label, uneven, m);
    cvk_topology_destroy(&t);
}

/* With a density, the masses add up to density × area. */
static void check_density(void)
{
    cvk_cloth_desc c = grid_cloth(9, 6, true, true, false);
    c.density = 0.25f;
    cvk_topology t;
    cvk_error err;
    REQUIRE_OK(cvk_topology_create(&c, 0, &t, &err), err);
    double total = 0.0;
    for (uint32_t v = 0; v < t.vertex_count; v++)
        total += t.mass[v];
    double expected = 0.25 * 1.2 * 0.8;
    CHECK(fabs(total - expected) < 1e-6, "density: masses add up to %.9g kg, expected %.9g", total, expected);
    /* A corner touches one triangle of its cell or two; an inner vertex six. */
    CHECK(t.mass[0] < t.mass[10], "density: corner %.9g kg not lighter than inner %.9g kg", t.mass[0], t.mass[10]);
    cvk_topology_destroy(&t);
}

static uint32_t pinned_count(const cvk_topology* t)
{
    uint32_t n = 0;
    for (uint32_t v = 0; v < t->vertex_count; v++)
        n += t->pinned[v] != 0;
    return n;
}

static void check_pins(void)
{
    cvk_cloth_desc c = grid_cloth(7, 5, true, false, false);
    const uint32_t pins[2][2] = {{0, 0}, {6, 4}};
    const uint32_t vertices[3] = {3, 3, 17};
    c.pins = pins;
    c.pin_count = 2;
    c.pin_vertices = vertices;
    c.pin_vertex_count = 3;
    /* The row j = 4 lies at y = −0.8 (v_axis points down); the box holds it whole. */
    c.use_pin_box = true;
    c.pin_box = (cvk_box3){{-1.0f, -0.85f, -1.0f}, {2.0f, -0.75f, 1.0f}};
    cvk_topology t;
    cvk_error err;
    REQUIRE_OK(cvk_topology_create(&c, 0, &t, &err), err);
    CHECK(t.pinned[0] && t.pinned[34] && t.pinned[3] && t.pinned[17], "pins: a listed vertex is free");
    uint32_t row = 0;
    for (uint32_t i = 0; i < 7; i++)
        row += t.pinned[4 * 7 + i] != 0;
    CHECK(row == 7, "pin_box: %u of the 7 vertices of the last row pinned", row);
    CHECK(pinned_count(&t) == 10, "pins: %u pinned, expected 10 (2 by [i, j], 2 by index, 7 by box, 1 shared)",
          pinned_count(&t));
    cvk_topology_destroy(&t);
}

static void check_pin_errors(void)
{
    cvk_cloth_desc c = grid_cloth(7, 5, true, false, false);
    const uint32_t vertices[2] = {3, 35};
    c.pin_vertices = vertices;
    c.pin_vertex_count = 2;
    cvk_topology t;
    cvk_error err = {0};
    cvk_result r = cvk_topology_create(&c, 3, &t, &err);
    const char* expected = "cloths.3.pins.1: vertex 35 is out of range; the cloth has 35 vertices";
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT && strcmp(err.message, expected) == 0,
          "pin out of range: %s \"%s\", expected \"%s\"", cvk_result_name(r), err.message, expected);
    CHECK(t.position == NULL && t.pinned == NULL, "pin out of range: the topology was not released");

    c.pin_vertex_count = 0;
    c.use_pin_box = true;
    c.pin_box = (cvk_box3){{5.0f, 5.0f, 5.0f}, {6.0f, 6.0f, 6.0f}};
    r = cvk_topology_create(&c, 1, &t, &err);
    expected = "cloths.1.pin_box: holds none of the cloth's 35 vertices";
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT && strcmp(err.message, expected) == 0,
          "empty pin_box: %s \"%s\", expected \"%s\"", cvk_result_name(r), err.message, expected);
}

/* A topology's error comes out of cvk_build_create unchanged, and nothing is left built. */
static void check_build_error(void)
{
    cvk_cloth_desc cloths[2] = {grid_cloth(6, 6, true, true, true), grid_cloth(7, 5, true, false, false)};
    cloths[1].use_pin_box = true;
    cloths[1].pin_box = (cvk_box3){{5.0f, 5.0f, 5.0f}, {6.0f, 6.0f, 6.0f}};
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = 2;
    cvk_build b;
    cvk_error err = {0};
    cvk_result r = cvk_build_create(&scene, &b, &err);
    const char* expected = "cloths.1.pin_box: holds none of the cloth's 35 vertices";
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT && strcmp(err.message, expected) == 0,
          "build with an empty pin_box: %s \"%s\", expected \"%s\"", cvk_result_name(r), err.message, expected);
    CHECK(b.position == NULL && b.springs == NULL && b.cloths == NULL, "failed build: arrays left behind");
}

/* The stretch quantile over structural springs: a rope of 101 particles whose spring i (in
   build order) is stretched by i / 1000 has its 99th percentile (nearest rank: the 99th
   smallest of 100) at 0.098; a non-finite position makes it NaN. */
static void check_stretch_quantile(void)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = 101;
    cloth.grid[1] = 1;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    cvk_build b;
    cvk_error err;
    REQUIRE_OK(cvk_build_create(&scene, &b, &err), err);
    float* xyz = malloc(3 * sizeof(float) * b.particle_count);
    CHECK(xyz && b.spring_count == 100, "%u springs", b.spring_count);
    if (xyz && b.spring_count == 100) {
        /* Lay the rope out along x so that spring s has length L (1 + s / 1000), in any
           particle order: walk the chain from particle 0 in user order. */
        double x = 0.0;
        for (uint32_t i = 0; i < 101; i++) {
            uint32_t p = b.internal_of[i];
            xyz[3 * p] = (float)x;
            xyz[3 * p + 1] = xyz[3 * p + 2] = 0.0f;
            if (i < 100)
                x += b.springs[0].rest * (1.0 + (double)((i * 37) % 100) / 1000.0);
        }
        double p99 = -1.0;
        CHECK(cvk_metrics_structural_stretch_quantile(&b, xyz, 0.99, &p99), "out of memory");
        CHECK(fabs(p99 - 0.098) < 1e-5, "p99 stretch %.6f, expected 0.098", p99);
        double median = -1.0;
        cvk_metrics_structural_stretch_quantile(&b, xyz, 0.5, &median);
        CHECK(fabs(median - 0.049) < 1e-5, "median stretch %.6f, expected 0.049", median);
        xyz[3 * b.internal_of[50]] = NAN;
        cvk_metrics_structural_stretch_quantile(&b, xyz, 0.99, &p99);
        CHECK(isnan(p99), "p99 stretch with a NaN position: %g", p99);
    }
    free(xyz);
    cvk_build_destroy(&b);
}

int main(void)
{
    const uint32_t sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {2, 2}, {3, 3}, {7, 5}, {16, 11}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        for (int kind = 0; kind < 8; kind++)
            check_grid(sizes[i][0], sizes[i][1], kind & 1, (kind & 2) != 0, (kind & 4) != 0);
    check_density();
    check_pins();
    check_pin_errors();
    check_build_error();
    check_stretch_quantile();
    printf("%d checks, %d failed\n", harness_checks, harness_failures);
    return harness_failures ? 1 : 0;
}
