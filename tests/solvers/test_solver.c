/* The GPU solvers against the host reference:
   - rbgs on the GPU equals gs-cpu (sequential double-precision Gauss-Seidel in the same colour
     order) to float rounding, on random small grids, stencils, pins, omega and iteration counts;
   - GPU jacobi and chebyshev equal the host Jacobi / Chebyshev iteration; the Chebyshev
     weights that both take (cvk_chebyshev_weight) equal the closed form
     w_j = 2 T_j(1/rho) / (rho T_j+1(1/rho)), and the stable rho over m sweeps solves
     T_m(1/rho) = 3;
   - the residual falls monotonically with iterations on enlarged.json, for rbgs and gs-cpu;
   - the converged solution of a substep by Newton's method equals Gauss-Seidel's fixed point;
   - rbgs's first sweep that predicts gives the bits of the prediction's own pass, and its
     last sweep that finalizes the bits of finalize's own pass. */
#include "topology/build.h"
#include "harness.h"
#include "solvers/solve_pd.h"
#include "solvers/reference.h"

/* Float rounding over one substep of up to 3 x 7 sweeps. The solver works on displacements,
   so its own rounding is tiny; what remains is reading positions of O(1) m back as floats,
   where an ulp is 6e-8 to 1.2e-7 m. Measured: at most 3 ulps (3.6e-7 m, SOR 1.5 over 8
   sweeps), mostly 1. A solver that differs (another omega, another order) misses the bound
   by orders of magnitude (checked below). Over many substeps of violently shaken cloth
   differences grow like any chaotic motion, so the comparison is per substep. */
#define SAME_TO_ROUNDING 5e-7

typedef struct random_scene {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    uint32_t pins[4][2];
} random_scene;

static void make_random_scene(harness_rng* rng, random_scene* rs)
{
    rs->cloth = cvk_default_cloth_desc();
    rs->cloth.grid[0] = 2 + harness_next(rng) % 20;
    rs->cloth.grid[1] = 2 + harness_next(rng) % 20;
    rs->cloth.size[0] = (float)harness_uniform(rng, 0.3, 1.5);
    rs->cloth.size[1] = (float)harness_uniform(rng, 0.3, 1.5);
    rs->cloth.stiffness.structural = (float)harness_uniform(rng, 1e3, 1e6);
    rs->cloth.stiffness.shear = harness_next(rng) % 2 ? (float)harness_uniform(rng, 1e3, 1e5) : 0.0f;
    rs->cloth.stiffness.bend = harness_next(rng) % 2 ? (float)harness_uniform(rng, 1e2, 1e4) : 0.0f;
    rs->cloth.rest_scale = (float)harness_uniform(rng, 0.8, 1.1);
    uint32_t pins = harness_next(rng) % 4;
    for (uint32_t p = 0; p < pins; p++) {
        rs->pins[p][0] = harness_next(rng) % rs->cloth.grid[0];
        rs->pins[p][1] = harness_next(rng) % rs->cloth.grid[1];
    }
    rs->cloth.pins = (const uint32_t(*)[2])rs->pins;
    rs->cloth.pin_count = pins;
    rs->scene = cvk_default_scene_desc();
    rs->scene.cloths = &rs->cloth;
    rs->scene.cloth_count = 1;
    rs->scene.substeps = 1;
    rs->scene.damping = (float)harness_uniform(rng, 0.0, 0.02);
    rs->scene.solver.outer_iterations = 1 + harness_next(rng) % 3;
    rs->scene.solver.inner_iterations = 1 + harness_next(rng) % 4;
    rs->scene.solver.omega = harness_next(rng) % 2 ? 1.0f : 1.5f;
}

/* Random initial positions: the grid shaken by up to 10% of its spacing. */
static float* shaken_positions(cvk_sim* sim, harness_rng* rng)
{
    float* xyz = harness_read_all(sim);
    uint64_t n = cvk_sim_particle_count(sim);
    for (uint64_t i = 0; i < 3 * n; i++)
        xyz[i] += (float)harness_uniform(rng, -0.01, 0.01);
    return xyz;
}

