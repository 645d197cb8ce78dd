/* The implicit Euler family (lib/solvers/solve_implicit.c, shaders/implicit_*.comp):
   - the scene keys and their messages;
   - device CG and block Jacobi equal the host double-precision reference, iteration count by
     iteration count, on small random cloths, and stop within one iteration of each other (the
     device's float residual and the host's double one cross the tolerance a step apart at
     most);
   - the filter keeps pinned particles exactly where they are;
   - seed 000 §6.1: strongly compressed springs without the clamp make the system indefinite
     (CG meets pᵀAp <= 0, Jacobi a block that is not positive definite, in the first
     substep); with the clamp both stay finite for 50 substeps;
   - a hanging cloth settles, and the energy of a damped run never grows over 1,000 frames. */
#include "topology/build.h"
#include "harness.h"
#include "solvers/solve_implicit.h"

/* Float rounding over one substep with up to 5 iterations: velocities are compared relative
   to the largest velocity change of the substep. Measured below 1e-5; an iteration more or
   fewer moves them by 1e-2 and more (checked). */
#define SAME_TO_ROUNDING 1e-4

static void scene_keys(void)
{
    cvk_scene* scene = NULL;
    cvk_error err;
    REQUIRE_OK(cvk_scene_parse("{\"solver\": {\"method\": \"implicit\", \"linear\": \"cg\", "
                               "\"tolerance\": 1e-4, \"max_iterations\": 7, \"kd\": 0.5}, "
                               "\"cloths\": [{}]}", "t.json", NULL, 0, &scene, &err), err);
    const cvk_solver_desc* s = &cvk_scene_get_desc(scene)->solver;
    CHECK(s->method == CVK_METHOD_IMPLICIT && s->linear == CVK_LINEAR_CG, "method %d linear %d",
          s->method, s->linear);
    CHECK(s->tolerance == 1e-4f && s->max_iterations == 7 && s->kd == 0.5f,
          "tolerance %g, max_iterations %u, kd %g", s->tolerance, s->max_iterations, s->kd);
    cvk_scene_destroy(scene);
    cvk_scene_desc d = cvk_default_scene_desc();
    d.solver.method = CVK_METHOD_IMPLICIT; /* 0 in the description: the method's default */
    cvk_solver_desc resolved = cvk_solver_desc_resolve(&d.solver);
    CHECK(resolved.tolerance == 1e-3f && resolved.max_iterations == 100 && d.solver.kd == 0.0f,
          "defaults: tolerance %g, max_iterations %u, kd %g", resolved.tolerance,
          resolved.max_iterations, d.solver.kd);

    harness_expect_scene_message("{\"solver\": {\"method\": \"implicit\"}, \"cloths\": [{}]}",
                   "t.json: solver.linear: rbgs is not a linear solver of the implicit method; "
                   "use cg or jacobi");
    harness_expect_scene_message("{\"solver\": {\"linear\": \"cg\"}, \"cloths\": [{}]}",
                   "t.json: solver.linear: cg solves the implicit method only; use rbgs, jacobi, "
                   "chebyshev or gs-cpu with pd");
    harness_expect_scene_message("{\"solver\": {\"method\": \"implicit\", \"linear\": \"cg\", \"tolerance\": 0}, "
                   "\"cloths\": [{}]}",
                   "t.json: solver.tolerance: must be greater than 0 and less than 1, got 0");
    harness_expect_scene_message("{\"solver\": {\"method\": \"implicit\", \"linear\": \"cg\", \"kd\": -1}, "
                   "\"cloths\": [{}]}",
                   "t.json: solver.kd: must be at least 0, got -1");
    harness_expect_scene_message("{\"solver\": {\"method\": \"implicit\", \"linear\": \"cg\", "
                   "\"max_iterations\": 0}, \"cloths\": [{}]}",
                   "t.json: solver.max_iterations: must be at least 1, got 0");
}

typedef struct random_cloth {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    uint32_t pins[3][2];
} random_cloth;

