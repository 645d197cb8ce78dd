/* The explicit family (lib/solvers/solve_explicit.c, shaders/explicit_*.comp):
   - the scene keys, their defaults and messages;
   - every integrator on the device equals the host double-precision reference (both damping
     models) over 8 substeps of a small random cloth;
   - for a single spring, each integrator's largest stable step, found by bisection on device
     runs, is within 10 % of the analytic limit from the eigenvalues and the method's stability
     region;
   - a diverging explicit run is reported as CVK_ERROR_DIVERGED with its message, never as
     success, and stops with finite positions;
   - the energy of a damped run does not grow;
   - a snapshot resumes Adams-Bashforth bit for bit. */
#include <float.h>

#include "topology/build.h"
#include "harness.h"
#include "solvers/solve_explicit.h"

/* Float rounding over 8 substeps: 1e-4 of the largest displacement (the force's rounding)
   plus 4 ulp of the largest coordinate per substep (a position rounds each time it moves).
   One integrator against another differs by far more (checked). */
#define SAME_TO_ROUNDING 1e-4
#define ULPS_PER_SUBSTEP 4.0

static const cvk_integrator integrators[] = {CVK_INTEGRATOR_EULER, CVK_INTEGRATOR_RK2,
                                             CVK_INTEGRATOR_AB4, CVK_INTEGRATOR_VERLET};

static void scene_keys(void)
{
    cvk_scene* scene = NULL;
    cvk_error err;
    REQUIRE_OK(cvk_scene_parse("{\"solver\": {\"method\": \"explicit\", \"integrator\": "
                               "\"adams-bashforth\", \"damping_model\": \"viscosity\", \"kd\": "
                               "0.25}, \"cloths\": [{}]}", "t.json", NULL, 0, &scene, &err), err);
    const cvk_solver_desc* s = &cvk_scene_get_desc(scene)->solver;
    CHECK(s->method == CVK_METHOD_EXPLICIT && s->integrator == CVK_INTEGRATOR_AB4 &&
              s->damping_model == CVK_DAMPING_VISCOSITY && s->kd == 0.25f,
          "method %d integrator %d damping model %d kd %g", s->method, s->integrator,
          s->damping_model, s->kd);
    cvk_scene_destroy(scene);
    cvk_scene_desc d = cvk_default_scene_desc();
    cvk_step_params step_params = cvk_step_params_of(&d);
    cvk_explicit_params ep = cvk_explicit_params_of(&step_params, &d.solver);
    CHECK(d.solver.integrator == CVK_INTEGRATOR_NONE && d.solver.damping_model == CVK_DAMPING_NONE &&
              ep.integrator == CVK_INTEGRATOR_EULER && ep.damping_model == CVK_DAMPING_SPRING,
          "defaults: integrator %d (%d), damping model %d (%d)", d.solver.integrator,
          ep.integrator, d.solver.damping_model, ep.damping_model);
    CHECK(!strcmp(cvk_integrator_name(CVK_INTEGRATOR_RK2), "rk2") &&
              !strcmp(cvk_damping_model_name(CVK_DAMPING_SPRING), "spring") &&
              !strcmp(cvk_method_name(CVK_METHOD_EXPLICIT), "explicit"),
          "names");

    harness_expect_scene_message("{\"solver\": {\"method\": \"explicit\", \"integrator\": \"rk4\"}, "
                   "\"cloths\": [{}]}",
                   "t.json: solver.integrator: unknown integrator \"rk4\" (expected euler, rk2, "
                   "adams-bashforth or verlet)");
    harness_expect_scene_message("{\"solver\": {\"method\": \"explicit\", \"damping_model\": \"none\"}, "
                   "\"cloths\": [{}]}",
                   "t.json: solver.damping_model: unknown damping model \"none\" (expected "
                   "spring or viscosity)");
    harness_expect_scene_message("{\"solver\": {\"integrator\": \"rk2\"}, \"cloths\": [{}]}",
                   "t.json: solver.integrator: is a key of the explicit method; remove it or set "
                   "\"method\": \"explicit\" (method is pd)");
    harness_expect_scene_message("{\"solver\": {\"method\": \"implicit\", \"linear\": \"cg\", "
                   "\"damping_model\": \"spring\"}, \"cloths\": [{}]}",
                   "t.json: solver.damping_model: is a key of the explicit method; remove it or "
                   "set \"method\": \"explicit\" (method is implicit)");
    harness_expect_scene_message("{\"solver\": {\"kd\": 2}, \"cloths\": [{}]}",
                   "t.json: solver.kd: is a key of the implicit and explicit methods; pd damps "
                   "with \"damping\" (remove kd or change the method)");
    harness_expect_scene_message("{\"solver\": {\"method\": \"explicit\", \"kd\": -1}, \"cloths\": [{}]}",
                   "t.json: solver.kd: must be at least 0, got -1");
    harness_expect_scene_message("{\"solver\": {\"method\": \"explicit\", \"linear\": \"jacobi\"}, "
                   "\"cloths\": [{}]}",
                   "t.json: solver.linear: the explicit method solves no linear system; remove "
                   "\"linear\" (got jacobi)");
    harness_expect_scene_message("{\"solver\": {\"method\": \"explicit\"}, \"colliders\": [{\"type\": "
                   "\"plane\"}], \"cloths\": [{}]}",
                   "t.json: solver.method: explicit does not handle contact; remove "
                   "\"colliders\" and \"collision.self\", or use pd");
}

