/* The mesh generation (cvk_mesh_record) recorded alone, submitted and waited for: for the tests
   that read the drawn mesh back. Needs harness.h and the internal gpu.h and render/mesh.h. */
#ifndef CVK_TEST_REGENERATE_H
#define CVK_TEST_REGENERATE_H

static inline void harness_regenerate(cvk_context* ctx, cvk_mesh* mesh)
{
    cvk_error err;
    cvk_submitter sub;
    VkCommandBuffer cmd;
    REQUIRE_OK(cvk_submitter_create(ctx, &sub, &err), err);
    REQUIRE_OK(cvk_command_buffer_allocate(ctx, &sub, &cmd, &err), err);
    REQUIRE_OK(cvk_command_buffer_begin(cmd, 0, &err), err);
    REQUIRE_OK(cvk_mesh_record(mesh, cmd, &err), err);
    REQUIRE_OK(cvk_command_buffer_end(cmd, &err), err);
    REQUIRE_OK(cvk_submit_and_wait(ctx, &sub, &cmd, 1, &err), err);
    cvk_submitter_destroy(ctx, &sub);
}

#endif