static float* run(cvk_context* ctx, const cvk_scene_desc* scene, const float* start, uint32_t frames)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_write_positions(sim, start, cvk_sim_particle_count(sim), &err), err);
    REQUIRE_OK(cvk_sim_step(sim, frames, &err), err);
    float* out = harness_read_all(sim);
    cvk_sim_destroy(sim);
    return out;
}

static void rbgs_equals_gs_cpu(cvk_context* ctx)
{
    harness_rng rng = {0x9e3779b9u};
    double worst = 0.0;
    for (int trial = 0; trial < 12; trial++) {
        random_scene rs;
        make_random_scene(&rng, &rs);
        cvk_error err;
        cvk_sim* probe;
        REQUIRE_OK(harness_sim_create(ctx, &rs.scene, &probe, &err), err);
        float* start = shaken_positions(probe, &rng);
        uint64_t n = cvk_sim_particle_count(probe);
        cvk_sim_destroy(probe);

        rs.scene.solver.linear = CVK_LINEAR_RBGS;
        float* gpu = run(ctx, &rs.scene, start, 1);
        rs.scene.solver.linear = CVK_LINEAR_GS_CPU;
        float* host = run(ctx, &rs.scene, start, 1);
        double diff = harness_max_diff(gpu, host, 3 * n);
        if (diff > worst)
            worst = diff;
        CHECK(diff < SAME_TO_ROUNDING,
              "trial %d (%ux%u, shear %g, bend %g, %u pins, omega %g, %ux%u iterations): rbgs and "
              "gs-cpu differ by %g m",
              trial, rs.cloth.grid[0], rs.cloth.grid[1], rs.cloth.stiffness.shear,
              rs.cloth.stiffness.bend, rs.cloth.pin_count, rs.scene.solver.omega,
              rs.scene.solver.outer_iterations, rs.scene.solver.inner_iterations, diff);

        /* The comparison must be able to fail: another omega gives other iterates. */
        if (trial == 0) {
            rs.scene.solver.omega = rs.scene.solver.omega == 1.0f ? 1.5f : 1.0f;
            float* other = run(ctx, &rs.scene, start, 1);
            double apart = harness_max_diff(gpu, other, 3 * n);
            CHECK(apart > 1000 * SAME_TO_ROUNDING,
                  "a different omega changed positions by only %g m", apart);
            printf("rbgs with another omega: %.3g m away\n", apart);
            free(other);
        }
        free(start);
        free(gpu);
        free(host);
    }
    printf("rbgs vs gs-cpu: largest difference %.3g m over 12 random scenes\n", worst);
}

/* Host Jacobi / Chebyshev over the same substeps as the GPU plan; the result ends in x. */
static void reference_jacobi(const cvk_build* b, const cvk_scene_desc* scene, double rho,
                             double* x, double* prev, uint32_t frames)
{
    size_t n = b->particle_count;
    double* y = calloc(3 * n, sizeof(double));
    double* rhs = calloc(4 * n, sizeof(double));
    double* buf[2] = {x, calloc(3 * n, sizeof(double))};
    uint32_t cur = 0;
    cvk_step_params step_params = cvk_step_params_of(scene);
    cvk_ref_params params = cvk_ref_params_of(&step_params);
    const cvk_solver_desc* s = &scene->solver;
    bool chebyshev = s->linear == CVK_LINEAR_CHEBYSHEV;
    for (uint32_t f = 0; f < frames * scene->substeps; f++) {
        cvk_ref_predict(b, &params, buf[cur], prev, y);
        /* the other array holds the iterate before the current one (and the pinned particles) */
        memcpy(buf[1 - cur], buf[cur], 3 * n * sizeof(double));
        uint32_t sweep = 0;
        for (uint32_t o = 0; o < s->outer_iterations; o++) {
            cvk_ref_rhs(b, &params, buf[cur], y, rhs);
            for (uint32_t i = 0; i < s->inner_iterations; i++, sweep++) {
                uint32_t cycle = cvk_sweep_cycle(s), c = sweep % cycle;
                double w = chebyshev ? cvk_chebyshev_weight(c, s->chebyshev_delay, rho) : 1.0;
                cvk_ref_jacobi_sweep(b, rhs, cvk_jacobi_sweep_omega(c, cycle, s->omega), w,
                                     buf[cur], buf[1 - cur]);
                cur = 1 - cur;
            }
        }
    }
    if (cur == 1)
        memcpy(x, buf[1], 3 * n * sizeof(double));
    free(buf[1]);
    free(y);
    free(rhs);
}

