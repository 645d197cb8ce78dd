/* A tiny test harness: CHECK prints which fact failed and by how much; every GPU test runs
   with the validation layer on and fails on any message. Header-only, one per test program. */
#ifndef CVK_TEST_HARNESS_H
#define CVK_TEST_HARNESS_H

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clothvk.h"

static int harness_failures;
static int harness_checks;

#define CHECK(cond, ...)                                                                        \
    do {                                                                                        \
        harness_checks++;                                                                       \
        if (!(cond)) {                                                                          \
            harness_failures++;                                                                 \
            fprintf(stderr, "%s:%d: FAILED: %s: ", __FILE__, __LINE__, #cond);                  \
            fprintf(stderr, __VA_ARGS__);                                                       \
            fputc('\n', stderr);                                                                \
        }                                                                                       \
    } while (0)

/* Stops the program: for failures after which nothing else can be checked. */
#define REQUIRE_OK(call, err)                                                                   \
    do {                                                                                        \
        cvk_result r_ = (call);                                                                 \
        if (r_ != CVK_SUCCESS) {                                                                \
            fprintf(stderr, "%s:%d: FAILED: %s returned %s: %s\n", __FILE__, __LINE__, #call,  \
                    cvk_result_name(r_), (err).message);                                        \
            exit(1);                                                                            \
        }                                                                                       \
    } while (0)

static inline void harness_log(void* user, const char* message)
{
    (void)user;
    fprintf(stderr, "validation: %s\n", message);
}

/* A library-made context with the validation layer on (tests always run with it). */
static inline cvk_context* harness_context(void)
{
    cvk_error err;
    cvk_context* ctx = NULL;
    cvk_context_desc desc = cvk_default_context_desc();
    desc.validation = 1;
    desc.log = harness_log;
    REQUIRE_OK(cvk_context_create(&desc, &ctx, &err), err);
    cvk_context_info info = cvk_context_get_info(ctx);
    CHECK(info.validation, "the validation layer is not on");
    return ctx;
}

/* Destroys the context, checks it saw no validation message and prints the summary;
   returns the exit status of the test program. */
static inline int harness_finish(cvk_context* ctx)
{
    if (ctx) {
        uint32_t messages = cvk_context_validation_message_count(ctx);
        CHECK(messages == 0, "%u validation messages", messages);
        cvk_context_destroy(ctx);
    }
    printf("%d checks, %d failed\n", harness_checks, harness_failures);
    return harness_failures ? 1 : 0;
}

/* Deterministic pseudo-random numbers for test inputs (xorshift32). */
typedef struct harness_rng {
    uint32_t state;
} harness_rng;

static inline uint32_t harness_next(harness_rng* r)
{
    uint32_t x = r->state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return r->state = x;
}

/* Uniform in [lo, hi). */
static inline double harness_uniform(harness_rng* r, double lo, double hi)
{
    return lo + (hi - lo) * (harness_next(r) >> 8) / (double)(1u << 24);
}

/* A small unpinned cloth for free-fall checks: 12 x 9 particles, shear 1e5 and bend 1e4 N/m. */
static inline cvk_cloth_desc harness_falling_cloth(void)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = 12;
    cloth.grid[1] = 9;
    cloth.stiffness.shear = 1e5f;
    cloth.stiffness.bend = 1e4f;
    return cloth;
}

/* cvk_sim_create with the default description for `scene`. */
static inline cvk_result harness_sim_create(cvk_context* ctx, const cvk_scene_desc* scene,
                                            cvk_sim** out_sim, cvk_error* err)
{
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = scene;
    return cvk_sim_create(ctx, &desc, out_sim, err);
}

static inline float* harness_read_all(cvk_sim* sim)
{
    cvk_error err;
    uint64_t n = cvk_sim_particle_count(sim);
    float* xyz = malloc(3 * n * sizeof(float));
    if (!xyz) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    REQUIRE_OK(cvk_sim_read_positions(sim, xyz, n, &err), err);
    return xyz;
}

/* The dispatches of the pass named `name` in the last frame (0 when the plan has none). */
static inline uint32_t harness_pass_dispatches(cvk_sim* sim, const char* name)
{
    cvk_sim_stats st;
    cvk_error err;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    for (uint32_t i = 0; i < st.pass_count; i++)
        if (!strcmp(st.passes[i].name, name))
            return st.passes[i].dispatches;
    return 0;
}

/* A level plane 10 m below the origin: contact in the plan that touches no cloth near it. */
static inline cvk_collider_desc harness_far_plane(void)
{
    cvk_collider_desc plane = cvk_default_collider_desc();
    plane.type = CVK_COLLIDER_PLANE;
    plane.point[1] = -10.0f;
    plane.normal[1] = 1.0f;
    return plane;
}

