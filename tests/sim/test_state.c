/* The run-time API the benchmark and applications use to freeze and replay substeps:
   - a state read with cvk_sim_read_state and written back continues the same motion;
   - velocities are Verlet's: 0 at rest, g t in free fall;
   - cvk_sim_set_solver keeps the state bit for bit, runs the new solver as a simulation
     created with it would, and rejects a bad description without changing anything;
   - the energy of a resting cloth is 0, of a free fall constant, of one stretched spring ½ k e²;
   - on one frozen substep, rbgs after k iterations equals gs-cpu after k iterations to float
     rounding, for every k (seed 002's claim that RBGS converges per iteration as GS does). */
#include "harness.h"

/* Float rounding over one substep (see test_solver.c): a few ulps of an O(1) m position. */
#define SAME_TO_ROUNDING 5e-7

static cvk_sim* make_sim(cvk_context* ctx, const cvk_scene_desc* scene)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    return sim;
}

typedef struct state {
    float* x;
    float* v;
    uint64_t n;
} state;

static state read_state(cvk_sim* sim)
{
    cvk_error err;
    state s = {.n = cvk_sim_particle_count(sim)};
    s.x = malloc(3 * s.n * sizeof(float));
    s.v = malloc(3 * s.n * sizeof(float));
    if (!s.x || !s.v) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    REQUIRE_OK(cvk_sim_read_state(sim, s.x, s.v, s.n, &err), err);
    return s;
}

static void free_state(state* s)
{
    free(s->x);
    free(s->v);
}

/* A 16 x 12 cloth pinned along one edge, with shear springs: it swings and stretches. */
typedef struct swinging {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    uint32_t pins[2][2];
} swinging;

static void make_swinging(swinging* w)
{
    w->pins[0][0] = 0;
    w->pins[0][1] = 0;
    w->pins[1][0] = 15;
    w->pins[1][1] = 0;
    w->cloth = cvk_default_cloth_desc();
    w->cloth.grid[0] = 16;
    w->cloth.grid[1] = 12;
    w->cloth.stiffness.shear = 1e5f;
    w->cloth.pins = (const uint32_t(*)[2])w->pins;
    w->cloth.pin_count = 2;
    w->scene = cvk_default_scene_desc();
    w->scene.cloths = &w->cloth;
    w->scene.cloth_count = 1;
}

static void snapshot_continues(cvk_context* ctx, cvk_linear_solver linear)
{
    swinging w;
    make_swinging(&w);
    w.scene.solver.linear = linear;
    cvk_sim* a = make_sim(ctx, &w.scene);
    cvk_sim* b = make_sim(ctx, &w.scene);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(a, 6, &err), err);
    state snap = read_state(a);
    REQUIRE_OK(cvk_sim_write_state(b, snap.x, snap.v, snap.n, &err), err);
    REQUIRE_OK(cvk_sim_step(a, 4, &err), err);
    REQUIRE_OK(cvk_sim_step(b, 4, &err), err);
    state ea = read_state(a), eb = read_state(b);
    double moved = harness_max_diff(snap.x, ea.x, 3 * snap.n);
    double apart = harness_max_diff(ea.x, eb.x, 3 * snap.n);
    /* The velocity goes through v = u/h + hg/2 and back: a float rounding of u per particle. */
    CHECK(apart < SAME_TO_ROUNDING, "%s: a restored snapshot is %g m off the original run",
          cvk_linear_solver_name(linear), apart);
    CHECK(moved > 1e-3, "%s: the cloth moved only %g m: nothing was tested",
          cvk_linear_solver_name(linear), moved);
    printf("snapshot (%s): restored run within %.3g m of the original after 32 substeps "
           "(the cloth moved %.3g m)\n", cvk_linear_solver_name(linear), apart, moved);
    free_state(&snap);
    free_state(&ea);
    free_state(&eb);
    cvk_sim_destroy(a);
    cvk_sim_destroy(b);
}

static void velocity_is_verlet(cvk_context* ctx)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = 5;
    cloth.grid[1] = 4;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    cvk_sim* sim = make_sim(ctx, &scene);
    state rest = read_state(sim);
    /* u = −½ h² g is stored as a float: its rounding over h is a few 1e-10 m/s. */
    float zero[60] = {0};
    CHECK(harness_max_diff(rest.v, zero, 60) < 1e-8, "a new cloth has velocity %g m/s",
          harness_max_diff(rest.v, zero, 60));
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
    state fall = read_state(sim);
    double t = 10.0 * scene.substeps * scene.dt, worst = 0.0;
    for (uint64_t p = 0; p < fall.n; p++)
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(fall.v[3 * p + c] - scene.gravity[c] * t));
    /* u is a float of about g h t, rounded after each of the 80 additions: 1e-4 m/s is 1e-7 of
       g h t / h per step, summed. */
    CHECK(worst < 1e-4, "free fall: velocity %g m/s off g t after %.3f s", worst, t);
    printf("velocity: free fall %.3g m/s off g t after %.2f s\n", worst, t);
    free_state(&rest);
    free_state(&fall);
    cvk_sim_destroy(sim);
}

