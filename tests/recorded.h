/* A frame recorded into the test's own command buffer, as an application records it
   (cvk_sim_record), for the tests that submit it again and again and compare with
   cvk_sim_step. Needs harness.h and the internal gpu.h. */
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

#endif
