/* The export calls an application uses to take the cloths through its own pipeline:
   - cvk_sim_cloth_count, cvk_sim_get_cloth and cvk_sim_triangle_count describe the cloths'
     particle and triangle ranges (a grid: 2 (nu − 1)(nv − 1) triangles);
   - cvk_sim_read_mesh gives the positions of cvk_sim_read_positions bit for bit, the grid's
     triangles (a, b, c), (b, d, c) per cell, and unit normals on the front side (u × v);
   - wrong counts and a missing simulation are refused with a sentence naming the call. */
#include "harness.h"

typedef struct two_cloths {
    cvk_cloth_desc cloths[2];
    cvk_scene_desc scene;
    uint32_t pins[2][2];
} two_cloths;

/* "a": 5 × 4 in the x-z plane (front u × v = x × z = −y); "b": 3 × 3, no name, in the
   x-y plane (front +z). Both pinned at [0, 0]. */
static void make_scene(two_cloths* t)
{
    t->pins[0][0] = t->pins[0][1] = 0;
    for (int c = 0; c < 2; c++) {
        t->cloths[c] = cvk_default_cloth_desc();
        t->cloths[c].size[0] = t->cloths[c].size[1] = 0.3f;
        t->cloths[c].stiffness.structural = 1e4f;
        t->cloths[c].pins = (const uint32_t(*)[2])t->pins;
        t->cloths[c].pin_count = 1;
    }
    t->cloths[0].name = "a";
    t->cloths[0].grid[0] = 5;
    t->cloths[0].grid[1] = 4;
    memcpy(t->cloths[0].v_axis, (const float[3]){0, 0, 1}, sizeof(float[3]));
    t->cloths[1].grid[0] = t->cloths[1].grid[1] = 3;
    t->cloths[1].origin[0] = 1.0f;
    memcpy(t->cloths[1].v_axis, (const float[3]){0, 1, 0}, sizeof(float[3]));
    t->scene = cvk_default_scene_desc();
    t->scene.substeps = 2;
    t->scene.cloths = t->cloths;
    t->scene.cloth_count = 2;
}

static const float fronts[2][3] = {{0, -1, 0}, {0, 0, 1}};

static void check_info(cvk_sim* sim)
{
    CHECK(cvk_sim_cloth_count(sim) == 2, "%u cloths, expected 2", cvk_sim_cloth_count(sim));
    cvk_cloth_info a = cvk_sim_get_cloth(sim, 0), b = cvk_sim_get_cloth(sim, 1);
    CHECK(a.name && strcmp(a.name, "a") == 0, "cloth 0 is called %s, expected a", a.name ? a.name : "(null)");
    CHECK(b.name && strcmp(b.name, "cloth1") == 0, "cloth 1 is called %s, expected cloth1",
          b.name ? b.name : "(null)");
    CHECK(a.first_particle == 0 && a.particle_count == 20, "cloth 0 has particles %u + %u, expected 0 + 20",
          a.first_particle, a.particle_count);
    CHECK(b.first_particle == 20 && b.particle_count == 9, "cloth 1 has particles %u + %u, expected 20 + 9",
          b.first_particle, b.particle_count);
    CHECK(a.first_triangle == 0 && a.triangle_count == 24, "cloth 0 has triangles %u + %u, expected 0 + 24",
          a.first_triangle, a.triangle_count);
    CHECK(b.first_triangle == 24 && b.triangle_count == 8, "cloth 1 has triangles %u + %u, expected 24 + 8",
          b.first_triangle, b.triangle_count);
    CHECK(!a.mesh && !b.mesh, "a grid is reported as a mesh");
    cvk_cloth_info none = cvk_sim_get_cloth(sim, 2);
    CHECK(!none.name && none.particle_count == 0 && none.triangle_count == 0,
          "cloth 2 of 2 is not all zeroes");
    CHECK(cvk_sim_triangle_count(sim) == 32, "%llu triangles, expected 32",
          (unsigned long long)cvk_sim_triangle_count(sim));
    CHECK(cvk_sim_cloth_count(NULL) == 0 && cvk_sim_triangle_count(NULL) == 0,
          "a NULL simulation has cloths or triangles");
}

