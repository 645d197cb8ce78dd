/* Simulates one frame of a small cloth through the public API only. */
#include <stdio.h>

#include <clothvk.h>

int main(void)
{
    cvk_error err;
    cvk_context* ctx;
    cvk_context_desc ctx_desc = cvk_default_context_desc();
    if (cvk_context_create(&ctx_desc, &ctx, &err) != CVK_SUCCESS) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = 8;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    cvk_sim* sim;
    int status = 1;
    cvk_sim_desc sim_desc = cvk_default_sim_desc();
    sim_desc.scene = &scene;
    if (cvk_sim_create(ctx, &sim_desc, &sim, &err) == CVK_SUCCESS) {
        if (cvk_sim_step(sim, 1, &err) == CVK_SUCCESS) {
            printf("consumer: %llu particles, 1 frame\n", (unsigned long long)cvk_sim_particle_count(sim));
            status = 0;
        }
        cvk_sim_destroy(sim);
    }
    if (status)
        fprintf(stderr, "%s\n", err.message);
    cvk_context_destroy(ctx);
    return status;
}
