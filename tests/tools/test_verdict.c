/* The stability verdict of clothvk-bench (apps/bench/verdict.c):
   - statistics with a NaN, with exploding motion, or with a spring stretched past the bound are
     flagged, each for its reason; the start itself and a rubbery but bounded cloth are not;
   - real runs: a resting cloth is stable; over-relaxed Jacobi (omega 1.3, whose iteration
     matrix reaches -1.6) explodes and is flagged for its energy, and, with the energy and
     stretch bounds lifted, as diverged: the library's divergence watch stops it before any
     coordinate is lost. */
#include "bench.h"
#include "harness.h"

static cvk_sim_stats resting(void)
{
    cvk_sim_stats st = {0};
    st.gravitational_energy = 0.981; /* 0.1 kg at 1 m */
    st.energy = st.gravitational_energy;
    st.max_stretch = 0.0;
    return st;
}

static void synthetic(void)
{
    const float g[3] = {0.0f, -9.81f, 0.0f};
    cvk_sim_stats start = resting();
    bench_watch w = bench_watch_start(&start, 0.1, g, 1.4);
    double growth;
    CHECK(bench_classify(&w, &start, 1.0, 10.0, &growth) == BENCH_STABLE && growth == 0.0,
          "the start itself is not stable (growth %g)", growth);

    cvk_sim_stats nan = start;
    nan.nan_count = 3;
    CHECK(bench_classify(&w, &nan, 1.0, 10.0, &growth) == BENCH_NAN, "a NaN is not flagged");
    nan.nan_count = 0;
    nan.kinetic_energy = NAN;
    nan.energy = NAN;
    CHECK(bench_classify(&w, &nan, 1.0, 10.0, &growth) == BENCH_NAN, "a NaN energy is not flagged");

    cvk_sim_stats exploding = start;
    exploding.kinetic_energy = 50.0; /* 0.1 kg at 32 m/s: no fall of 1.4 m gives that */
    exploding.energy += 50.0;
    CHECK(bench_classify(&w, &exploding, 1.0, 10.0, &growth) == BENCH_ENERGY,
          "an energy growth of %g scales is not flagged", growth);

    /* A truncated solve is rubbery: stretched springs hold much nominal energy, but the
       motion stays what the fall released. */
    cvk_sim_stats rubbery = start;
    rubbery.gravitational_energy = 0.7;
    rubbery.kinetic_energy = 0.25;
    rubbery.elastic_energy = 60.0;
    rubbery.max_stretch = 0.05;
    rubbery.energy = 60.95;
    CHECK(bench_classify(&w, &rubbery, 1.0, 10.0, &growth) == BENCH_STABLE,
          "a rubbery cloth is flagged (growth %g)", growth);

    cvk_sim_stats stretched = start;
    stretched.max_stretch = 12.0;
    CHECK(bench_classify(&w, &stretched, 1.0, 10.0, &growth) == BENCH_STRETCH,
          "a stretch of 1200%% is not flagged");
    /* a run that starts stretched (a pin moved far away) is judged against its start */
    cvk_sim_stats pulled = start;
    pulled.max_stretch = 99.0;
    bench_watch w_pulled = bench_watch_start(&pulled, 0.1, g, 1.4);
    pulled.max_stretch = 50.0;
    CHECK(bench_classify(&w_pulled, &pulled, 1.0, 10.0, &growth) == BENCH_STABLE,
          "a stretch falling from its start is flagged");
}

typedef struct small_scene {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    uint32_t pins[2][2];
} small_scene;

static void make_scene(small_scene* s, bool gravity)
{
    s->cloth = cvk_default_cloth_desc();
    s->cloth.grid[0] = 10;
    s->cloth.grid[1] = 8;
    s->pins[0][0] = 0;
    s->pins[0][1] = 0;
    s->pins[1][0] = 9;
    s->pins[1][1] = 0;
    s->cloth.pins = (const uint32_t(*)[2])s->pins;
    s->cloth.pin_count = 2;
    s->scene = cvk_default_scene_desc();
    s->scene.cloths = &s->cloth;
    s->scene.cloth_count = 1;
    s->scene.substeps = 1;
    if (!gravity)
        s->scene.gravity[1] = 0.0f;
}

static bench_stability_run run(cvk_context* ctx, const cvk_scene_desc* scene, uint64_t steps,
                               double energy_bound, double stretch_bound)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    bench_stability_run r;
    CHECK(bench_run_stability(sim, scene, steps, energy_bound, stretch_bound, &r, &err),
          "bench_run_stability failed: %s", err.message);
    cvk_sim_destroy(sim);
    return r;
}

static void real_runs(cvk_context* ctx)
{
    small_scene s;
    make_scene(&s, false);
    bench_stability_run r = run(ctx, &s.scene, 200, 1.0, 10.0);
    CHECK(r.verdict == BENCH_STABLE && r.steps_done == 200,
          "a resting cloth is %s after %llu steps (growth %g, stretch %g)",
          bench_verdict_name(r.verdict), (unsigned long long)r.steps_done, r.growth, r.max_stretch);

    /* Two Jacobi sweeps a step at omega 1.3: the checkerboard mode grows by (1 − 2.6)² = 2.56
       a step, from rounding to an explosion in a few dozen steps. */
    make_scene(&s, true);
    s.scene.solver.linear = CVK_LINEAR_JACOBI;
    s.scene.solver.omega = 1.3f;
    s.scene.solver.outer_iterations = 1;
    s.scene.solver.inner_iterations = 2;
    r = run(ctx, &s.scene, 400, 1.0, 10.0);
    CHECK(r.verdict == BENCH_ENERGY, "over-relaxed Jacobi is %s after %llu steps (growth %g)",
          bench_verdict_name(r.verdict), (unsigned long long)r.steps_done, r.growth);
    printf("over-relaxed Jacobi: %s after %llu steps (energy growth %.3g scales)\n",
           bench_verdict_name(r.verdict), (unsigned long long)r.steps_done, r.growth);

    /* With the bench's own bounds lifted the library's divergence watch stops the run, before
       any coordinate is lost (it used to run on to NaN). */
    r = run(ctx, &s.scene, 4000, INFINITY, INFINITY);
    CHECK(r.verdict == BENCH_DIVERGED && r.nan_count == 0 && r.steps_done < 4000,
          "over-relaxed Jacobi with no energy or stretch bound is %s after %llu steps, %llu NaN",
          bench_verdict_name(r.verdict), (unsigned long long)r.steps_done,
          (unsigned long long)r.nan_count);
    printf("over-relaxed Jacobi, bounds lifted: %s after %llu steps (%llu non-finite coordinates)\n",
           bench_verdict_name(r.verdict), (unsigned long long)r.steps_done,
           (unsigned long long)r.nan_count);
}

int main(void)
{
    synthetic();
    cvk_context* ctx = harness_context();
    real_runs(ctx);
    return harness_finish(ctx);
}
