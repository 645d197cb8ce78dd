/* The divergence watch (shaders/solvers/predict.comp, shaders/solvers/finalize.comp, lib/sim/sim_watch.c):
   - a cloth falling with 9981 m/s and gaining 1 m/s per 0.1 s substep moves 1000.05 m in its
     20th substep (the first gains half a substep's worth), 10000.5 m/s (from 9980.5 m/s it
     moved exactly 1000 m, on the bound, and only the rounding of the solve tipped it over):
     cvk_sim_step returns CVK_ERROR_DIVERGED in frame 19 (one substep per frame), the statistics say so, and the positions stop there, finite; rewriting the state clears it;
   - the same cloth 5 m/s slower is fast but sane: 20 frames, never diverged;
   - a step far too long for the springs (dt = 1000 s) is caught by the stretch bound in frame 0;
   - a spring written 20 times its rest length long is caught by the prediction's stretch check
     in the first substep, before any particle moves, and names the cloth it is in: with the
     prediction's own pass and where rbgs's first sweep predicts;
   - hanging.json, a normal scene, runs without tripping it.
   Each with every GPU linear solver. And ribbons.json with over-relaxed Gauss-Seidel (omega
   1.7 and 1.8) and contact runs 60 frames without tripping it, largest stretch under 100 %. */
#include <string.h>

#include "harness.h"

static const cvk_linear_solver linears[] = {CVK_LINEAR_RBGS, CVK_LINEAR_JACOBI,
                                             CVK_LINEAR_CHEBYSHEV};

static cvk_sim* falling_cloth(cvk_context* ctx, cvk_linear_solver linear, float speed, double dt)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = 4;
    cloth.grid[1] = 3;
    cloth.pin_count = 0;
    cloth.velocity[1] = -speed;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.dt = (float)dt;
    scene.substeps = 1;
    scene.damping = 0.0f;
    scene.gravity[0] = scene.gravity[2] = 0.0f;
    scene.gravity[1] = -10.0f;
    scene.solver.linear = linear;
    cvk_error err;
    cvk_sim* sim = NULL;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    return sim;
}

static bool all_finite(const float* x, uint64_t n)
{
    for (uint64_t i = 0; i < 3 * n; i++)
        if (!isfinite(x[i]))
            return false;
    return true;
}

static void test_too_fast(cvk_context* ctx, cvk_linear_solver linear, const char* name)
{
    cvk_sim* sim = falling_cloth(ctx, linear, 9981.0f, 0.1);
    cvk_error err = {.message = ""};
    cvk_result r = CVK_SUCCESS;
    uint32_t frame = 0;
    for (; frame < 40 && r == CVK_SUCCESS; frame++)
        r = cvk_sim_step(sim, 1, &err);
    CHECK(r == CVK_ERROR_DIVERGED && frame == 20, "%s: stepping ended with %s after %u frames "
          "(expected CVK_ERROR_DIVERGED after 20)", name, cvk_result_name(r), frame);
    const char* expected = "the simulation diverged in frame 19: a particle moved faster than "
                           "10000 m/s or a spring stretched past ten times its rest length in "
                           "cloth 0 (\"cloth0\"); positions stopped advancing there (a smaller "
                           "dt, more substeps or iterations, or softer springs)";
    CHECK(strcmp(err.message, expected) == 0, "%s: message\n  %s\nexpected\n  %s", name,
          err.message, expected);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    CHECK(st.diverged && st.diverged_frame == 19 && st.diverged_cloth == 0 &&
              !st.diverged_nonfinite,
          "%s: stats say diverged %d in frame %llu, cloth %u, non-finite %d", name, st.diverged,
          (unsigned long long)st.diverged_frame, st.diverged_cloth, st.diverged_nonfinite);

    float* stopped = harness_read_all(sim);
    r = cvk_sim_step(sim, 3, &err);
    float* later = harness_read_all(sim);
    uint64_t n = cvk_sim_particle_count(sim);
    CHECK(r == CVK_ERROR_DIVERGED && memcmp(stopped, later, 3 * n * sizeof(float)) == 0 &&
              all_finite(later, n),
          "%s: after the divergence the positions moved or are not finite", name);
    REQUIRE_OK(cvk_sim_write_positions(sim, later, n, &err), err);
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    CHECK(!st.diverged, "%s: a rewritten state still counts as diverged", name);
    free(stopped);
    free(later);
    cvk_sim_destroy(sim);
}

static void test_fast_but_sane(cvk_context* ctx, cvk_linear_solver linear, const char* name)
{
    cvk_sim* sim = falling_cloth(ctx, linear, 9976.0f, 0.1);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, 20, &err), err); /* 9995.5 m/s at the end */
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    CHECK(!st.diverged && st.max_stretch < 0.01, "%s: a cloth falling at 9995 m/s tripped the "
          "watch (diverged %d) or stretched %.3g", name, st.diverged, st.max_stretch);
    cvk_sim_destroy(sim);
}

static void test_step_too_long(cvk_context* ctx, cvk_linear_solver linear, const char* name)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = 4;
    cloth.grid[1] = 3;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.dt = 1000.0f;
    scene.solver.linear = linear;
    cvk_error err;
    cvk_sim* sim = NULL;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    cvk_result r = cvk_sim_step(sim, 2, &err);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    CHECK(r == CVK_ERROR_DIVERGED && st.diverged && st.diverged_frame == 0 && st.nan_count == 0,
          "%s: dt = 1000 s: %s, diverged %d in frame %llu, %llu non-finite", name,
          cvk_result_name(r), st.diverged, (unsigned long long)st.diverged_frame,
          (unsigned long long)st.nan_count);
    cvk_sim_destroy(sim);
}

