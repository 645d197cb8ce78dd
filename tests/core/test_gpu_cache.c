/* The context's shared layouts and pipelines (lib/core/gpu_cache.h): a second simulation of a
   scene on the same context adds nothing to the context's table and steps to the same bits as
   the first did; one with another workgroup size adds pipelines, and only pipelines (its
   layouts are those of the first); a simulation of the scene on a fresh context, which makes
   every object anew, gives the same bits again. The harness fails on any validation message,
   and the sanitized run on any leak of the table. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "harness.h"

/* A cloth with self-contact falling on a sphere and a box: the solver, detection, hash and
   contact passes all make pipelines. */
static const char* const SCENE =
    "{\"substeps\": 4, \"solver\": {\"outer_iterations\": 2, \"inner_iterations\": 4},"
    " \"collision\": {\"self\": true},"
    " \"cloths\": [{\"grid\": [12, 12], \"size\": [0.5, 0.5], \"origin\": [-0.25, 0.3, -0.25]}],"
    " \"colliders\": [{\"type\": \"sphere\", \"radius\": 0.2},"
    " {\"type\": \"box\", \"center\": [0, 0.1, 0], \"half_extents\": [0.1, 0.1, 0.1]}]}";
#define FRAMES 4

/* The positions after FRAMES frames (NULL on failure), and the particle count. */
static float* run(cvk_context* ctx, const cvk_scene_desc* scene, uint32_t workgroup_size,
                  uint64_t* count)
{
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = scene;
    desc.workgroup_size = workgroup_size;
    desc.timing = -1;
    cvk_sim* sim = NULL;
    cvk_error err;
    cvk_result r = cvk_sim_create(ctx, &desc, &sim, &err);
    CHECK(r == CVK_SUCCESS, "create (workgroup size %u): %s", workgroup_size, err.message);
    if (r != CVK_SUCCESS)
        return NULL;
    float* xyz = NULL;
    r = cvk_sim_step(sim, FRAMES, &err);
    CHECK(r == CVK_SUCCESS, "step (workgroup size %u): %s", workgroup_size, err.message);
    if (r == CVK_SUCCESS) {
        *count = cvk_sim_particle_count(sim);
        xyz = harness_read_all(sim);
    }
    cvk_sim_destroy(sim);
    return xyz;
}

/* How many objects of each kind the table holds: set layouts, pipeline layouts, pipelines. */
static void kinds(const cvk_context* ctx, uint32_t out[3])
{
    out[0] = out[1] = out[2] = 0;
    for (uint32_t i = 0; i < ctx->cache.count; i++)
        out[cvk_gpu_cache_kind(&ctx->cache, i)]++;
}

static void check_same(const char* what, const float* a, const float* b, uint64_t count)
{
    if (!a || !b)
        return;
    CHECK(memcmp(a, b, 3 * count * sizeof(float)) == 0, "%s: positions differ from the first "
          "simulation's (largest difference %g m)", what, harness_max_diff(a, b, 3 * count));
}

int main(void)
{
    cvk_context* ctx = harness_context();
    cvk_scene* scene = NULL;
    cvk_error err;
    CHECK(cvk_scene_parse(SCENE, "cache.json", NULL, 0, &scene, &err) == CVK_SUCCESS, "%s",
          err.message);
    if (!scene)
        return harness_finish(ctx);
    const cvk_scene_desc* desc = cvk_scene_get_desc(scene);

    uint64_t count = 0;
    CHECK(ctx->cache.count == 0, "a new context's table holds %u objects", ctx->cache.count);
    float* first = run(ctx, desc, 0, &count);
    uint32_t after_first[3], after_second[3], after_other[3];
    kinds(ctx, after_first);
    CHECK(after_first[0] > 0 && after_first[1] > 0 && after_first[2] > 0,
          "after the first simulation the table holds %u set layouts, %u pipeline layouts and %u "
          "pipelines", after_first[0], after_first[1], after_first[2]);

    float* second = run(ctx, desc, 0, &count);
    kinds(ctx, after_second);
    CHECK(memcmp(after_first, after_second, sizeof after_first) == 0,
          "the second simulation of the scene made objects: %u, %u, %u set layouts, pipeline "
          "layouts, pipelines, were %u, %u, %u", after_second[0], after_second[1],
          after_second[2], after_first[0], after_first[1], after_first[2]);
    check_same("the second simulation", first, second, count);

    float* other = run(ctx, desc, 32, &count);
    kinds(ctx, after_other);
    CHECK(after_other[2] > after_first[2] && after_other[0] == after_first[0] &&
              after_other[1] == after_first[1],
          "workgroup size 32: %u, %u, %u set layouts, pipeline layouts, pipelines, were %u, %u, "
          "%u (only pipelines should be new)", after_other[0], after_other[1], after_other[2],
          after_first[0], after_first[1], after_first[2]);
    check_same("workgroup size 32", first, other, count);
    printf("the table: %u set layouts, %u pipeline layouts, %u pipelines after a simulation; "
           "none more after a second; %u pipelines after one of workgroup size 32\n",
           after_first[0], after_first[1], after_first[2], after_other[2]);

    cvk_context* fresh_ctx = harness_context();
    float* fresh = run(fresh_ctx, desc, 0, &count);
    check_same("a fresh context", first, fresh, count);
    CHECK(cvk_context_validation_message_count(fresh_ctx) == 0, "fresh context: %u validation "
          "messages", cvk_context_validation_message_count(fresh_ctx));
    cvk_context_destroy(fresh_ctx);

    free(first);
    free(second);
    free(other);
    free(fresh);
    cvk_scene_destroy(scene);
    return harness_finish(ctx);
}
