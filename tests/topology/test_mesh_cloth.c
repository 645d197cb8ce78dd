/* Mesh cloths through the whole library, against things known to be true:
   - a quad mesh of a grid (v lines row by row, faces a b d c) simulates like the grid cloth it
     describes: the same particles, springs and triangles, and with Jacobi the same positions
     up to the order in which spring forces are summed;
   - pin_box pins exactly the vertices inside it, pins by vertex index hold their particles;
   - density gives the cloth density · area of mass (read from the gravitational energy);
   - readback is in file order. */
#include <stdint.h>
#include <unistd.h>

#include "harness.h"

#define NU 12
#define NV 10

static char folder[] = "/tmp/clothvk-mesh-cloth-XXXXXX";
static char obj_path[512];

/* The grid of cvk_default_cloth_desc() with size 1 x 1, origin (0, 1, 0), u = x, v = z, as
   quads: vertex [i, j] on line j * NU + i, face (a, b, d, c) per cell. */
static void write_grid_obj(void)
{
    snprintf(obj_path, sizeof obj_path, "%s/grid.obj", folder);
    FILE* f = fopen(obj_path, "w");
    if (!f) {
        fprintf(stderr, "cannot write %s\n", obj_path);
        exit(1);
    }
    fprintf(f, "# %d x %d grid as quads\n", NU, NV);
    for (int j = 0; j < NV; j++)
        for (int i = 0; i < NU; i++)
            fprintf(f, "v %.9g %.9g %.9g\n", i / (double)(NU - 1), 1.0, j / (double)(NV - 1));
    for (int j = 0; j + 1 < NV; j++)
        for (int i = 0; i + 1 < NU; i++) {
            int a = j * NU + i + 1, b = a + 1, c = a + NU, d = c + 1;
            fprintf(f, "f %d %d %d %d\n", a, b, d, c);
        }
    fclose(f);
}

static cvk_cloth_desc grid_cloth(void)
{
    static const uint32_t pins[2][2] = {{0, 0}, {NU - 1, 0}};
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = NU;
    c.grid[1] = NV;
    c.origin[0] = 0.0f;
    c.origin[1] = 1.0f;
    c.stiffness.structural = 1e4f;
    c.stiffness.shear = 1e3f;
    c.pins = pins;
    c.pin_count = 2;
    return c;
}

static cvk_cloth_desc mesh_cloth(void)
{
    static const uint32_t pins[2] = {0, NU - 1};
    cvk_cloth_desc c = grid_cloth();
    c.mesh = obj_path;
    c.pins = NULL;
    c.pin_count = 0;
    c.pin_vertices = pins;
    c.pin_vertex_count = 2;
    /* The grid spreads mass evenly; a mesh by area: the same only with the same total per
       vertex, which the comparison below does not need (Jacobi's result depends on masses,
       so both use the mesh's lumping through density on the grid too). */
    return c;
}

static cvk_sim* make_sim(cvk_context* ctx, const cvk_cloth_desc* cloth, cvk_linear_solver linear)
{
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloth;
    scene.cloth_count = 1;
    scene.solver.linear = linear;
    cvk_error err;
    cvk_sim* sim = NULL;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    return sim;
}

/* Same particles, springs, colours aside, and triangles. */
static void same_structure(cvk_sim* grid, cvk_sim* mesh)
{
    cvk_error err;
    cvk_sim_stats a, b;
    REQUIRE_OK(cvk_sim_get_stats(grid, &a, &err), err);
    REQUIRE_OK(cvk_sim_get_stats(mesh, &b, &err), err);
    CHECK(a.particles == b.particles && a.pinned == b.pinned, "particles %llu/%llu pinned vs %llu/%llu",
          (unsigned long long)a.particles, (unsigned long long)a.pinned,
          (unsigned long long)b.particles, (unsigned long long)b.pinned);
    for (int t = 0; t < 3; t++)
        CHECK(a.springs[t] == b.springs[t], "springs of type %d: grid %llu, mesh %llu", t,
              (unsigned long long)a.springs[t], (unsigned long long)b.springs[t]);
    uint64_t tris = cvk_sim_triangle_count(grid);
    CHECK(tris == 2 * (NU - 1) * (NV - 1) && cvk_sim_triangle_count(mesh) == tris,
          "triangles: grid %llu, mesh %llu", (unsigned long long)tris,
          (unsigned long long)cvk_sim_triangle_count(mesh));
    uint64_t n = a.particles;
    uint32_t* ta = malloc(3 * tris * sizeof(uint32_t));
    uint32_t* tb = malloc(3 * tris * sizeof(uint32_t));
    if (!ta || !tb)
        exit(1);
    REQUIRE_OK(cvk_sim_read_mesh(grid, NULL, NULL, ta, n, tris, &err), err);
    REQUIRE_OK(cvk_sim_read_mesh(mesh, NULL, NULL, tb, n, tris, &err), err);
    CHECK(memcmp(ta, tb, 3 * tris * sizeof(uint32_t)) == 0,
          "the mesh's triangles differ from the grid's");
    free(ta);
    free(tb);
}