static void jacobi_equals_reference(cvk_context* ctx, cvk_linear_solver linear)
{
    harness_rng rng = {0x1234567u + (uint32_t)linear};
    const char* name = cvk_linear_solver_name(linear);
    for (int trial = 0; trial < 4; trial++) {
        random_scene rs;
        make_random_scene(&rng, &rs);
        rs.scene.solver.linear = linear;
        rs.scene.solver.omega = linear == CVK_LINEAR_CHEBYSHEV ? 0.9f : rs.scene.solver.omega * 0.6f;
        rs.scene.solver.inner_iterations = 2 + harness_next(&rng) % 6;
        cvk_error err;
        cvk_sim* sim;
        REQUIRE_OK(harness_sim_create(ctx, &rs.scene, &sim, &err), err);
        uint64_t n = cvk_sim_particle_count(sim);
        float* start = shaken_positions(sim, &rng);
        REQUIRE_OK(cvk_sim_write_positions(sim, start, n, &err), err);
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        float* gpu = harness_read_all(sim);
        cvk_sim_destroy(sim);

        cvk_build b;
        REQUIRE_OK(cvk_build_create(&rs.scene, &b, &err), err);
        double* x = malloc(3 * n * sizeof(double));
        double* prev = malloc(3 * n * sizeof(double));
        cvk_step_params step_params = cvk_step_params_of(&rs.scene);
        cvk_ref_params params = cvk_ref_params_of(&step_params);
        for (uint32_t p = 0; p < n; p++)
            for (int c = 0; c < 3; c++) {
                x[3 * p + c] = start[3 * b.user_of[p] + c];
                prev[3 * p + c] = x[3 * p + c] + (p < b.free_count ? 0.5 * params.gravity_h2[c] : 0.0);
            }
        double rho = cvk_pd_chebyshev_rho(&rs.scene.solver, rs.scene.dt, &b, -1.0, NULL);
        reference_jacobi(&b, &rs.scene, rho, x, prev, 1);
        double worst = 0.0;
        for (uint32_t p = 0; p < n; p++)
            for (int c = 0; c < 3; c++) {
                double d = fabs(x[3 * p + c] - gpu[3 * b.user_of[p] + c]);
                if (d > worst || isnan(d))
                    worst = d;
            }
        CHECK(worst < SAME_TO_ROUNDING, "%s trial %d (%ux%u, %ux%u iterations): GPU and host differ by %g m",
              name, trial, rs.cloth.grid[0], rs.cloth.grid[1], rs.scene.solver.outer_iterations,
              rs.scene.solver.inner_iterations, worst);
        cvk_build_destroy(&b);
        free(x);
        free(prev);
        free(start);
        free(gpu);
    }
}

