/* Physics against known truths:
   - free fall of an unpinned cloth under Verlet follows x0 + ½ g t² to float rounding;
   - a hanging chain (a 1×N cloth pinned at both ends) settles to the catenary within 1%;
   - pinned particles do not move, also after they are moved by cvk_sim_write_positions;
   - 1000 frames of hanging.json stay finite. */
#include "harness.h"

static cvk_sim* make_sim(cvk_context* ctx, const cvk_scene_desc* scene)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    return sim;
}

static void free_fall(cvk_context* ctx, cvk_linear_solver linear)
{
    cvk_cloth_desc cloth = harness_falling_cloth();
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.solver.linear = linear;
    const uint32_t frames = 50; /* 0.8 s, a 3.1 m drop */
    cvk_sim* sim = make_sim(ctx, &scene);
    float* start = harness_read_all(sim);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, frames, &err), err);
    float* end = harness_read_all(sim);
    uint64_t n = cvk_sim_particle_count(sim);
    double t = frames * scene.substeps * (double)scene.dt;
    double worst = 0.0, largest = 0.0;
    for (uint64_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++) {
            double expected = start[3 * p + c] + 0.5 * scene.gravity[c] * t * t;
            double d = fabs(end[3 * p + c] - expected);
            if (d > worst || isnan(d))
                worst = d;
            largest = fmax(largest, fabs(expected));
        }
    /* The solver works on displacements, so the only rounding that builds up is x += u, once
       per step: at most half an ulp of the largest coordinate each, summed over the steps.
       (Solving for absolute positions fed that rounding back into the velocity and grew
       quadratically: 4.5 mm here.) A missing half-step start or one step too many is
       1.6e-4 m or more. */
    uint32_t steps = frames * scene.substeps;
    double bound = steps * (double)(nextafterf((float)largest, INFINITY) - (float)largest);
    CHECK(worst < bound, "%s: free fall after %.2f s is %g m off x0 + g t^2 / 2",
          cvk_linear_solver_name(linear), t, worst);
    printf("free fall (%s): %.3g m from x0 + g t^2 / 2 after %.2f s (rounding bound %.3g m)\n",
           cvk_linear_solver_name(linear), worst, t, bound);
    free(start);
    free(end);
    cvk_sim_destroy(sim);
}

/* Catenary through (±D/2, 0) with arc length S: a from S = 2a sinh(D / 2a), by bisection. */
static double catenary_parameter(double span, double length)
{
    double lo = 1e-3, hi = 1e3;
    for (int i = 0; i < 200; i++) {
        double a = sqrt(lo * hi);
        if (2 * a * sinh(span / (2 * a)) > length)
            lo = a;
        else
            hi = a;
    }
    return sqrt(lo * hi);
}

static void hanging_chain(cvk_context* ctx)
{
    const uint32_t n = 41;
    const double span = 1.0, slack = 1.3;
    uint32_t pins[2][2] = {{0, 0}, {n - 1, 0}};
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = n;
    cloth.grid[1] = 1;
    cloth.size[0] = (float)span;
    cloth.origin[0] = 0.0f;
    cloth.origin[1] = 1.0f;
    cloth.origin[2] = 0.0f;
    cloth.rest_scale = (float)slack; /* the chain is 1.3 m long between pins 1 m apart */
    cloth.stiffness.structural = 1e5f;
    cloth.pins = (const uint32_t(*)[2])pins;
    cloth.pin_count = 2;
    /* A truncated projective-dynamics solve rests where it returns no displacement, which is
       the true equilibrium only up to its local-step lag: the springs to the pins are
       projected from a prediction h² g below them. At the seed's h = 2 ms with 4 x 4 sweeps
       this chain rests 0.9% of its sag off the exact discrete equilibrium (itself 0.07% off
       the catenary); at h = 0.5 ms, 0.5%. The test checks the physics at the finer step. */
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.dt = 0.0005f;
    scene.substeps = 32;
    scene.damping = 0.01f;
    cvk_sim* sim = make_sim(ctx, &scene);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, 200, &err), err); /* 3.2 s: the swing has died out */
    float* xyz = harness_read_all(sim);

    double a = catenary_parameter(span, span * slack);
    double sag = a * (cosh(span / (2 * a)) - 1.0);
    double lowest = 1.0, worst = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        double x = xyz[3 * i] - span / 2, y = xyz[3 * i + 1] - 1.0;
        double expected = a * (cosh(x / a) - cosh(span / (2 * a)));
        double d = fabs(y - expected);
        if (d > worst || isnan(d))
            worst = d;
        if (y < lowest)
            lowest = y;
    }
    CHECK(fabs(-lowest - sag) < 0.01 * sag, "chain sags %.5f m, the catenary %.5f m (%.2f%% off)",
          -lowest, sag, 100 * fabs(-lowest - sag) / sag);
    CHECK(worst < 0.01 * sag, "a chain particle is %.5f m off the catenary (%.2f%% of the sag)",
          worst, 100 * worst / sag);
    printf("catenary: sag %.5f m vs %.5f m, worst particle %.3f%% of the sag\n", -lowest, sag,
           100 * worst / sag);
    free(xyz);
    cvk_sim_destroy(sim);
}