/* ---- the device against the host reference ----------------------------------------------- */

typedef struct random_cloth {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    uint32_t pins[3][2];
} random_cloth;

static void make_random_cloth(harness_rng* rng, random_cloth* rc)
{
    rc->cloth = cvk_default_cloth_desc();
    rc->cloth.grid[0] = 3 + harness_next(rng) % 6;
    rc->cloth.grid[1] = 3 + harness_next(rng) % 6;
    rc->cloth.size[0] = (float)harness_uniform(rng, 0.3, 1.0);
    rc->cloth.size[1] = (float)harness_uniform(rng, 0.3, 1.0);
    rc->cloth.mass = 1.0f;
    rc->cloth.stiffness.structural = (float)harness_uniform(rng, 1e2, 1e3);
    rc->cloth.stiffness.shear = harness_next(rng) % 2 ? (float)harness_uniform(rng, 1e1, 1e2) : 0.0f;
    rc->cloth.stiffness.bend = harness_next(rng) % 2 ? (float)harness_uniform(rng, 1e0, 1e1) : 0.0f;
    rc->cloth.rest_scale = (float)harness_uniform(rng, 0.9, 1.1);
    uint32_t pins = 1 + harness_next(rng) % 2;
    for (uint32_t p = 0; p < pins; p++) {
        rc->pins[p][0] = harness_next(rng) % rc->cloth.grid[0];
        rc->pins[p][1] = harness_next(rng) % rc->cloth.grid[1];
    }
    rc->cloth.pins = (const uint32_t(*)[2])rc->pins;
    rc->cloth.pin_count = pins;
    rc->scene = cvk_default_scene_desc();
    rc->scene.cloths = &rc->cloth;
    rc->scene.cloth_count = 1;
    rc->scene.substeps = 8;
    rc->scene.dt = 4e-4f;
    rc->scene.damping = (float)harness_uniform(rng, 0.0, 0.02);
    rc->scene.solver.method = CVK_METHOD_EXPLICIT;
    rc->scene.solver.kd = (float)harness_uniform(rng, 0.0, 0.5);
}

/* The same frame on the host; positions (user order) into hx. */
static void host_frame(const cvk_scene_desc* scene, const float* xyz, const float* v, double* hx)
{
    cvk_error err;
    cvk_build b;
    REQUIRE_OK(cvk_build_create(scene, &b, &err), err);
    cvk_explicit_host st;
    CHECK(cvk_ref_explicit_init(&b, &st), "out of memory");
    for (uint32_t p = 0; p < b.particle_count; p++)
        for (int c = 0; c < 3; c++) {
            st.x[3 * p + c] = xyz[3 * b.user_of[p] + c];
            st.v[3 * p + c] = p < b.free_count ? v[3 * b.user_of[p] + c] : 0.0;
        }
    cvk_step_params step_params = cvk_step_params_of(scene);
    cvk_explicit_params ep = cvk_explicit_params_of(&step_params, &scene->solver);
    for (uint32_t s = 0; s < scene->substeps; s++)
        CHECK(cvk_ref_explicit_substep(&b, &ep, &st), "out of memory");
    for (uint32_t p = 0; p < b.particle_count; p++)
        for (int c = 0; c < 3; c++)
            hx[3 * b.user_of[p] + c] = st.x[3 * p + c];
    cvk_ref_explicit_free(&st);
    cvk_build_destroy(&b);
}