static bool same_floats(const float* a, const float* b, uint64_t n)
{
    return memcmp(a, b, n * sizeof(float)) == 0;
}

/* Switching keeps the state bit for bit, and the new solver runs as a fresh simulation with
   it would from that state. */
static void switching_solvers(cvk_context* ctx)
{
    swinging w;
    make_swinging(&w);
    cvk_sim* sim = make_sim(ctx, &w.scene);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, 5, &err), err);
    const cvk_linear_solver order[] = {CVK_LINEAR_GS_CPU, CVK_LINEAR_JACOBI, CVK_LINEAR_CHEBYSHEV,
                                       CVK_LINEAR_GS_CPU, CVK_LINEAR_RBGS};
    for (size_t i = 0; i < sizeof order / sizeof order[0]; i++) {
        const char* name = cvk_linear_solver_name(order[i]);
        cvk_solver_desc solver = w.scene.solver;
        solver.linear = order[i];
        solver.outer_iterations = 2 + (uint32_t)i % 2;
        solver.inner_iterations = 3;
        solver.omega = order[i] == CVK_LINEAR_JACOBI ? 0.8f : 1.0f;
        state before = read_state(sim);
        REQUIRE_OK(cvk_sim_set_solver(sim, &solver, &err), err);
        state after = read_state(sim);
        CHECK(same_floats(before.x, after.x, 3 * before.n) && same_floats(before.v, after.v, 3 * before.n),
              "switching to %s changed the state", name);
        cvk_solver_desc now = cvk_sim_get_solver(sim);
        CHECK(now.linear == order[i] && now.outer_iterations == solver.outer_iterations,
              "cvk_sim_get_solver says %s %ux%u after switching to %s",
              cvk_linear_solver_name(now.linear), now.outer_iterations, now.inner_iterations, name);

        cvk_scene_desc fresh_scene = w.scene;
        fresh_scene.solver = solver;
        cvk_sim* fresh = make_sim(ctx, &fresh_scene);
        REQUIRE_OK(cvk_sim_write_state(fresh, before.x, before.v, before.n, &err), err);
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_sim_step(fresh, 1, &err), err);
        state a = read_state(sim), b = read_state(fresh);
        double apart = harness_max_diff(a.x, b.x, 3 * a.n);
        CHECK(apart < SAME_TO_ROUNDING, "after switching to %s the next frame is %g m off a fresh "
              "simulation with that solver", name, apart);
        cvk_sim_stats timing;
        cvk_sim_get_timing(sim, &timing);
        uint32_t sweeps = solver.outer_iterations * solver.inner_iterations;
        uint32_t expected = order[i] == CVK_LINEAR_GS_CPU ? 0
                            : order[i] == CVK_LINEAR_RBGS ? sweeps * timing.colours
                                                          : sweeps;
        CHECK(timing.passes[1].dispatches == expected * w.scene.substeps,
              "%s: %u solve dispatches per frame, expected %u", name, timing.passes[1].dispatches,
              expected * w.scene.substeps);
        CHECK(timing.passes[1].gpu_ms >= 0.0, "%s: no solve time after a frame", name);
        free_state(&before);
        free_state(&after);
        free_state(&a);
        free_state(&b);
        cvk_sim_destroy(fresh);
    }
    printf("set_solver: state kept bit for bit over 5 switches; each continues as a fresh "
           "simulation\n");
    cvk_sim_destroy(sim);
}

