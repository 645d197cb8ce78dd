/* clothvk — cloth simulation as Vulkan compute work.
 *
 * Step by step
 * ------------
 * This header includes the others, one per concern (clothvk/context.h, scene.h, sim.h,
 * render.h, over base.h); each step below names its own, which goes on in detail.
 *
 * 1. Make a context (clothvk/context.h). Either the library creates a headless Vulkan
 *    instance and device (the first device, or the one $CLOTHVK_DEVICE names by index or
 *    name substring):
 *
 *        cvk_error err;
 *        cvk_context* ctx;
 *        cvk_context_desc desc = cvk_default_context_desc();
 *        if (cvk_context_create(&desc, &ctx, &err) != CVK_SUCCESS)
 *            fprintf(stderr, "%s\n", err.message);
 *
 *    or it adopts yours: fill instance, physical_device, device, queue_family and queue in
 *    cvk_context_desc. The library never destroys what it adopted.
 *
 * 2. Describe a scene, in code or from a JSON file (format in README.md; clothvk/scene.h):
 *
 *        cvk_cloth_desc cloth = cvk_default_cloth_desc();
 *        cloth.grid[0] = 64; cloth.grid[1] = 64;
 *        cvk_scene_desc scene = cvk_default_scene_desc();
 *        scene.cloths = &cloth; scene.cloth_count = 1;
 *
 *    or   cvk_scene* file; cvk_scene_load("hanging.json", NULL, 0, &file, &err);
 *         const cvk_scene_desc* scene = cvk_scene_get_desc(file);
 *
 * 3. Create a simulation and advance it (clothvk/sim.h). Either record its frames into your
 *    own command buffer (nothing is submitted and nothing waits inside), or call the blocking
 *    step:
 *
 *        cvk_sim_desc sim_desc = cvk_default_sim_desc();
 *        sim_desc.scene = &scene;
 *        cvk_sim* sim;
 *        cvk_sim_create(ctx, &sim_desc, &sim, &err);
 *        cvk_sim_record(sim, my_cmd, 1, &err);   // one frame per submission of my_cmd
 *        cvk_sim_step(sim, 10, &err);            // or: ten frames, submitted and waited for
 *
 * 4. Read the particles back (cloth by cloth: grids row by row, meshes in file order), or
 *    the whole mesh with cvk_sim_read_mesh, and ask for statistics: residual, stretch, NaN
 *    count, GPU time per pass. Let a user pull the cloth: cvk_sim_pick finds the particle
 *    under a ray (a click), cvk_sim_grab drags it to where the mouse goes, frame after frame,
 *    cvk_sim_release lets go (examples/drag.c).
 *
 * 5. See it (clothvk/render.h). A mesh turns the particles into triangles and normals on the
 *    device, every frame, with no trip through the host. Either clothvk draws it
 *    (shadow-mapped, two lights, multisampled, sRGB) and hands you the pixels:
 *
 *        cvk_mesh* mesh;
 *        cvk_mesh_create(sim, NULL, &mesh, &err);
 *        cvk_renderer* renderer;
 *        cvk_renderer_create(mesh, &scene.render, &renderer, &err);
 *        cvk_renderer_draw(renderer, &err);     // or cvk_renderer_record into your buffer
 *        cvk_image image = cvk_renderer_get_image(renderer);
 *        cvk_image_write_png(&image, "frame.png", &err);
 *
 *    or you draw it with your own pipeline: cvk_mesh_record into your command buffer, one
 *    barrier (see cvk_mesh_record), then bind the buffers of cvk_mesh_get_buffers.
 *    examples/embed.c is a complete program that does that.
 *
 * 6. Destroy in reverse order: cvk_renderer_destroy, cvk_mesh_destroy, cvk_sim_destroy,
 *    cvk_scene_destroy, cvk_context_destroy.
 *
 * Rules that hold everywhere
 * - Every fallible call returns a cvk_result; on failure the optional cvk_error receives the
 *   same code and one sentence naming the cause (the JSON key path, the Vulkan call and its
 *   VkResult, the device limit). The library never prints, exits or aborts. A create call
 *   that fails leaves its output pointer NULL.
 * - No global state: objects are independent; one object must not be used from two threads
 *   at once.
 * - Descriptions are plain structs: start from the description's cvk_default_*_desc() and
 *   change what you need (see clothvk/base.h).
 */
#ifndef CLOTHVK_H
#define CLOTHVK_H

/* The headers by concern, in the order of the steps above; each reads top to bottom. */
#include "clothvk/base.h"    /* export macro, results and errors */
#include "clothvk/context.h" /* step 1: the Vulkan instance, device and queue */
#include "clothvk/scene.h"   /* step 2: descriptions and scene files */
#include "clothvk/sim.h"     /* steps 3 and 4: the simulation, statistics, picking and dragging */
#include "clothvk/render.h"  /* step 5: the mesh, the renderer and images */

#define CLOTHVK_VERSION_MAJOR 0
#define CLOTHVK_VERSION_MINOR 1
#define CLOTHVK_VERSION_PATCH 0

#ifdef __cplusplus
extern "C" {
#endif

/* The library's version, "MAJOR.MINOR.PATCH" as in CLOTHVK_VERSION_*: the one it was built as. */
CVK_API const char* cvk_version(void);

#ifdef __cplusplus
}
#endif
#endif /* CLOTHVK_H */