static void make_random_cloth(harness_rng* rng, random_cloth* rc, cvk_linear_solver linear)
{
    rc->cloth = cvk_default_cloth_desc();
    rc->cloth.grid[0] = 3 + harness_next(rng) % 7;
    rc->cloth.grid[1] = 3 + harness_next(rng) % 7;
    rc->cloth.size[0] = (float)harness_uniform(rng, 0.3, 1.0);
    rc->cloth.size[1] = (float)harness_uniform(rng, 0.3, 1.0);
    rc->cloth.stiffness.structural = (float)harness_uniform(rng, 1e2, 1e4);
    rc->cloth.stiffness.shear = harness_next(rng) % 2 ? (float)harness_uniform(rng, 1e1, 1e3) : 0.0f;
    rc->cloth.stiffness.bend = harness_next(rng) % 2 ? (float)harness_uniform(rng, 1e0, 1e2) : 0.0f;
    rc->cloth.rest_scale = (float)harness_uniform(rng, 0.9, 1.1);
    uint32_t pins = harness_next(rng) % 3;
    for (uint32_t p = 0; p < pins; p++) {
        rc->pins[p][0] = harness_next(rng) % rc->cloth.grid[0];
        rc->pins[p][1] = harness_next(rng) % rc->cloth.grid[1];
    }
    rc->cloth.pins = (const uint32_t(*)[2])rc->pins;
    rc->cloth.pin_count = pins;
    rc->scene = cvk_default_scene_desc();
    rc->scene.cloths = &rc->cloth;
    rc->scene.cloth_count = 1;
    rc->scene.substeps = 1;
    rc->scene.dt = (float)harness_uniform(rng, 0.002, 0.03);
    rc->scene.damping = (float)harness_uniform(rng, 0.0, 0.02);
    rc->scene.solver.method = CVK_METHOD_IMPLICIT;
    rc->scene.solver.linear = linear;
    rc->scene.solver.kd = (float)harness_uniform(rng, 0.0, 1.0);
    rc->scene.solver.tolerance = 1e-7f; /* runs every iteration it is given */
}

/* The same substep on the host; returns its report. */
static cvk_implicit_report host_substep(const cvk_scene_desc* scene, const float* xyz,
                                        const float* v, double* hx, double* hv)
{
    cvk_error err;
    cvk_build b;
    REQUIRE_OK(cvk_build_create(scene, &b, &err), err);
    for (uint32_t p = 0; p < b.particle_count; p++)
        for (int c = 0; c < 3; c++) {
            hx[3 * p + c] = xyz[3 * b.user_of[p] + c];
            hv[3 * p + c] = p < b.free_count ? v[3 * b.user_of[p] + c] : 0.0;
        }
    cvk_step_params step_params = cvk_step_params_of(scene);
    cvk_implicit_params ip = cvk_implicit_params_of(&step_params, &scene->solver);
    cvk_implicit_report rep;
    CHECK(cvk_ref_implicit_substep(&b, &ip, hx, hv, &rep), "out of memory");
    /* back to user order */
    double* t = malloc(6 * b.particle_count * sizeof(double));
    memcpy(t, hx, 3 * b.particle_count * sizeof(double));
    memcpy(t + 3 * b.particle_count, hv, 3 * b.particle_count * sizeof(double));
    for (uint32_t p = 0; p < b.particle_count; p++)
        for (int c = 0; c < 3; c++) {
            hx[3 * b.user_of[p] + c] = t[3 * p + c];
            hv[3 * b.user_of[p] + c] = t[3 * (b.particle_count + p) + c];
        }
    free(t);
    cvk_build_destroy(&b);
    return rep;
}

/* Largest |a − b| over the largest |b − before|: the difference relative to the step. */
static double relative_diff(const float* a, const double* b, const float* before, size_t n)
{
    double diff = 0.0, scale = 1e-30;
    for (size_t i = 0; i < n; i++) {
        double d = fabs(a[i] - b[i]);
        diff = isnan(d) || d > diff ? d : diff;
        scale = fmax(scale, fabs(b[i] - before[i]));
    }
    return diff / scale;
}

