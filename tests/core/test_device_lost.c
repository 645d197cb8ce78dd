/* Device loss (lib/core/gpu.c: cvk_queue_submit, cvk_fence_wait): the context's test injection makes
   a fence wait report VK_ERROR_DEVICE_LOST, as a driver reset would. Then
   - the call that saw it returns CVK_ERROR_DEVICE_LOST with a sentence that says so;
   - every later call that would submit or wait (step, read-back, draw, a new simulation's
     upload) returns CVK_ERROR_DEVICE_LOST without calling Vulkan: the wait counter stands still;
   - destroying everything (which skips vkQueueWaitIdle) neither hangs nor draws a validation
     message. */
#include <string.h>

#include "core/context.h"
#include "harness.h"

static cvk_scene_desc small_scene(cvk_cloth_desc* cloth)
{
    *cloth = cvk_default_cloth_desc();
    cloth->grid[0] = 6;
    cloth->grid[1] = 5;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloth;
    scene.cloth_count = 1;
    scene.substeps = 2;
    return scene;
}

int main(void)
{
    cvk_context* ctx = harness_context();
    cvk_cloth_desc cloth;
    cvk_scene_desc scene = small_scene(&cloth);
    cvk_error err = {.message = ""};
    cvk_sim* sim = NULL;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    cvk_mesh* mesh = NULL;
    cvk_mesh_desc mdesc = cvk_default_mesh_desc();
    REQUIRE_OK(cvk_mesh_create(sim, &mdesc, &mesh, &err), err);
    cvk_render_desc rdesc = cvk_default_render_desc();
    rdesc.size[0] = 64;
    rdesc.size[1] = 48;
    cvk_renderer* renderer = NULL;
    REQUIRE_OK(cvk_renderer_create(mesh, &rdesc, &renderer, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 3, &err), err);
    CHECK(!cvk_context_lost(ctx), "the device counts as lost before any loss");

    /* The second wait from here on is lost: one frame steps, the next does not. */
    ctx->lose_at_wait = atomic_load(&ctx->fence_waits) + 2;
    REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
    cvk_result r = cvk_sim_step(sim, 1, &err);
    CHECK(r == CVK_ERROR_DEVICE_LOST, "the lost wait returned %s", cvk_result_name(r));
    const char* lost = "vkWaitForFences failed: the device was lost (VK_ERROR_DEVICE_LOST: a "
                       "driver reset, a removed GPU or a hung submission); nothing more is "
                       "submitted to it";
    CHECK(strcmp(err.message, lost) == 0, "message\n  %s\nexpected\n  %s", err.message, lost);
    CHECK(cvk_context_lost(ctx), "the context does not know its device is lost");

    unsigned waits = atomic_load(&ctx->fence_waits);
    const char* after = "the device was lost earlier (VK_ERROR_DEVICE_LOST); vkQueueSubmit was "
                        "not called: objects on this context can only be destroyed";
    r = cvk_sim_step(sim, 1, &err);
    CHECK(r == CVK_ERROR_DEVICE_LOST && strcmp(err.message, after) == 0,
          "a step after the loss: %s, %s", cvk_result_name(r), err.message);
    float xyz[3 * 30];
    r = cvk_sim_read_positions(sim, xyz, 30, &err);
    CHECK(r == CVK_ERROR_DEVICE_LOST, "a read-back after the loss returned %s", cvk_result_name(r));
    r = cvk_renderer_draw(renderer, &err);
    CHECK(r == CVK_ERROR_DEVICE_LOST, "a draw after the loss returned %s", cvk_result_name(r));
    cvk_sim* second = NULL;
    r = harness_sim_create(ctx, &scene, &second, &err);
    CHECK(r == CVK_ERROR_DEVICE_LOST && second == NULL,
          "a simulation created after the loss: %s", cvk_result_name(r));
    CHECK(atomic_load(&ctx->fence_waits) == waits,
          "%u fence waits after the loss (expected none)", atomic_load(&ctx->fence_waits) - waits);

    cvk_renderer_destroy(renderer);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
    return harness_finish(ctx);
}
