/* Fused Gauss-Seidel sweeps (shaders/solvers/pd_fused.comp): where they run, and their op. */
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "solvers/solve_pd.h"

_Static_assert(sizeof(cvk_pd_fused_push) == 128, "cvk_pd_fused_push: 128 bytes in GLSL");
_Static_assert(offsetof(cvk_pd_fused_push, iterations) == 52,
               "cvk_pd_fused_push.iterations at 52");
_Static_assert(offsetof(cvk_pd_fused_push, ends0) == 64, "cvk_pd_fused_push.ends0: a uvec4 at 64");
_Static_assert(sizeof(cvk_pd_fused_push) <= CVK_PUSH_MAX_BYTES, "within the guaranteed push size");

uint32_t cvk_pd_fused_copies(const cvk_build* b, uint32_t instances)
{
    uint32_t n = instances;
    if (n <= 1 || b->cloth_count % n != 0 || b->particle_count % n != 0 ||
        b->free_count / n > CVK_PD_FUSED_MAX_PARTICLES ||
        b->colour_count == 0 || b->colour_count > CVK_PD_FUSED_MAX_COLOURS)
        return 1;
    uint32_t per_copy = b->particle_count / n, cloths = b->cloth_count / n;
    for (uint32_t k = 0; k < n; k++)
        if (b->cloths[k * cloths].first_user != k * per_copy)
            return 1;
    /* copy k's particles of colour c at start[c] + k size / n, its pinned ones at free + k P */
    for (uint32_t c = 0; c <= b->colour_count; c++) {
        uint32_t start = c < b->colour_count ? b->colour_start[c] : b->free_count;
        uint32_t end = c < b->colour_count ? b->colour_start[c + 1] : b->particle_count;
        if ((end - start) % n != 0)
            return 1;
        uint32_t size = (end - start) / n;
        for (uint32_t p = start; p < end; p++)
            if (b->user_of[p] / per_copy != (p - start) / size)
                return 1;
    }
    return n;
}

const char* cvk_pd_fuse_refusal(const cvk_build* b, const cvk_solver_desc* solver, bool checking,
                                uint32_t copies)
{
    if (solver->fuse == CVK_FUSE_OFF)
        return "solver.fuse off";
    if (solver->linear != CVK_LINEAR_RBGS)
        return "not rbgs";
    if (checking)
        return "a checked solve (tolerance)";
    if (b->free_count == 0)
        return "no free particles";
    if (copies <= 1 && b->free_count > CVK_PD_FUSED_MAX_PARTICLES)
        return "over 65535 free particles";
    if (b->colour_count == 0 || b->colour_count > CVK_PD_FUSED_MAX_COLOURS)
        return "over 24 colours";
    if (b->colour_start[0] != 0)
        return "colours not from particle 0";
    /* The one workgroup's barriers and serial sweeps cost more than the dispatches they save
       wherever this was measured: on lavapipe (docs/figures/fused) and on an NVIDIA H200
       (docs/figures/gpu-h200: peer-hanging.json 2.50 ms a frame fused, 0.73 unfused). */
    if (solver->fuse == CVK_FUSE_AUTO)
        return "solver.fuse auto, which does not fuse: slower on every device measured";
    return NULL;
}

cvk_pd_fused_push cvk_pd_fused_push_of(const cvk_pd_push* base, const cvk_build* b,
                                       uint32_t sweeps, uint32_t outers, float last_omega,
                                       uint32_t copies)
{
    cvk_pd_fused_push push;
    memset(&push, 0, sizeof push);
    memcpy(&push, base, sizeof *base);
    push.first = 0;
    push.count = b->free_count;
    push.iterations = (sweeps & 0xffffu) | outers << 16;
    push.last_omega = last_omega;
    push.colours = b->colour_count | copies << 8;
    uint32_t* ends[3] = {push.ends0, push.ends1, push.ends2};
    for (uint32_t c = 0; c < b->colour_count && c < CVK_PD_FUSED_MAX_COLOURS; c++) {
        uint32_t end = (b->colour_start[c + 1] / copies) & 0xffffu; /* one copy's */
        ends[c / 8][(c % 8) / 2] |= c % 2 == 0 ? end : end << 16;
    }
    return push;
}

cvk_op* cvk_pd_add_fused(cvk_plan* plan, uint32_t pass, VkPipelineLayout layout,
                         VkDescriptorSet set, const cvk_pd_fused_push* push,
                         cvk_pipeline_id pipeline)
{
    cvk_op* op = cvk_plan_dispatch(plan, pass, pipeline, layout, set,
                                   CVK_DOMAIN_PARTICLES, 0, push->count, push, sizeof *push);
    /* a workgroup a copy, its barriers ordering the colours, up to the plan's workgroups a
       dispatch (the device's limit at most): each strides over the copies past them */
    uint32_t copies = push->colours >> 8;
    if (op)
        op->groups = copies < plan->max_groups ? copies : plan->max_groups;
    return op;
}