static void device_equals_reference(cvk_context* ctx, cvk_linear_solver linear)
{
    harness_rng rng = {0x2545f491u + (uint32_t)linear};
    const char* name = cvk_linear_solver_name(linear);
    double worst = 0.0;
    for (int trial = 0; trial < 5; trial++) {
        random_cloth rc;
        make_random_cloth(&rng, &rc, linear);
        uint64_t n = (uint64_t)rc.cloth.grid[0] * rc.cloth.grid[1];
        float *x0, *v0;
        harness_random_start(ctx, &rc.scene, &rng, 0.01, 0.5, n, &x0, &v0);
        float* x = malloc(3 * n * sizeof(float));
        float* v = malloc(3 * n * sizeof(float));
        double* hx = malloc(3 * n * sizeof(double));
        double* hv = malloc(3 * n * sizeof(double));
        double* hv_previous = calloc(3 * n, sizeof(double));
        const uint32_t counts[] = {1, 2, 3, 5};
        for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
            rc.scene.solver.max_iterations = counts[k];
            memcpy(x, x0, 3 * n * sizeof(float));
            memcpy(v, v0, 3 * n * sizeof(float));
            cvk_sim_stats st;
            harness_frame_from(ctx, &rc.scene, x, v, &st);
            cvk_implicit_report rep = host_substep(&rc.scene, x0, v0, hx, hv);
            double dv = relative_diff(v, hv, v0, 3 * n), dx = relative_diff(x, hx, x0, 3 * n);
            worst = fmax(worst, fmax(dv, dx));
            CHECK(dv < SAME_TO_ROUNDING && dx < SAME_TO_ROUNDING,
                  "%s trial %d (%ux%u, %u pins, h %g) after %u iterations: velocities differ by "
                  "%g, positions by %g of the step", name, trial, rc.cloth.grid[0],
                  rc.cloth.grid[1], rc.cloth.pin_count, rc.scene.dt, counts[k], dv, dx);
            CHECK(st.solver_iterations == rep.iterations && st.solver_breakdowns == 0,
                  "%s trial %d: the device did %u iterations (%u breakdowns), the host %u", name,
                  trial, st.solver_iterations, st.solver_breakdowns, rep.iterations);
            /* The comparison can fail: the previous count's velocities are far off. */
            if (k > 0 && rep.iterations == counts[k]) {
                double apart = 0.0, scale = 1e-30;
                for (uint64_t i = 0; i < 3 * n; i++) {
                    apart = fmax(apart, fabs(hv[i] - hv_previous[i]));
                    scale = fmax(scale, fabs(hv[i] - v0[i]));
                }
                CHECK(apart / scale > 10 * SAME_TO_ROUNDING,
                      "%s trial %d: %u and %u iterations differ by only %g", name, trial,
                      counts[k - 1], counts[k], apart / scale);
            }
            memcpy(hv_previous, hv, 3 * n * sizeof(double));
        }
        /* The stopping rule: the same number of iterations on both sides, to one. */
        rc.scene.solver.tolerance = 1e-2f;
        rc.scene.solver.max_iterations = 500;
        memcpy(x, x0, 3 * n * sizeof(float));
        memcpy(v, v0, 3 * n * sizeof(float));
        cvk_sim_stats st;
        harness_frame_from(ctx, &rc.scene, x, v, &st);
        cvk_implicit_report rep = host_substep(&rc.scene, x0, v0, hx, hv);
        CHECK(st.solver_iterations + 1 >= rep.iterations && st.solver_iterations <= rep.iterations + 1,
              "%s trial %d: to 1e-2 the device stopped after %u iterations, the host after %u",
              name, trial, st.solver_iterations, rep.iterations);
        /* Block Jacobi converges only where the blocks dominate (h² k small against m). */
        CHECK(linear != CVK_LINEAR_CG || rep.residual <= 1e-2,
              "%s trial %d: the host stopped at residual %g", name, trial, rep.residual);
        free(x0);
        free(v0);
        free(x);
        free(v);
        free(hx);
        free(hv);
        free(hv_previous);
    }
    printf("%s: device vs host, largest difference %.3g of the step\n", name, worst);
}