static void check_refusals(cvk_sim* sim)
{
    float xyz[3 * 29];
    uint32_t tri[3 * 32];
    cvk_error err = {0};
    cvk_result r = cvk_sim_read_mesh(sim, xyz, NULL, NULL, 28, 32, &err);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT &&
              !strcmp(err.message, "cvk_sim_read_mesh: the array holds 28 particles; the simulation has 29"),
          "28 particles: %s: %s", cvk_result_name(r), err.message);
    r = cvk_sim_read_mesh(sim, NULL, NULL, tri, 29, 31, &err);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT &&
              !strcmp(err.message, "cvk_sim_read_mesh: the array holds 31 triangles; the simulation has 32"),
          "31 triangles: %s: %s", cvk_result_name(r), err.message);
    r = cvk_sim_read_mesh(NULL, xyz, NULL, NULL, 29, 32, &err);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT && !strcmp(err.message, "cvk_sim_read_mesh needs a simulation"),
          "no simulation: %s: %s", cvk_result_name(r), err.message);
    r = cvk_sim_read_mesh(sim, NULL, NULL, NULL, 29, 32, &err);
    CHECK(r == CVK_SUCCESS, "no arrays: %s: %s", cvk_result_name(r), err.message);
}

/* Cell (i, j) of a cloth with nu particles per row, first particle f: (a, b, c), (b, d, c). */
static uint32_t mismatched_triangles(const uint32_t* tri)
{
    const uint32_t grids[2][3] = {{5, 4, 0}, {3, 3, 20}};
    uint32_t t = 0, wrong = 0;
    for (int c = 0; c < 2; c++)
        for (uint32_t j = 0; j + 1 < grids[c][1]; j++)
            for (uint32_t i = 0; i + 1 < grids[c][0]; i++, t += 2) {
                uint32_t a = grids[c][2] + j * grids[c][0] + i, b = a + 1, cc = a + grids[c][0];
                uint32_t want[6] = {a, b, cc, b, cc + 1, cc};
                wrong += memcmp(&tri[3 * t], want, sizeof want) != 0;
            }
    return wrong;
}

/* Largest |n − expected| over the cloths' vertices (expected NULL: | |n| − 1 |). */
static double normal_error(const float* normals, const float (*expected)[3])
{
    double worst = 0.0;
    for (uint32_t p = 0; p < 29; p++) {
        const float* n = &normals[3 * p];
        double e = 0.0;
        if (expected) {
            const float* f = expected[p < 20 ? 0 : 1];
            e = fmax(fabs(n[0] - f[0]), fmax(fabs(n[1] - f[1]), fabs(n[2] - f[2])));
        } else {
            e = fabs(sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]) - 1.0);
        }
        worst = fmax(worst, e);
    }
    return worst;
}

static void check_mesh(cvk_context* ctx, cvk_linear_solver linear)
{
    two_cloths t;
    make_scene(&t);
    t.scene.solver.linear = linear;
    const char* name = cvk_linear_solver_name(linear);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &t.scene, &sim, &err), err);
    if (linear == CVK_LINEAR_RBGS) {
        check_info(sim);
        check_refusals(sim);
    }
    float xyz[3 * 29], normals[3 * 29];
    uint32_t tri[3 * 32];
    uint64_t tris = cvk_sim_triangle_count(sim);
    REQUIRE_OK(cvk_sim_read_mesh(sim, xyz, normals, tri, 29, tris, &err), err);
    CHECK(tris == 32 && mismatched_triangles(tri) == 0, "%s: %llu triangles, %u cells differ from the grid's",
          name, (unsigned long long)tris, tris == 32 ? mismatched_triangles(tri) : 0);
    double e = normal_error(normals, fronts);
    CHECK(e < 1e-6, "%s: flat cloths' normals are %g off u x v", name, e);

    REQUIRE_OK(cvk_sim_step(sim, 3, &err), err);
    float* positions = harness_read_all(sim);
    REQUIRE_OK(cvk_sim_read_mesh(sim, xyz, normals, NULL, 29, tris, &err), err);
    CHECK(memcmp(xyz, positions, sizeof xyz) == 0, "%s: read_mesh positions differ from read_positions by %g m",
          name, harness_max_diff(xyz, positions, 3 * 29));
    e = normal_error(normals, NULL);
    CHECK(e < 1e-6, "%s: a normal's length is %g off 1 after 3 frames", name, e);
    free(positions);
    cvk_sim_destroy(sim);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    check_mesh(ctx, CVK_LINEAR_RBGS);
    check_mesh(ctx, CVK_LINEAR_GS_CPU);
    return harness_finish(ctx);
}