/* Largest |a − b| over what float rounding allows (see SAME_TO_ROUNDING): below 1 is a match. */
static double rounding_ratio(const float* a, const double* b, const float* before, size_t n,
                             uint32_t substeps)
{
    double diff = 0.0, scale = 1e-30, coordinate = 0.0;
    for (size_t i = 0; i < n; i++) {
        double d = fabs(a[i] - b[i]);
        diff = isnan(d) || d > diff ? d : diff;
        scale = fmax(scale, fabs(b[i] - before[i]));
        coordinate = fmax(coordinate, fabs(b[i]));
    }
    return diff / (SAME_TO_ROUNDING * scale + ULPS_PER_SUBSTEP * substeps * FLT_EPSILON * coordinate);
}

static void device_equals_reference(cvk_context* ctx, cvk_damping_model model)
{
    harness_rng rng = {0x9e3779b9u + (uint32_t)model};
    double worst = 0.0, closest_other = INFINITY;
    for (int trial = 0; trial < 3; trial++) {
        random_cloth rc;
        make_random_cloth(&rng, &rc);
        rc.scene.solver.damping_model = model;
        uint64_t n = (uint64_t)rc.cloth.grid[0] * rc.cloth.grid[1];
        float *x0, *v0;
        harness_random_start(ctx, &rc.scene, &rng, 0.03, 2.0, n, &x0, &v0);
        float* x = malloc(3 * n * sizeof(float));
        float* v = malloc(3 * n * sizeof(float));
        double* hx[4];
        for (size_t k = 0; k < 4; k++) {
            hx[k] = malloc(3 * n * sizeof(double));
            rc.scene.solver.integrator = integrators[k];
            memcpy(x, x0, 3 * n * sizeof(float));
            memcpy(v, v0, 3 * n * sizeof(float));
            harness_frame_from(ctx, &rc.scene, x, v, NULL);
            host_frame(&rc.scene, x0, v0, hx[k]);
            double dx = rounding_ratio(x, hx[k], x0, 3 * n, rc.scene.substeps);
            worst = fmax(worst, dx);
            CHECK(dx < 1.0, "%s, %s damping, trial %d (%ux%u, %u pins): positions differ by "
                  "%g times float rounding", cvk_integrator_name(integrators[k]),
                  cvk_damping_model_name(model), trial, rc.cloth.grid[0], rc.cloth.grid[1],
                  rc.cloth.pin_count, dx);
            /* The comparison can fail: each integrator is far from every other. */
            for (size_t j = 0; j < k; j++) {
                float* other = malloc(3 * n * sizeof(float));
                for (uint64_t i = 0; i < 3 * n; i++)
                    other[i] = (float)hx[j][i];
                closest_other = fmin(closest_other, rounding_ratio(other, hx[k], x0, 3 * n,
                                                                   rc.scene.substeps));
                free(other);
            }
        }
        CHECK(closest_other > 10.0, "two integrators differ by only %g times float rounding",
              closest_other);
        for (size_t k = 0; k < 4; k++)
            free(hx[k]);
        free(x0);
        free(v0);
        free(x);
        free(v);
    }
    printf("%s damping: device vs host, largest difference %.3g times float rounding; "
           "integrators at least %.3g times apart\n", cvk_damping_model_name(model), worst,
           closest_other);
}