static void quad_grid_equals_grid(cvk_context* ctx)
{
    cvk_cloth_desc g = grid_cloth(), m = mesh_cloth();
    /* Equal masses: a uniform grid lumps by area to ¼, ½ and 1 of an interior vertex's
       share at corners, edges and inside, so give the grid the same lumping by density. */
    g.density = m.density = 0.1f;
    cvk_sim* grid = make_sim(ctx, &g, CVK_LINEAR_JACOBI);
    cvk_sim* mesh = make_sim(ctx, &m, CVK_LINEAR_JACOBI);
    same_structure(grid, mesh);
    float* start_g = harness_read_all(grid);
    float* start_m = harness_read_all(mesh);
    uint64_t n = cvk_sim_particle_count(grid);
    double d0 = harness_max_diff(start_g, start_m, 3 * n);
    CHECK(d0 < 1e-6, "initial positions differ by %g m (file order must be the v lines' order)",
          d0);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(grid, 20, &err), err);
    REQUIRE_OK(cvk_sim_step(mesh, 20, &err), err);
    float* end_g = harness_read_all(grid);
    float* end_m = harness_read_all(mesh);
    double moved = harness_max_diff(start_g, end_g, 3 * n);
    double d = harness_max_diff(end_g, end_m, 3 * n);
    /* Jacobi does not depend on the particle order; only the order of the spring sums does,
       a few float ulps per sweep of motions of ~0.3 m. */
    CHECK(moved > 0.1, "the cloth barely moved (%g m)", moved);
    CHECK(d < 1e-5, "mesh and grid cloths differ by %g m after 20 frames (moved %g m)", d, moved);
    printf("quad mesh of a %dx%d grid vs the grid (jacobi, 20 frames): %.3g m apart, moved %.3g m\n",
           NU, NV, d, moved);
    free(start_g);
    free(start_m);
    free(end_g);
    free(end_m);
    cvk_sim_destroy(grid);
    cvk_sim_destroy(mesh);
}

/* The top row (z = 0) by a box; those particles stay, the rest fall. */
static void pin_box(cvk_context* ctx)
{
    cvk_cloth_desc m = mesh_cloth();
    m.pin_vertices = NULL;
    m.pin_vertex_count = 0;
    m.use_pin_box = true;
    m.pin_box = (cvk_box3){{-0.1f, 0.9f, -0.01f}, {1.1f, 1.1f, 0.01f}};
    cvk_sim* sim = make_sim(ctx, &m, CVK_LINEAR_RBGS);
    cvk_error err;
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    CHECK(st.pinned == NU, "pin_box pinned %llu particles, expected the %d of the top row",
          (unsigned long long)st.pinned, NU);
    float* start = harness_read_all(sim);
    REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
    float* end = harness_read_all(sim);
    double still = 0.0, fell = INFINITY;
    for (uint64_t p = 0; p < cvk_sim_particle_count(sim); p++) {
        double dy = fabs((double)end[3 * p + 1] - start[3 * p + 1]);
        if (p < NU)
            still = fmax(still, dy);
        else
            fell = fmin(fell, dy);
    }
    CHECK(still == 0.0, "a particle pinned by the box moved by %g m", still);
    CHECK(fell > 0.0, "a free particle did not move");
    free(start);
    free(end);
    cvk_sim_destroy(sim);
}

/* Flat at height 1 with integration on: gravitational energy = −Σ m g·x = M · 9.81 · 1. */
static void density_mass(cvk_context* ctx)
{
    cvk_cloth_desc m = mesh_cloth();
    m.density = 0.25f; /* kg/m², 1 m² */
    cvk_sim* sim = make_sim(ctx, &m, CVK_LINEAR_RBGS);
    cvk_error err;
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    /* Pinned particles are left out of the energy. Particle [0, 0] lies in one triangle
       (half a cell), [NU − 1, 0] in two, and each holds a third of its triangles' area. */
    double cell = 1.0 / ((NU - 1) * (NV - 1));
    double pinned_mass = 0.25 * 3.0 * (0.5 * cell) / 3.0;
    double expected = (0.25 - pinned_mass) * 9.81;
    CHECK(fabs(st.gravitational_energy - expected) < 1e-5 * expected,
          "gravitational energy %.9g J, expected %.9g J for 0.25 kg/m² over 1 m²",
          st.gravitational_energy, expected);
    cvk_sim_destroy(sim);
}

int main(void)
{
    if (!mkdtemp(folder)) {
        perror("mkdtemp");
        return 1;
    }
    write_grid_obj();
    cvk_context* ctx = harness_context();
    quad_grid_equals_grid(ctx);
    pin_box(ctx);
    density_mass(ctx);
    remove(obj_path);
    rmdir(folder);
    return harness_finish(ctx);
}