static cvk_scene_desc hanging_scene(cvk_cloth_desc* cloth, uint32_t (*pins)[2], uint32_t grid)
{
    *cloth = cvk_default_cloth_desc();
    cloth->grid[0] = cloth->grid[1] = grid;
    cloth->stiffness.structural = 1e4f;
    cloth->stiffness.shear = 1e3f;
    cloth->stiffness.bend = 1e1f;
    pins[0][0] = 0;
    pins[0][1] = 0;
    pins[1][0] = grid - 1;
    pins[1][1] = 0;
    cloth->pins = (const uint32_t(*)[2])pins;
    cloth->pin_count = 2;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloth;
    scene.cloth_count = 1;
    scene.dt = 1.0f / 60.0f;
    scene.substeps = 1;
    scene.solver.method = CVK_METHOD_IMPLICIT;
    scene.solver.linear = CVK_LINEAR_CG;
    scene.solver.kd = 0.5f;
    return scene;
}

/* Pinned particles are filtered out of the system: they keep their exact bits. */
static void pins_stay(cvk_context* ctx, cvk_linear_solver linear)
{
    cvk_cloth_desc cloth;
    uint32_t pins[2][2];
    cvk_scene_desc scene = hanging_scene(&cloth, pins, 8);
    scene.solver.linear = linear;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    float* before = harness_read_all(sim);
    REQUIRE_OK(cvk_sim_step(sim, 50, &err), err);
    float* after = harness_read_all(sim);
    uint32_t corners[2] = {0, 7};
    for (int i = 0; i < 2; i++)
        for (int c = 0; c < 3; c++)
            CHECK(before[3 * corners[i] + c] == after[3 * corners[i] + c],
                  "%s: pin %u moved from %.9g to %.9g", cvk_linear_solver_name(linear),
                  corners[i], before[3 * corners[i] + c], after[3 * corners[i] + c]);
    CHECK(harness_max_diff(before, after, 3 * 64) > 0.01, "%s: the cloth did not fall",
          cvk_linear_solver_name(linear));
    free(before);
    free(after);
    cvk_sim_destroy(sim);
}

/* Seed 000 §6.1 lost particles to NaN when a 3×3 diagonal block became singular. Springs
   compressed to a tenth of their rest length have transverse stiffness k (1 − L/l) = −9 k:
   without the clamp the system is indefinite. */
static cvk_scene_desc compressed_scene(cvk_cloth_desc* cloth)
{
    *cloth = cvk_default_cloth_desc();
    cloth->grid[0] = cloth->grid[1] = 5;
    cloth->stiffness.structural = 1e4f;
    cloth->stiffness.shear = 1e4f;
    cloth->stiffness.bend = 1e3f;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloth;
    scene.cloth_count = 1;
    scene.dt = 0.02f;
    scene.substeps = 1;
    scene.solver.method = CVK_METHOD_IMPLICIT;
    scene.solver.linear = CVK_LINEAR_CG;
    scene.solver.tolerance = 1e-6f;
    scene.solver.max_iterations = 200;
    return scene;
}

/* Positions of the build squeezed to a tenth around their centre, with a small random
   wrinkle so that the transverse directions are excited. */
static void squeeze(const cvk_build* b, double* x)
{
    harness_rng rng = {77u};
    double centre[3] = {0, 0, 0};
    for (uint32_t p = 0; p < b->particle_count; p++)
        for (int c = 0; c < 3; c++)
            centre[c] += b->position[3 * p + c] / b->particle_count;
    for (uint32_t p = 0; p < b->particle_count; p++)
        for (int c = 0; c < 3; c++)
            x[3 * p + c] = centre[c] + 0.1 * (b->position[3 * p + c] - centre[c]) +
                           harness_uniform(&rng, -1e-3, 1e-3);
}

static bool all_finite(const double* a, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(a[i]))
            return false;
    return true;
}