/* ---- stability limits of a single spring ------------------------------------------------- *
 * A particle of mass m on a spring (stiffness k, rest length L) whose other end is pinned,
 * moving along the spring with no gravity: d'' = −ω² d − c d', d = l − L, ω² = k/m, c = kd/m
 * (damping along the spring). As a first-order system y = (d, d'), y' = J y, the eigenvalues
 * of J are s = −c/2 ± √(c²/4 − ω²). A one-step or multistep method applied to y' = J y is
 * stable while h·s lies in its stability region for both s:
 *   forward Euler, R(z) = 1 + z: underdamped (c < 2ω), |1 + h s|² = 1 − h c + h² ω² ≤ 1
 *     ⇔ h ≤ c/ω² = kd/k;
 *   TVD-RK2 (Shu-Osher; R(z) = 1 + z + z²/2, Heun's polynomial): on the real axis |R| ≤ 1
 *     for −2 ≤ z ≤ 0, so overdamped (c = 10 ω, real s): h ≤ 2/|s_fast|;
 *   Adams-Bashforth 4: ρ(ζ) − z σ(ζ) with ρ = ζ⁴ − ζ³, σ = (55ζ³ − 59ζ² + 37ζ − 9)/24 has a
 *     root ζ = −1 when 2 + 20z/3 = 0: the region meets the real axis at z = −3/10, so
 *     overdamped: h ≤ 0.3/|s_fast| (seed 001's "−3/10");
 *   position Verlet, undamped (kd = 0): d_n+1 − 2 d_n + d_n−1 = −h² ω² d_n has both roots of
 *     ζ² − (2 − h²ω²) ζ + 1 on the unit circle iff |2 − h² ω²| ≤ 2 ⇔ h ≤ 2/ω.
 * The device run is stable when its amplitude √(d² + (d'/ω)²) over its last 200 substeps
 * (the largest of four samples) stays below 30 times its start, v0/ω: an unstable run grows
 * by far more within 1000 substeps (until the particle swings through the pin, which bounds
 * it at about L), and Verlet's neutral oscillation near its limit swings the amplitude by up
 * to √((1 + hω/2)/(1 − hω/2)), about 10. The limit is bisected between 0.7 and 1.3 times the
 * analytic one, to 2 %. */

#define SPRING_K 100.0
#define SPRING_M 0.1
#define SPRING_V0 0.01 /* m/s along the spring, the start */

typedef struct spring_case {
    cvk_integrator integrator;
    double kd;
    double limit; /* analytic, s */
} spring_case;

static cvk_scene_desc spring_scene(cvk_cloth_desc* cloth, uint32_t (*pin)[2], cvk_integrator i,
                                   double kd, double h)
{
    *cloth = cvk_default_cloth_desc();
    cloth->grid[0] = 2;
    cloth->grid[1] = 1;
    cloth->size[0] = cloth->size[1] = 1.0f;
    cloth->mass = (float)(2 * SPRING_M);
    cloth->stiffness = (cvk_stiffness){.structural = (float)SPRING_K};
    pin[0][0] = pin[0][1] = 0;
    cloth->pins = (const uint32_t(*)[2])pin;
    cloth->pin_count = 1;
    cloth->velocity[0] = (float)SPRING_V0;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloth;
    scene.cloth_count = 1;
    scene.gravity[1] = 0.0f;
    scene.dt = (float)h;
    scene.substeps = 50;
    scene.solver.method = CVK_METHOD_EXPLICIT;
    scene.solver.integrator = i;
    scene.solver.kd = (float)kd;
    return scene;
}

static double spring_amplitude(cvk_sim* sim)
{
    float x[6], v[6];
    cvk_error err;
    REQUIRE_OK(cvk_sim_read_state(sim, x, v, 2, &err), err);
    double d = x[3] - x[0] - 1.0, speed = v[3] / sqrt(SPRING_K / SPRING_M);
    return sqrt(d * d + speed * speed);
}

/* Whether the spring stays bounded at step h (20 frames of 50 substeps). */
static bool spring_stable(cvk_context* ctx, const spring_case* sc, double h)
{
    cvk_cloth_desc cloth;
    uint32_t pin[1][2];
    cvk_scene_desc scene = spring_scene(&cloth, pin, sc->integrator, sc->kd, h);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    double start = SPRING_V0 / sqrt(SPRING_K / SPRING_M), end = 0.0;
    bool diverged = false;
    for (int f = 0; f < 20 && !diverged; f++) {
        cvk_result r = cvk_sim_step(sim, 1, &err);
        diverged = r == CVK_ERROR_DIVERGED;
        CHECK(r == CVK_SUCCESS || diverged, "spring at h = %g: %s", h, err.message);
        if (f >= 16 && !diverged)
            end = fmax(end, spring_amplitude(sim));
    }
    cvk_sim_destroy(sim);
    return !diverged && isfinite(end) && end <= 30.0 * start;
}