/* One iteration per frame (one substep, one outer, one inner): the residual after each. */
static void residual_falls(cvk_context* ctx, cvk_linear_solver linear)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    char path[1024];
    snprintf(path, sizeof path, "%s/assets/scenes/enlarged.json", root ? root : ".");
    const char* overrides[] = {"substeps=1", "solver.outer_iterations=1", "solver.inner_iterations=1"};
    cvk_error err;
    cvk_scene* file;
    REQUIRE_OK(cvk_scene_load(path, overrides, 3, &file, &err), err);
    cvk_scene_desc scene = *cvk_scene_get_desc(file);
    scene.solver.linear = linear;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    double first = st.residual, last = st.residual;
    int rises = 0, iterations = 60;
    for (int k = 0; k < iterations; k++) {
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
        if (!(st.residual <= last))
            rises++;
        last = st.residual;
    }
    const char* name = cvk_linear_solver_name(linear);
    CHECK(rises == 0, "%s: the residual rose in %d of %d iterations", name, rises, iterations);
    /* Gauss-Seidel needs thousands of iterations here (seed 002 fig. 6.3); 60 must still
       show a clear fall, or a solver that does nothing would pass. */
    CHECK(last < 0.9 * first, "%s: the residual fell only from %g to %g in %d iterations", name,
          first, last, iterations);
    printf("%s on enlarged.json: residual %.4g -> %.4g in %d iterations\n", name, first, last, iterations);
    cvk_sim_destroy(sim);
    cvk_scene_destroy(file);
}

/* The converged solution of a substep: Newton on the substep energy and Gauss-Seidel run
   until it stops moving find the same point (PD's fixed points are E's stationary points). */
static void newton_equals_gauss_seidel(const char* name, const char* const* overrides,
                                       uint32_t override_count, uint32_t warm_substeps)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    char path[1024];
    snprintf(path, sizeof path, "%s/assets/scenes/%s", root ? root : ".", name);
    cvk_error err;
    cvk_scene* file;
    REQUIRE_OK(cvk_scene_load(path, overrides, override_count, &file, &err), err);
    const cvk_scene_desc* scene = cvk_scene_get_desc(file);
    cvk_build b;
    REQUIRE_OK(cvk_build_create(scene, &b, &err), err);
    size_t n = b.particle_count;
    double* x = malloc(3 * n * sizeof(double));
    double* prev = malloc(3 * n * sizeof(double));
    double* y = malloc(3 * n * sizeof(double));
    double* scratch = malloc(4 * n * sizeof(double));
    double* newton = malloc(3 * n * sizeof(double));
    cvk_step_params step_params = cvk_step_params_of(scene);
    cvk_ref_params params = cvk_ref_params_of(&step_params);
    for (size_t i = 0; i < 3 * n; i++) {
        x[i] = b.position[i];
        prev[i] = x[i] + (i / 3 < b.free_count ? 0.5 * params.gravity_h2[i % 3] : 0.0);
    }
    /* some motion first: substeps with the scene's own (truncated) solver */
    for (uint32_t s = 0; s < warm_substeps; s++)
        cvk_ref_substep_gauss_seidel(&b, &params, &scene->solver, x, prev, y, NULL, scratch);
    cvk_ref_predict(&b, &params, x, prev, y);
    memcpy(newton, x, 3 * n * sizeof(double));
    cvk_ref_newton_report report;
    CHECK(cvk_ref_solve_newton(&b, &params, y, 1e-12, 200, 5, newton, &report), "out of memory");
    double change = 0.0;
    uint64_t sweeps = cvk_ref_solve_converged(&b, &params, y, 1.0, 1e-14, 4000000, x, scratch, &change);
    double apart = 0.0, travel = 0.0;
    for (size_t i = 0; i < 3 * n; i++)
        apart = fmax(apart, fabs(newton[i] - x[i]));
    for (size_t i = 0; i < 3 * (size_t)b.free_count; i++) /* y holds free particles only */
        travel = fmax(travel, fabs(x[i] - y[i]));
    CHECK(change <= 1e-14, "%s: Gauss-Seidel still moves %g m after %llu iterations", name, change,
          (unsigned long long)sweeps);
    CHECK(report.last_step <= 1e-12, "%s: Newton's last step (of %u) is %g m", name, report.steps,
          report.last_step);
    CHECK(apart < 1e-9, "%s: Newton and Gauss-Seidel converge %g m apart", name, apart);
    CHECK(report.gs_change < 1e-12, "%s: Gauss-Seidel moves %g m from Newton's x*", name,
          report.gs_change);
    CHECK(travel > 1e-4, "%s: the solve moves only %g m: nothing was tested", name, travel);
    printf("%s: Newton (%u steps, %llu CG iterations) and Gauss-Seidel (%llu iterations) agree "
           "within %.3g m; the solve moves %.3g m\n", name, report.steps,
           (unsigned long long)report.cg_iterations, (unsigned long long)sweeps, apart, travel);
    free(x);
    free(prev);
    free(y);
    free(scratch);
    free(newton);
    cvk_build_destroy(&b);
    cvk_scene_destroy(file);
}