static void pins_hold(cvk_context* ctx)
{
    uint32_t pins[3][2] = {{0, 0}, {15, 0}, {7, 0}}; /* one edge: the cloth swings down */
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = 16;
    cloth.grid[1] = 12;
    cloth.stiffness.shear = 1e5f;
    cloth.pins = (const uint32_t(*)[2])pins;
    cloth.pin_count = 3;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    for (int solver = 0; solver < 4; solver++) {
        scene.solver.linear = (cvk_linear_solver)solver;
        cvk_sim* sim = make_sim(ctx, &scene);
        float* before = harness_read_all(sim);
        cvk_error err;
        REQUIRE_OK(cvk_sim_step(sim, 30, &err), err);
        float* after = harness_read_all(sim);
        const char* name = cvk_linear_solver_name(scene.solver.linear);
        for (uint32_t p = 0; p < 3; p++) {
            size_t u = pins[p][1] * 16 + pins[p][0];
            CHECK(memcmp(&before[3 * u], &after[3 * u], 3 * sizeof(float)) == 0,
                  "%s: pin [%u, %u] moved from (%g, %g, %g) to (%g, %g, %g)", name, pins[p][0],
                  pins[p][1], before[3 * u], before[3 * u + 1], before[3 * u + 2], after[3 * u],
                  after[3 * u + 1], after[3 * u + 2]);
        }
        size_t free_one = 5 * 16 + 5;
        CHECK(after[3 * free_one + 1] < before[3 * free_one + 1] - 0.01f, "%s: the cloth did not fall",
              name);
        /* A pin moved by the application holds its new place. */
        after[3 * 0 + 1] += 0.25f;
        REQUIRE_OK(cvk_sim_write_positions(sim, after, cvk_sim_particle_count(sim), &err), err);
        REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
        float* moved = harness_read_all(sim);
        CHECK(memcmp(&moved[0], &after[0], 3 * sizeof(float)) == 0, "%s: a moved pin did not hold",
              name);
        free(before);
        free(after);
        free(moved);
        cvk_sim_destroy(sim);
    }
}

static void hanging_stays_finite(cvk_context* ctx)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    char path[1024];
    snprintf(path, sizeof path, "%s/assets/scenes/hanging.json", root ? root : ".");
    cvk_error err;
    cvk_scene* file;
    REQUIRE_OK(cvk_scene_load(path, NULL, 0, &file, &err), err);
    cvk_sim* sim = make_sim(ctx, cvk_scene_get_desc(file));
    cvk_sim_stats st;
    double worst_stretch = 0.0;
    for (int chunk = 0; chunk < 10; chunk++) {
        REQUIRE_OK(cvk_sim_step(sim, 100, &err), err);
        REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
        CHECK(st.nan_count == 0, "after %llu frames: %llu non-finite coordinates",
              (unsigned long long)st.frames, (unsigned long long)st.nan_count);
        if (st.max_stretch > worst_stretch)
            worst_stretch = st.max_stretch;
    }
    float* xyz = harness_read_all(sim);
    double far = 0.0;
    for (uint64_t i = 0; i < 3 * cvk_sim_particle_count(sim); i++)
        far = fmax(far, fabs(xyz[i]));
    CHECK(far < 10.0, "after 1000 frames a particle is %g m from the origin", far);
    CHECK(st.frames == 1000, "%llu frames stepped", (unsigned long long)st.frames);
    printf("hanging.json: 1000 frames finite, largest stretch seen %.1f%%, residual %.3g m^2\n",
           100 * worst_stretch, st.residual);
    free(xyz);
    cvk_sim_destroy(sim);
    cvk_scene_destroy(file);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    free_fall(ctx, CVK_LINEAR_RBGS);
    free_fall(ctx, CVK_LINEAR_CHEBYSHEV);
    free_fall(ctx, CVK_LINEAR_GS_CPU);
    hanging_chain(ctx);
    pins_hold(ctx);
    hanging_stays_finite(ctx);
    return harness_finish(ctx);
}