static void spring_limits(cvk_context* ctx)
{
    double omega = sqrt(SPRING_K / SPRING_M);
    double c_over = 10.0 * omega; /* overdamped: c = 10 ω */
    double s_fast = c_over / 2 + sqrt(c_over * c_over / 4 - omega * omega);
    double kd_under = omega * SPRING_M; /* underdamped: c = ω */
    const spring_case cases[] = {
        {CVK_INTEGRATOR_EULER, kd_under, kd_under / SPRING_K},
        {CVK_INTEGRATOR_RK2, c_over * SPRING_M, 2.0 / s_fast},
        {CVK_INTEGRATOR_AB4, c_over * SPRING_M, 0.3 / s_fast},
        {CVK_INTEGRATOR_VERLET, 0.0, 2.0 / omega},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const spring_case* sc = &cases[i];
        const char* name = cvk_integrator_name(sc->integrator);
        double lo = 0.7 * sc->limit, hi = 1.3 * sc->limit;
        bool lo_ok = spring_stable(ctx, sc, lo), hi_ok = spring_stable(ctx, sc, hi);
        CHECK(lo_ok && !hi_ok, "%s: stable at 0.7x the analytic limit: %d, at 1.3x: %d", name,
              lo_ok, hi_ok);
        while (hi - lo > 0.02 * sc->limit) {
            double mid = 0.5 * (lo + hi);
            if (spring_stable(ctx, sc, mid))
                lo = mid;
            else
                hi = mid;
        }
        double measured = 0.5 * (lo + hi);
        CHECK(fabs(measured / sc->limit - 1.0) < 0.1,
              "%s: largest stable step %.4g ms, analytic %.4g ms (%.1f %% off)", name,
              1e3 * measured, 1e3 * sc->limit, 100 * (measured / sc->limit - 1.0));
        printf("single spring, %s (kd %.3g N s/m): largest stable step %.4g ms, analytic %.4g ms "
               "(%+.1f %%)\n", name, sc->kd, 1e3 * measured, 1e3 * sc->limit,
               100 * (measured / sc->limit - 1.0));
    }
}

/* ---- divergence and energy ---------------------------------------------------------------- */

static cvk_scene_desc hanging_scene(cvk_cloth_desc* cloth, uint32_t (*pins)[2], double h)
{
    *cloth = cvk_default_cloth_desc();
    cloth->grid[0] = cloth->grid[1] = 8;
    cloth->stiffness.structural = 1e3f;
    cloth->stiffness.shear = 1e2f;
    cloth->stiffness.bend = 1e1f;
    pins[0][0] = pins[0][1] = pins[1][1] = 0;
    pins[1][0] = 7;
    cloth->pins = (const uint32_t(*)[2])pins;
    cloth->pin_count = 2;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloth;
    scene.cloth_count = 1;
    scene.dt = (float)h;
    scene.substeps = 20;
    scene.solver.method = CVK_METHOD_EXPLICIT;
    scene.solver.kd = 0.05f;
    return scene;
}

/* Forward Euler far past its limit: the step fails with CVK_ERROR_DIVERGED and the watch's
   sentence, the statistics say so, and the positions stop where they were still finite. */
static void divergence(cvk_context* ctx)
{
    cvk_cloth_desc cloth;
    uint32_t pins[2][2];
    cvk_scene_desc scene = hanging_scene(&cloth, pins, 5e-3);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    cvk_result r = cvk_sim_step(sim, 10, &err);
    char said[sizeof err.message];
    snprintf(said, sizeof said, "%s", err.message);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    CHECK(st.diverged && st.nan_count == 0 && !st.diverged_nonfinite && st.diverged_cloth == 0,
          "diverged %d (non-finite %d, cloth %u), %llu NaN", st.diverged, st.diverged_nonfinite,
          st.diverged_cloth, (unsigned long long)st.nan_count);
    /* The watch's sentence for the frame the statistics name, the one cloth (named by the
       scene's default) caught moving too fast or stretched, not yet non-finite. */
    char expected[sizeof err.message];
    snprintf(expected, sizeof expected,
             "the simulation diverged in frame %llu: a particle moved faster than 10000 m/s or a "
             "spring stretched past ten times its rest length in cloth 0 (\"cloth0\"); positions "
             "stopped advancing there (a smaller dt, more substeps or iterations, or softer "
             "springs)", (unsigned long long)st.diverged_frame);
    CHECK(r == CVK_ERROR_DIVERGED && strcmp(said, expected) == 0,
          "euler at 5 ms: result %d, \"%s\", expected \"%s\"", r, said, expected);
    printf("euler at 5 ms: %s\n", err.message);
    cvk_sim_destroy(sim);

    /* The same cloth at a stable step is a success (the check above can fail). */
    scene.dt = 1e-4f;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
    cvk_sim_destroy(sim);
}