/* Largest |a − b| over n coordinates. */
static inline double harness_max_diff(const float* a, const float* b, uint64_t n)
{
    double worst = 0.0;
    for (uint64_t i = 0; i < n; i++) {
        double d = fabs((double)a[i] - (double)b[i]);
        if (d > worst || isnan(d))
            worst = d;
    }
    return worst;
}

/* One frame of `scene` on the device from (xyz, v) in user order; the result replaces them,
   and the statistics go to *st (may be NULL). */
static inline void harness_frame_from(cvk_context* ctx, const cvk_scene_desc* scene, float* xyz,
                                      float* v, cvk_sim_stats* st)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    uint64_t n = cvk_sim_particle_count(sim);
    REQUIRE_OK(cvk_sim_write_state(sim, xyz, v, n, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
    REQUIRE_OK(cvk_sim_read_state(sim, xyz, v, n, &err), err);
    if (st)
        REQUIRE_OK(cvk_sim_get_stats(sim, st, &err), err);
    cvk_sim_destroy(sim);
}

/* A random start for `scene` (n particles): its built positions moved by up to ±dx m and
   velocities up to ±dv m/s, each coordinate; the caller frees both. */
static inline void harness_random_start(cvk_context* ctx, const cvk_scene_desc* scene,
                                        harness_rng* rng, double dx, double dv, uint64_t n,
                                        float** x0, float** v0)
{
    cvk_error err;
    cvk_sim* probe;
    REQUIRE_OK(harness_sim_create(ctx, scene, &probe, &err), err);
    *x0 = harness_read_all(probe);
    cvk_sim_destroy(probe);
    *v0 = malloc(3 * n * sizeof(float));
    for (uint64_t i = 0; i < 3 * n; i++) {
        (*x0)[i] += (float)harness_uniform(rng, -dx, dx);
        (*v0)[i] = (float)harness_uniform(rng, -dv, dv);
    }
}

/* Energy over `frames` frames of one step each: how often it grew by more than 1e-6 of its
   start (float positions round it), the largest such rise, the start, and the statistics at
   the end. Stops the program when a step fails. */
typedef struct harness_energy_run {
    uint32_t rises;
    double worst_rise, start;
    cvk_sim_stats end;
} harness_energy_run;

static inline harness_energy_run harness_energy_watch(cvk_sim* sim, uint32_t frames)
{
    harness_energy_run run = {.worst_rise = -INFINITY};
    cvk_error err;
    REQUIRE_OK(cvk_sim_get_stats(sim, &run.end, &err), err);
    double previous = run.end.energy;
    run.start = previous;
    for (uint32_t f = 0; f < frames; f++) {
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_sim_get_stats(sim, &run.end, &err), err);
        double rise = run.end.energy - previous;
        if (rise > 1e-6 * fabs(run.start)) {
            run.rises++;
            run.worst_rise = fmax(run.worst_rise, rise);
        }
        previous = run.end.energy;
    }
    return run;
}

/* Parsing `json_text` (as file "t.json") fails as bad input with exactly `want`. */
#define harness_expect_scene_message(json_text, want)                                           \
    do {                                                                                        \
        cvk_scene* scene_ = NULL;                                                               \
        cvk_error err_ = {0};                                                                   \
        cvk_result r_ = cvk_scene_parse((json_text), "t.json", NULL, 0, &scene_, &err_);        \
        CHECK(r_ == CVK_ERROR_INVALID_ARGUMENT, "%s: parsed", (json_text));                     \
        CHECK(strcmp(err_.message, (want)) == 0, "%s: got \"%s\", want \"%s\"", (json_text),  \
              err_.message, (want));                                                            \
        cvk_scene_destroy(scene_);                                                              \
    } while (0)

/* Two narrow strips, the second laid across the first (the square where they cross holds no
   particle of either, so only their edges meet: collision.edges): below, 6 x 2 particles along
   x, 1 m by 0.1 m (z in ±0.05; the particles nearest the crossing at x = ±0.1) at height
   below_y; above, 2 x 6 along z, 0.12 m by 1 m (x in ±0.06; particles at z = ±0.1) at
   above_y. */
static inline void harness_strips_across(cvk_cloth_desc strips[2], float below_y, float above_y)
{
    strips[0] = cvk_default_cloth_desc();
    strips[1] = cvk_default_cloth_desc();
    strips[0].grid[0] = 6, strips[0].grid[1] = 2;
    strips[0].size[0] = 1.0f, strips[0].size[1] = 0.1f;
    strips[0].origin[0] = -0.5f, strips[0].origin[1] = below_y, strips[0].origin[2] = -0.05f;
    strips[1].grid[0] = 2, strips[1].grid[1] = 6;
    strips[1].size[0] = 0.12f, strips[1].size[1] = 1.0f;
    strips[1].origin[0] = -0.06f, strips[1].origin[1] = above_y, strips[1].origin[2] = -0.5f;
}

#endif