/* A scene whose particles are all pinned has nothing to solve: every solver plans no sweep,
   steps, and leaves the particles where they are. */
static void all_pinned(cvk_context* ctx)
{
    const cvk_linear_solver solvers[] = {CVK_LINEAR_RBGS, CVK_LINEAR_JACOBI, CVK_LINEAR_CHEBYSHEV,
                                         CVK_LINEAR_GS_CPU};
    const uint32_t pins[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    const uint32_t grids[2][2] = {{1, 1}, {2, 2}};
    for (size_t g = 0; g < 2; g++) {
        for (size_t i = 0; i < sizeof solvers / sizeof solvers[0]; i++) {
            cvk_cloth_desc cloth = cvk_default_cloth_desc();
            cloth.grid[0] = grids[g][0];
            cloth.grid[1] = grids[g][1];
            cloth.pins = pins;
            cloth.pin_count = grids[g][0] * grids[g][1];
            cvk_scene_desc scene = cvk_default_scene_desc();
            scene.cloths = &cloth;
            scene.cloth_count = 1;
            scene.solver.linear = solvers[i];
            cvk_error err;
            cvk_sim* sim;
            REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
            float* before = harness_read_all(sim);
            REQUIRE_OK(cvk_sim_step(sim, 3, &err), err);
            uint32_t sweeps = harness_pass_dispatches(sim, "solve");
            CHECK(sweeps == 0, "%ux%u all pinned, solver %d: %u sweep dispatches a frame",
                  grids[g][0], grids[g][1], (int)solvers[i], sweeps);
            float* after = harness_read_all(sim);
            for (uint64_t k = 0; k < 3 * cvk_sim_particle_count(sim); k++)
                CHECK(after[k] == before[k], "%ux%u all pinned, solver %d: coordinate %llu moved "
                      "from %g to %g", grids[g][0], grids[g][1], (int)solvers[i],
                      (unsigned long long)k, before[k], after[k]);
            free(before);
            free(after);
            cvk_sim_destroy(sim);
        }
    }
}

/* Where the prediction is plain (no air, damping, contact, grab or check), rbgs's first sweep
   predicts (lib/solvers/pd_passes.c, first_sweep_predicts), and where nothing comes between
   the last sweep and finalize (no tethers, strain limit, contact, ...) the last sweep
   finalizes (last_sweep_finalizes): a pinned cloth with shear and bend springs (more colours
   than two) swinging for 24 frames, with odd and even outer iterations (the last substep's
   displacements in the sweep's dst and src), gives the bits of the same scene with a plane
   10 m below it, which keeps the prediction's and finalize's own passes. */
static void folded_prediction_same_bits(cvk_context* ctx)
{
    const uint32_t pins[2][2] = {{0, 0}, {19, 0}};
    for (uint32_t outer = 1; outer <= 2; outer++) {
        float *xyz[2] = {NULL, NULL}, *start = NULL;
        uint32_t predicts[2] = {0, 0}, finalizes[2] = {0, 0}, substeps = 0;
        uint64_t n = 0;
        for (int far_plane = 0; far_plane < 2; far_plane++) {
            cvk_cloth_desc cloth = cvk_default_cloth_desc();
            cloth.grid[0] = 20;
            cloth.grid[1] = 16;
            cloth.stiffness.structural = 1e5f;
            cloth.stiffness.shear = 2e3f;
            cloth.stiffness.bend = 50.0f;
            cloth.pins = pins;
            cloth.pin_count = 2;
            cvk_scene_desc scene = cvk_default_scene_desc();
            scene.cloths = &cloth;
            scene.cloth_count = 1;
            scene.substeps = 4;
            scene.solver.linear = CVK_LINEAR_RBGS;
            scene.solver.outer_iterations = outer;
            scene.solver.inner_iterations = 3;
            scene.solver.omega = 1.4f;
            cvk_collider_desc plane = harness_far_plane();
            if (far_plane) {
                scene.colliders = &plane;
                scene.collider_count = 1;
            }
            substeps = scene.substeps;
            cvk_error err;
            cvk_sim* sim;
            REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
            if (!far_plane)
                start = harness_read_all(sim);
            REQUIRE_OK(cvk_sim_step(sim, 24, &err), err);
            xyz[far_plane] = harness_read_all(sim);
            predicts[far_plane] = harness_pass_dispatches(sim, "predict");
            finalizes[far_plane] = harness_pass_dispatches(sim, "finalize");
            n = cvk_sim_particle_count(sim);
            cvk_sim_destroy(sim);
        }
        CHECK(predicts[0] == 0 && predicts[1] == substeps, "%u outer: %u and %u predict "
              "dispatches a frame alone and with a plane, expected 0 and %u", outer, predicts[0],
              predicts[1], substeps);
        CHECK(finalizes[0] == 0 && finalizes[1] == substeps, "%u outer: %u and %u finalize "
              "dispatches a frame alone and with a plane, expected 0 and %u", outer,
              finalizes[0], finalizes[1], substeps);
        double apart = harness_max_diff(xyz[0], xyz[1], 3 * n);
        CHECK(memcmp(xyz[0], xyz[1], sizeof(float) * 3 * n) == 0, "%u outer: the first sweep "
              "that predicts and the last that finalizes, and the prediction's and finalize's "
              "own passes, differ by %g m", outer, apart);
        /* The cloth moved: the comparison is of a swing, not of a rest. */
        double moved = harness_max_diff(start, xyz[0], 3 * n);
        CHECK(moved > 0.02, "%u outer: the cloth moved only %g m in 24 frames", outer, moved);
        printf("rbgs %u outer: the first sweep predicting and the last finalizing, and the "
               "prediction's and finalize's own passes, the same bits after 24 frames (moved "
               "%.3g m)\n", outer, moved);
        free(start);
        free(xyz[0]);
        free(xyz[1]);
    }
}

/* cvk_pd_fused_copies: the instances' copies where the build lays them out as the fused pass
   reads them (shared/layout.h), else 1 — checked against scenes that do and do not. */
static uint32_t fused_copies_of(const char* text, uint32_t instances)
{
    cvk_error err;
    cvk_scene* scene = NULL;
    if (cvk_scene_parse(text, "fused copies", NULL, 0, &scene, &err) != CVK_SUCCESS) {
        CHECK(false, "fused copies: %s", err.message);
        return 0;
    }
    cvk_build b;
    uint32_t copies = 0;
    if (cvk_build_create(cvk_scene_get_desc(scene), &b, &err) == CVK_SUCCESS) {
        copies = cvk_pd_fused_copies(&b, instances);
        cvk_build_destroy(&b);
    } else {
        CHECK(false, "fused copies: %s", err.message);
    }
    cvk_scene_destroy(scene);
    return copies;
}

#define COPY_CLOTHS                                                                             \
    "{\"cloths\": [{\"grid\": [5, 4], \"pins\": [[0, 0]]},"                                    \
    " {\"grid\": [3, 3], \"origin\": [2, 0, 0], \"stiffness\": {\"shear\": 1e3}}]"

static void fused_copies_layout(void)
{
    uint32_t n = fused_copies_of(COPY_CLOTHS ", \"instances\": {\"count\": 3, \"spacing\": [5, 0, 0]}}",
                                 3);
    CHECK(n == 3, "three copies of two cloths (one pinned, four colours): %u workgroups, expected 3", n);
    n = fused_copies_of(COPY_CLOTHS "}", 1);
    CHECK(n == 1, "one copy: %u, expected 1", n);
    /* two cloths of 16 particles taken for two copies: four colours of 4 and two of 8 make
       colours of 12, 12, 4 and 4, each even, but the first half of colour 0 is not the first
       cloth's alone */
    n = fused_copies_of("{\"cloths\": [{\"grid\": [4, 4], \"stiffness\": {\"shear\": 1e3}},"
                        " {\"grid\": [2, 8], \"origin\": [2, 0, 0]}]}",
                        2);
    CHECK(n == 1, "two unequal cloths as two copies: %u, expected 1", n);
    n = fused_copies_of(COPY_CLOTHS "}", 2);
    CHECK(n == 1, "a 5 x 4 and a 3 x 3 cloth as two copies: %u, expected 1", n);
    printf("fused copies: the layout check takes three copies and refuses unequal cloths\n");
}

/* The Chebyshev polynomial T_k(x) for x >= 1: cosh(k acosh x). */
static double chebyshev_t(uint32_t k, double x)
{
    return cosh(k * acosh(x));
}

/* The weights the device plan and the host reference share, against the closed form of
   Chebyshev semi-iteration (Golub and Varga 1961; Wang 2015's recurrence computes the same):
   after `delay` plain sweeps, the j-th accelerated sweep's weight is
   2 T_j(1/rho) / (rho T_j+1(1/rho)); and the cap on rho over m accelerated sweeps keeps
   T_m(1/rho) at 3 (solve_pd.h). */
static void chebyshev_closed_form(void)
{
    const double rhos[] = {0.3, 0.8, 0.95, 0.999};
    double worst = 0.0;
    for (size_t i = 0; i < sizeof rhos / sizeof rhos[0]; i++) {
        double rho = rhos[i];
        for (uint32_t delay = 1; delay <= 3; delay++) {
            CHECK(cvk_chebyshev_weight(delay - 1, delay, rho) == 1.0,
                  "rho %g: sweep %u before the delay of %u is weighted", rho, delay - 1, delay);
            for (uint32_t j = 1; j <= 12; j++) {
                double x = 1.0 / rho;
                double want = 2.0 * chebyshev_t(j, x) / (rho * chebyshev_t(j + 1, x));
                double got = cvk_chebyshev_weight(delay + j - 1, delay, rho);
                worst = fmax(worst, fabs(got - want) / want);
            }
        }
    }
    CHECK(worst < 1e-12, "Chebyshev weights differ from the closed form by %g (relative)", worst);
    double cap_worst = 0.0;
    for (uint32_t m = 1; m <= 16; m++)
        cap_worst = fmax(cap_worst, fabs(chebyshev_t(m, 1.0 / cvk_chebyshev_stable_rho(m)) - 3.0));
    CHECK(cap_worst < 1e-9, "T_m(1/rho) of the stable rho is off 3 by %g", cap_worst);
    printf("Chebyshev: weights equal the closed form to %.1e, the stable rho's T_m(1/rho) is 3 "
           "to %.1e\n", worst, cap_worst);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    chebyshev_closed_form();
    rbgs_equals_gs_cpu(ctx);
    jacobi_equals_reference(ctx, CVK_LINEAR_JACOBI);
    jacobi_equals_reference(ctx, CVK_LINEAR_CHEBYSHEV);
    all_pinned(ctx);
    folded_prediction_same_bits(ctx);
    fused_copies_layout();
    residual_falls(ctx, CVK_LINEAR_RBGS);
    residual_falls(ctx, CVK_LINEAR_GS_CPU);
    const char* enlarged[] = {"cloths.0.grid=[12,12]"};
    newton_equals_gauss_seidel("enlarged.json", enlarged, 1, 0);
    const char* hanging[] = {"cloths.0.grid=[14,14]", "cloths.0.pins=[[0,0],[13,0]]"};
    newton_equals_gauss_seidel("hanging.json", hanging, 2, 40);
    return harness_finish(ctx);
}