/* A damped hanging cloth released from flat, at a tenth of a millisecond: the energy never
   grows from one frame to the next, for every integrator. */
static void damped_energy(cvk_context* ctx)
{
    for (size_t k = 0; k < 4; k++) {
        cvk_cloth_desc cloth;
        uint32_t pins[2][2];
        cvk_scene_desc scene = hanging_scene(&cloth, pins, 1e-4);
        scene.solver.integrator = integrators[k];
        if (integrators[k] == CVK_INTEGRATOR_EULER)
            scene.solver.damping_model = CVK_DAMPING_VISCOSITY;
        cvk_error err;
        cvk_sim* sim;
        REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
        harness_energy_run run = harness_energy_watch(sim, 150);
        const char* name = cvk_integrator_name(integrators[k]);
        CHECK(run.rises == 0, "%s: the energy grew in %u of 150 frames, by up to %g J (scale "
              "%g J)", name, run.rises, run.worst_rise, fabs(run.start));
        CHECK(run.start - run.end.energy > 1e-3 * fabs(run.start),
              "%s: the energy fell only from %g to %g J", name, run.start, run.end.energy);
        printf("%s (%s damping), damped hanging cloth: energy %g -> %g J over 150 frames\n",
               name, cvk_damping_model_name(scene.solver.damping_model ? scene.solver.damping_model
                                                                       : CVK_DAMPING_SPRING),
               run.start, run.end.energy);
        cvk_sim_destroy(sim);
    }
}

/* A snapshot holds the Adams-Bashforth history: stepping on from a loaded one gives the bits
   the saved simulation gives, and without the history (a state written instead, which starts
   the Euler steps again) it does not (the check can fail). */
static void snapshot_resumes(cvk_context* ctx)
{
    cvk_cloth_desc cloth;
    uint32_t pins[2][2];
    cvk_scene_desc scene = hanging_scene(&cloth, pins, 1e-4);
    scene.solver.integrator = CVK_INTEGRATOR_AB4;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 3, &err), err);
    uint64_t size = cvk_sim_snapshot_size(sim);
    void* snap = malloc(size);
    REQUIRE_OK(cvk_sim_save_snapshot(sim, snap, size, &err), err);
    float x0[3 * 64], v0[3 * 64], a[3 * 64], b[3 * 64], c[3 * 64];
    REQUIRE_OK(cvk_sim_read_state(sim, x0, v0, 64, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 2, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(sim, a, 64, &err), err);
    REQUIRE_OK(cvk_sim_load_snapshot(sim, snap, size, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 2, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(sim, b, 64, &err), err);
    CHECK(memcmp(a, b, sizeof a) == 0, "adams-bashforth from a snapshot: positions differ by "
          "%g m", harness_max_diff(a, b, 3 * 64));
    REQUIRE_OK(cvk_sim_write_state(sim, x0, v0, 64, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 2, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(sim, c, 64, &err), err);
    CHECK(harness_max_diff(a, c, 3 * 64) > 0.0, "restarting from Euler steps changes nothing");
    free(snap);
    cvk_sim_destroy(sim);
}

int main(void)
{
    scene_keys();
    cvk_context* ctx = harness_context();
    device_equals_reference(ctx, CVK_DAMPING_SPRING);
    device_equals_reference(ctx, CVK_DAMPING_VISCOSITY);
    spring_limits(ctx);
    divergence(ctx);
    damped_energy(ctx);
    snapshot_resumes(ctx);
    return harness_finish(ctx);
}