/* Host: substeps until something is not finite (or `substeps`); returns how many ran. */
static uint32_t host_run(const cvk_build* b, cvk_implicit_params* ip, uint32_t substeps,
                         bool* breakdown, bool* finite)
{
    size_t n3 = 3 * (size_t)b->particle_count;
    double* x = malloc(n3 * sizeof(double));
    double* v = calloc(n3, sizeof(double));
    squeeze(b, x);
    *breakdown = false;
    *finite = true;
    uint32_t s = 0;
    for (; s < substeps && *finite; s++) {
        cvk_implicit_report rep;
        cvk_ref_implicit_substep(b, ip, x, v, &rep);
        *breakdown = *breakdown || rep.breakdown;
        *finite = all_finite(x, n3) && all_finite(v, n3);
    }
    free(x);
    free(v);
    return s;
}

static void compression(cvk_context* ctx)
{
    cvk_cloth_desc cloth;
    cvk_scene_desc scene = compressed_scene(&cloth);
    cvk_error err;
    cvk_build b;
    REQUIRE_OK(cvk_build_create(&scene, &b, &err), err);
    bool breakdown, finite;
    cvk_step_params step_params = cvk_step_params_of(&scene);
    cvk_implicit_params ip = cvk_implicit_params_of(&step_params, &scene.solver);

    ip.clamp = false;
    host_run(&b, &ip, 1, &breakdown, &finite);
    CHECK(breakdown, "unclamped CG on compressed springs did not meet pᵀAp <= 0");
    ip.linear = CVK_LINEAR_JACOBI;
    host_run(&b, &ip, 1, &breakdown, &finite);
    CHECK(breakdown, "unclamped Jacobi on compressed springs found the blocks positive definite");
    printf("unclamped: CG and Jacobi break down in the first substep\n");

    ip.clamp = true;
    for (int j = 0; j < 2; j++) {
        ip.linear = j ? CVK_LINEAR_JACOBI : CVK_LINEAR_CG;
        host_run(&b, &ip, 50, &breakdown, &finite);
        CHECK(finite && !breakdown, "clamped %s: finite %d, breakdown %d",
              cvk_linear_solver_name(ip.linear), finite, breakdown);
    }

    /* The device, clamped, from the same squeezed start. */
    for (int j = 0; j < 2; j++) {
        scene.solver.linear = j ? CVK_LINEAR_JACOBI : CVK_LINEAR_CG;
        cvk_sim* sim;
        REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
        size_t n = b.particle_count;
        double* x = malloc(3 * n * sizeof(double));
        float* user = malloc(3 * n * sizeof(float));
        squeeze(&b, x);
        for (uint32_t p = 0; p < n; p++)
            for (int c = 0; c < 3; c++)
                user[3 * b.user_of[p] + c] = (float)x[3 * p + c];
        REQUIRE_OK(cvk_sim_write_positions(sim, user, n, &err), err);
        REQUIRE_OK(cvk_sim_step(sim, 50, &err), err);
        cvk_sim_stats st;
        REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
        CHECK(st.nan_count == 0 && st.solver_breakdowns == 0,
              "device %s on compressed springs: %llu NaN, %u breakdowns",
              cvk_linear_solver_name(scene.solver.linear), (unsigned long long)st.nan_count,
              st.solver_breakdowns);
        free(x);
        free(user);
        cvk_sim_destroy(sim);
    }
    cvk_build_destroy(&b);
}

/* A hanging cloth with spring damping: the energy never grows (backward Euler dissipates),
   and the cloth comes to rest. */
static void energy_and_rest(cvk_context* ctx)
{
    cvk_cloth_desc cloth;
    uint32_t pins[2][2];
    cvk_scene_desc scene = hanging_scene(&cloth, pins, 10);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    harness_energy_run run = harness_energy_watch(sim, 1000);
    cvk_sim_stats st = run.end;
    double start = run.start;
    CHECK(run.rises == 0, "the energy grew in %u of 1000 frames, by up to %g J (scale %g J)",
          run.rises, run.worst_rise, fabs(start));
    CHECK(st.kinetic_energy < 1e-5 * fabs(start),
          "after 1000 frames the kinetic energy is %g J (scale %g J): not at rest",
          st.kinetic_energy, fabs(start));
    CHECK(st.nan_count == 0 && st.solver_breakdowns == 0, "%llu NaN, %u breakdowns",
          (unsigned long long)st.nan_count, st.solver_breakdowns);
    printf("hanging 10x10 at h = 1/60: energy %g -> %g J, kinetic %g J, max stretch %.3g %%\n",
           start, st.energy, st.kinetic_energy, 100 * st.max_stretch);
    cvk_sim_destroy(sim);
}