static void bad_solver_changes_nothing(cvk_context* ctx)
{
    swinging w;
    make_swinging(&w);
    cvk_sim* sim = make_sim(ctx, &w.scene);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, 3, &err), err); /* swinging: positions and velocities not trivial */
    state before = read_state(sim);
    cvk_solver_desc bad = w.scene.solver;
    bad.omega = 2.5f;
    bad.linear = CVK_LINEAR_JACOBI;
    cvk_result r = cvk_sim_set_solver(sim, &bad, &err);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT, "omega 2.5 returned %s", cvk_result_name(r));
    CHECK(!strcmp(err.message, "solver.omega: must be greater than 0 and less than 2, got 2.5"),
          "message: %s", err.message);
    bad = w.scene.solver;
    bad.outer_iterations = 0;
    r = cvk_sim_set_solver(sim, &bad, &err);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT &&
              !strcmp(err.message, "solver.outer_iterations: must be at least 1, got 0"),
          "0 outer iterations: %s: %s", cvk_result_name(r), err.message);
    cvk_solver_desc now = cvk_sim_get_solver(sim);
    CHECK(now.linear == CVK_LINEAR_RBGS && now.omega == 1.0f && now.outer_iterations == 4,
          "a rejected solver changed the settings");
    r = cvk_sim_set_solver(sim, NULL, &err);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT &&
              !strcmp(err.message, "cvk_sim_set_solver needs a simulation and a solver description"),
          "a NULL solver: %s: %s", cvk_result_name(r), err.message);

    float x[3] = {0};
    r = cvk_sim_read_state(sim, x, NULL, 1, &err);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT &&
              !strcmp(err.message, "cvk_sim_read_state: the array holds 1 particles; the "
                                   "simulation has 192"),
          "a short array: %s: %s", cvk_result_name(r), err.message);
    uint64_t n = cvk_sim_particle_count(sim);
    state s = read_state(sim);
    CHECK(same_floats(s.x, before.x, 3 * n) && same_floats(s.v, before.v, 3 * n),
          "a rejected call changed the state");
    s.v[7] = NAN;
    r = cvk_sim_write_state(sim, s.x, s.v, n, &err);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT &&
              !strcmp(err.message, "cvk_sim_write_state: velocity coordinate 1 of particle 2 is "
                                   "not a finite number"),
          "a NaN velocity: %s: %s", cvk_result_name(r), err.message);
    free_state(&s);
    s = read_state(sim);
    CHECK(same_floats(s.x, before.x, 3 * n) && same_floats(s.v, before.v, 3 * n),
          "a rejected state was written in part");
    free_state(&s);
    free_state(&before);
    cvk_sim_destroy(sim);
}

static cvk_sim_stats stats_of(cvk_sim* sim)
{
    cvk_error err;
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    return st;
}

static void energy(cvk_context* ctx)
{
    /* At rest without gravity: nothing moves, nothing is stretched. */
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = 6;
    cloth.grid[1] = 5;
    cloth.origin[1] = 0.0f;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.gravity[1] = 0.0f;
    cvk_sim* sim = make_sim(ctx, &scene);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, 20, &err), err);
    cvk_sim_stats st = stats_of(sim);
    /* Rest lengths come from float positions: springs are off by ~1e-8 m, ½ k e² ~ 1e-10 J. */
    CHECK(st.kinetic_energy < 1e-12 && st.elastic_energy < 1e-8 && fabs(st.energy) < 1e-8,
          "a cloth at rest has energy %g J (kinetic %g, elastic %g)", st.energy, st.kinetic_energy,
          st.elastic_energy);
    cvk_sim_destroy(sim);

    /* Free fall: ½ m v² gained = m g Δh lost; Verlet is exact for constant acceleration. */
    scene.gravity[1] = -9.81f;
    sim = make_sim(ctx, &scene);
    cvk_sim_stats start = stats_of(sim);
    REQUIRE_OK(cvk_sim_step(sim, 20, &err), err);
    st = stats_of(sim);
    double t = 20.0 * scene.substeps * scene.dt;
    double expected_kinetic = 0.5 * cloth.mass * 9.81 * 9.81 * t * t;
    CHECK(fabs(st.kinetic_energy - expected_kinetic) < 1e-4 * expected_kinetic,
          "free fall: kinetic energy %g J, expected %g J", st.kinetic_energy, expected_kinetic);
    CHECK(fabs(st.energy - start.energy) < 1e-4 * expected_kinetic,
          "free fall: energy went from %g J to %g J", start.energy, st.energy);
    printf("energy: free fall keeps %.6g J within %.2g J (kinetic %.4g J after %.2f s)\n",
           start.energy, fabs(st.energy - start.energy), st.kinetic_energy, t);
    cvk_sim_destroy(sim);

    /* One spring (a 2-particle rope) stretched by e: ½ k e². */
    cvk_cloth_desc rope = cvk_default_cloth_desc();
    rope.grid[0] = 2;
    rope.grid[1] = 1;
    rope.size[0] = 0.5f;
    rope.stiffness.structural = 1000.0f;
    scene.cloths = &rope;
    sim = make_sim(ctx, &scene);
    float xyz[6];
    REQUIRE_OK(cvk_sim_read_positions(sim, xyz, 2, &err), err);
    xyz[3] += 0.1f;
    REQUIRE_OK(cvk_sim_write_positions(sim, xyz, 2, &err), err);
    st = stats_of(sim);
    double e = (double)xyz[3] - xyz[0] - 0.5;
    CHECK(fabs(st.elastic_energy - 0.5 * 1000.0 * e * e) < 1e-9,
          "a spring stretched by %g m holds %g J, expected %g J", e, st.elastic_energy,
          0.5 * 1000.0 * e * e);
    cvk_sim_destroy(sim);
}

/* Loads a scene of assets/scenes on a 14 x 14 grid (hanging.json pinned at its two corners
   again) with one substep per frame. */