/* Two cloths, a particle of the second written 20 spacings from its place: the first substep's
   stretch check stops the simulation before any particle moves, and names cloth 1, whether
   the plan predicts in a pass of its own or in the first sweep (own_prediction, checked). */
static void test_stretched_start(cvk_context* ctx, cvk_linear_solver linear, float damping,
                                 bool own_prediction, const char* name)
{
    cvk_cloth_desc cloths[2];
    for (int c = 0; c < 2; c++) {
        cloths[c] = cvk_default_cloth_desc();
        cloths[c].grid[0] = 6;
        cloths[c].grid[1] = 5;
        cloths[c].origin[0] = 2.0f * (float)c;
    }
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = 2;
    scene.substeps = 4;
    scene.damping = damping;
    scene.solver.linear = linear;
    cvk_error err = {.message = ""};
    cvk_sim* sim = NULL;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    /* The path the case is for: a prediction pass of its own, or none (the first sweep
       predicts). */
    uint32_t predicts = harness_pass_dispatches(sim, "predict");
    CHECK((predicts > 0) == own_prediction, "%s: %u prediction dispatches a frame", name, predicts);
    float* xyz = harness_read_all(sim);
    uint64_t n = cvk_sim_particle_count(sim), moved = 30 + 14; /* cloth 1, row 2, column 2 */
    float spacing = cloths[1].size[0] / (float)(cloths[1].grid[0] - 1);
    xyz[3 * moved + 1] += 20.0f * spacing;
    REQUIRE_OK(cvk_sim_write_positions(sim, xyz, n, &err), err);
    cvk_result r = cvk_sim_step(sim, 1, &err);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    float* after = harness_read_all(sim);
    CHECK(r == CVK_ERROR_DIVERGED && st.diverged && st.diverged_frame == 0 &&
              st.diverged_cloth == 1 && !st.diverged_nonfinite,
          "%s: a spring 20 times its length: %s, diverged %d in frame %llu, cloth %u", name,
          cvk_result_name(r), st.diverged, (unsigned long long)st.diverged_frame,
          st.diverged_cloth);
    CHECK(memcmp(xyz, after, 3 * n * sizeof(float)) == 0, "%s: a spring 20 times its length: "
          "particles moved by up to %g m before the watch stopped them", name,
          harness_max_diff(xyz, after, 3 * n));
    free(xyz);
    free(after);
    cvk_sim_destroy(sim);
}

static void test_hanging(cvk_context* ctx)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    char path[1024];
    snprintf(path, sizeof path, "%s/assets/scenes/hanging.json", root ? root : ".");
    cvk_error err;
    cvk_scene* file;
    REQUIRE_OK(cvk_scene_load(path, NULL, 0, &file, &err), err);
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, cvk_scene_get_desc(file), &sim, &err),
               err);
    REQUIRE_OK(cvk_sim_step(sim, 20, &err), err);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    CHECK(!st.diverged, "hanging.json tripped the watch");
    cvk_sim_destroy(sim);
    cvk_scene_destroy(file);
}

/* Over-relaxed Gauss-Seidel with contact: ribbons.json's light, narrow ribbons falling across
   each other onto a log diverged at omega 1.7 (frame 28) and 1.8 on lavapipe, and at 1.6 on
   an NVIDIA H100, while the first sweep after each contact pass was over-relaxed too: a
   particle pushed out by the contact was pulled back past where it had been, and the next pass
   pushed it further (lib/solvers/pd_passes.c, gs_omega). Now they fall, cross and rest. */
static void test_ribbons_over_relaxed(cvk_context* ctx)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    char path[1024];
    snprintf(path, sizeof path, "%s/assets/scenes/ribbons.json", root ? root : ".");
    const char* omegas[] = {"solver.omega=1.7", "solver.omega=1.8"};
    for (int i = 0; i < 2; i++) {
        cvk_error err;
        cvk_scene* file;
        REQUIRE_OK(cvk_scene_load(path, &omegas[i], 1, &file, &err), err);
        cvk_sim* sim;
        REQUIRE_OK(harness_sim_create(ctx, cvk_scene_get_desc(file), &sim,
                                  &err),
                   err);
        cvk_result r = cvk_sim_step(sim, 60, &err);
        cvk_sim_stats st;
        REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
        CHECK(r == CVK_SUCCESS && !st.diverged && st.max_stretch < 1.0,
              "ribbons.json, %s, 60 frames: %s, diverged %d, largest stretch %.1f %%", omegas[i],
              cvk_result_name(r), st.diverged, 100.0 * st.max_stretch);
        printf("ribbons.json, %s, 60 frames: largest stretch %.1f %%\n", omegas[i],
               100.0 * st.max_stretch);
        cvk_sim_destroy(sim);
        cvk_scene_destroy(file);
    }
}

int main(void)
{
    cvk_context* ctx = harness_context();
    for (size_t i = 0; i < sizeof linears / sizeof linears[0]; i++) {
        const char* name = cvk_linear_solver_name(linears[i]);
        test_too_fast(ctx, linears[i], name);
        test_fast_but_sane(ctx, linears[i], name);
        test_step_too_long(ctx, linears[i], name);
    }
    /* Damping keeps the prediction's own pass for rbgs; without it the first sweep predicts. */
    test_stretched_start(ctx, CVK_LINEAR_RBGS, 0.0f, false, "rbgs, the first sweep predicting");
    test_stretched_start(ctx, CVK_LINEAR_RBGS, 0.01f, true, "rbgs, the prediction's own pass");
    test_stretched_start(ctx, CVK_LINEAR_JACOBI, 0.0f, true, "jacobi");
    test_hanging(ctx);
    test_ribbons_over_relaxed(ctx);
    return harness_finish(ctx);
}