/* cvk_sim_set_solver moves the state between families: pd -> implicit -> pd keeps the
   positions exactly and the velocities to float rounding; and it takes implicit where the
   scene has a collider (the implicit family filters collider contact) and steps on. */
static void switch_families(cvk_context* ctx)
{
    cvk_cloth_desc cloth;
    uint32_t pins[2][2];
    cvk_scene_desc scene = hanging_scene(&cloth, pins, 8);
    scene.solver.method = CVK_METHOD_PD;
    scene.solver.linear = CVK_LINEAR_RBGS;
    float kd = scene.solver.kd;
    scene.solver.kd = 0.0f; /* a key of implicit, not pd */
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 20, &err), err);
    float x0[3 * 64], v0[3 * 64], x1[3 * 64], v1[3 * 64];
    REQUIRE_OK(cvk_sim_read_state(sim, x0, v0, 64, &err), err);
    cvk_solver_desc implicit = scene.solver;
    implicit.method = CVK_METHOD_IMPLICIT;
    implicit.linear = CVK_LINEAR_CG;
    implicit.kd = kd;
    REQUIRE_OK(cvk_sim_set_solver(sim, &implicit, &err), err);
    REQUIRE_OK(cvk_sim_read_state(sim, x1, v1, 64, &err), err);
    double speed = 0.0;
    for (int i = 0; i < 3 * 64; i++)
        speed = fmax(speed, fabs(v0[i]));
    CHECK(harness_max_diff(x0, x1, 3 * 64) == 0.0 && harness_max_diff(v0, v1, 3 * 64) <= 1e-6 * speed,
          "pd -> implicit: positions moved by %g m, velocities by %g m/s (speed %g m/s)",
          harness_max_diff(x0, x1, 3 * 64), harness_max_diff(v0, v1, 3 * 64), speed);
    CHECK(speed > 0.01, "the cloth is not moving (%g m/s): the check is void", speed);
    REQUIRE_OK(cvk_sim_step(sim, 5, &err), err);
    REQUIRE_OK(cvk_sim_read_state(sim, x0, v0, 64, &err), err);
    REQUIRE_OK(cvk_sim_set_solver(sim, &scene.solver, &err), err);
    REQUIRE_OK(cvk_sim_read_state(sim, x1, v1, 64, &err), err);
    CHECK(harness_max_diff(x0, x1, 3 * 64) == 0.0 && harness_max_diff(v0, v1, 3 * 64) <= 1e-3 * speed,
          "implicit -> pd: positions moved by %g m, velocities by %g m/s",
          harness_max_diff(x0, x1, 3 * 64), harness_max_diff(v0, v1, 3 * 64));
    cvk_sim_destroy(sim);

    cvk_collider_desc plane = cvk_default_collider_desc();
    scene.colliders = &plane;
    scene.collider_count = 1;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    /* Colliders are filtered (tests/solvers/test_implicit_contact.c): the switch is taken. */
    REQUIRE_OK(cvk_sim_set_solver(sim, &implicit, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 2, &err), err);
    cvk_sim_destroy(sim);
}

int main(void)
{
    scene_keys();
    cvk_context* ctx = harness_context();
    device_equals_reference(ctx, CVK_LINEAR_CG);
    device_equals_reference(ctx, CVK_LINEAR_JACOBI);
    pins_stay(ctx, CVK_LINEAR_CG);
    pins_stay(ctx, CVK_LINEAR_JACOBI);
    compression(ctx);
    energy_and_rest(ctx);
    switch_families(ctx);
    return harness_finish(ctx);
}