static cvk_scene* load_small(const char* name)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    char path[1024];
    snprintf(path, sizeof path, "%s/assets/scenes/%s", root ? root : ".", name);
    const char* overrides[] = {"cloths.0.grid=[14,14]", "cloths.0.pins=[[0,0],[13,0]]",
                               "substeps=1"};
    bool pinned = !strcmp(name, "hanging.json");
    const char* chosen[] = {overrides[0], pinned ? overrides[1] : overrides[2], overrides[2]};
    cvk_error err;
    cvk_scene* file;
    REQUIRE_OK(cvk_scene_load(path, chosen, pinned ? 3 : 2, &file, &err), err);
    return file;
}

/* One substep from `snap` with `iterations` local steps of one sweep each. */
static cvk_sim_stats frozen_substep(cvk_sim* sim, const state* snap, cvk_linear_solver linear,
                                    uint32_t iterations, float* out)
{
    cvk_error err;
    cvk_solver_desc solver = cvk_sim_get_solver(sim);
    solver.linear = linear;
    solver.outer_iterations = iterations;
    solver.inner_iterations = 1;
    REQUIRE_OK(cvk_sim_set_solver(sim, &solver, &err), err);
    REQUIRE_OK(cvk_sim_write_state(sim, snap->x, snap->v, snap->n, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(sim, out, snap->n, &err), err);
    return stats_of(sim);
}

static void rbgs_converges_as_gs_cpu(cvk_context* ctx, const char* name, uint32_t warm_frames)
{
    cvk_scene* file = load_small(name);
    const cvk_scene_desc* scene = cvk_scene_get_desc(file);
    cvk_sim* sim = make_sim(ctx, scene);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, warm_frames, &err), err);
    state snap = read_state(sim);
    uint64_t n = snap.n;
    float* gpu = malloc(3 * n * sizeof(float));
    float* host = malloc(3 * n * sizeof(float));
    float* one = malloc(3 * n * sizeof(float));
    double first = 0.0, last = 0.0, worst_x = 0.0, worst_ratio = 0.0;
    const uint32_t iterations = 24;
    for (uint32_t k = 1; k <= iterations; k++) {
        cvk_sim_stats a = frozen_substep(sim, &snap, CVK_LINEAR_RBGS, k, gpu);
        cvk_sim_stats b = frozen_substep(sim, &snap, CVK_LINEAR_GS_CPU, k, host);
        double dx = harness_max_diff(gpu, host, 3 * n);
        /* Positions within δ change each spring's error by at most 2δ, so the residual by at
           most Σ 2|e|·2δ + (2δ)² ≤ 4δ √(springs · residual) + springs (2δ)². */
        double delta = SAME_TO_ROUNDING, springs = (double)a.springs[0];
        double bound = 4 * delta * sqrt(springs * fmax(a.residual, b.residual)) +
                       springs * 4 * delta * delta;
        double dr = fabs(a.residual - b.residual);
        CHECK(dx < SAME_TO_ROUNDING, "%s, %u iterations: rbgs and gs-cpu are %g m apart", name, k, dx);
        CHECK(dr <= bound, "%s, %u iterations: residuals %.9g (rbgs) and %.9g (gs-cpu) differ by %g, "
              "more than float rounding (%g)", name, k, a.residual, b.residual, dr, bound);
        worst_x = fmax(worst_x, dx);
        worst_ratio = fmax(worst_ratio, dr / bound);
        if (k == 1) {
            first = b.residual;
            memcpy(one, host, 3 * n * sizeof(float));
        }
        last = b.residual;
    }
    /* The comparison must be able to fail: the iterates must move far more than rounding. */
    double travel = harness_max_diff(one, host, 3 * n);
    CHECK(travel > 100 * SAME_TO_ROUNDING, "%s: iterations 1 and %u are only %g m apart", name,
          iterations, travel);
    printf("%s (14x14, frozen substep after %u frames): rbgs = gs-cpu for k = 1..%u, positions "
           "within %.3g m, residuals within %.2f of the rounding bound; iterates travel %.3g m, "
           "residual %.4g -> %.4g\n",
           name, warm_frames, iterations, worst_x, worst_ratio, travel, first, last);
    free(gpu);
    free(host);
    free(one);
    free_state(&snap);
    cvk_sim_destroy(sim);
    cvk_scene_destroy(file);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    snapshot_continues(ctx, CVK_LINEAR_RBGS);
    snapshot_continues(ctx, CVK_LINEAR_GS_CPU);
    velocity_is_verlet(ctx);
    switching_solvers(ctx);
    bad_solver_changes_nothing(ctx);
    energy(ctx);
    rbgs_converges_as_gs_cpu(ctx, "enlarged.json", 0);
    rbgs_converges_as_gs_cpu(ctx, "hanging.json", 40);
    return harness_finish(ctx);
}
