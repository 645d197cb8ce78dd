/* A frame recorded into the test's own command buffer, as an application records it
   (cvk_sim_record), for the tests that submit it again and again and compare with
   cvk_sim_step; and device buffers read back. Needs harness.h and the internal gpu.h. */
#ifndef CVK_TEST_RECORDED_H
#define CVK_TEST_RECORDED_H

#include "core/gpu.h"
#include "harness.h"

/* A submitter and one command buffer holding `frames` frames of `sim`; the caller destroys
   the submitter. */
static inline VkCommandBuffer harness_record(cvk_context* ctx, cvk_sim* sim, uint32_t frames,
                                             cvk_submitter* sub)
{
    cvk_error err;
    VkCommandBuffer cmd;
    REQUIRE_OK(cvk_submitter_create(ctx, sub, &err), err);
    REQUIRE_OK(cvk_command_buffer_allocate(ctx, sub, &cmd, &err), err);
    REQUIRE_OK(cvk_command_buffer_begin(cmd, 0, &err), err);
    REQUIRE_OK(cvk_sim_record(sim, cmd, frames, &err), err);
    REQUIRE_OK(cvk_command_buffer_end(cmd, &err), err);
    return cmd;
}

/* Submits `cmd` `times` times, waiting for each. */
static inline void harness_submit(cvk_context* ctx, cvk_submitter* sub, VkCommandBuffer cmd,
                                  uint32_t times)
{
    cvk_error err;
    for (uint32_t i = 0; i < times; i++)
        REQUIRE_OK(cvk_submit_and_wait(ctx, sub, &cmd, 1, &err), err);
}

/* A copy of the first `size` bytes of a device buffer the compute passes wrote (freed by the
   caller), read back through a host buffer. */
static inline void* harness_read_buffer(cvk_context* ctx, VkBuffer buffer, VkDeviceSize size)
{
    cvk_error err;
    cvk_submitter sub;
    VkCommandBuffer cmd;
    cvk_buffer host;
    REQUIRE_OK(cvk_submitter_create(ctx, &sub, &err), err);
    REQUIRE_OK(cvk_command_buffer_allocate(ctx, &sub, &cmd, &err), err);
    REQUIRE_OK(cvk_buffer_create(ctx, size ? size : 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 CVK_MEMORY_HOST, "readback", &host, &err), err);
    REQUIRE_OK(cvk_command_buffer_begin(cmd, 0, &err), err);
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    if (size > 0) {
        VkBufferCopy region = {0, 0, size};
        vkCmdCopyBuffer(cmd, buffer, host.buffer, 1, &region);
    }
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    REQUIRE_OK(cvk_command_buffer_end(cmd, &err), err);
    REQUIRE_OK(cvk_submit_and_wait(ctx, &sub, &cmd, 1, &err), err);
    void* copy = malloc(size ? size : 1);
    if (!copy) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    memcpy(copy, host.mapped, size);
    cvk_buffer_destroy(ctx, &host);
    cvk_submitter_destroy(ctx, &sub);
    return copy;
}

#endif
