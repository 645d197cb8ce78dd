/* Recording a plan into a command buffer: the one loop every family's passes go through. */
#include "plan/plan.h"

#include "core/checked.h"

#define COMPUTE VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT
#define TRANSFER VK_PIPELINE_STAGE_TRANSFER_BIT
#define SHADER_RW (VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_UNIFORM_READ_BIT)

static void record_barrier(VkCommandBuffer cmd, cvk_barrier barrier)
{
    switch (barrier) {
    case CVK_BARRIER_NONE:
        break;
    case CVK_BARRIER_COMPUTE_TO_COMPUTE:
        cvk_cmd_barrier(cmd, COMPUTE, VK_ACCESS_SHADER_WRITE_BIT, COMPUTE, SHADER_RW);
        break;
    case CVK_BARRIER_COMPUTE_TO_INDIRECT:
        cvk_cmd_barrier(cmd, COMPUTE, VK_ACCESS_SHADER_WRITE_BIT,
                        VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | COMPUTE,
                        VK_ACCESS_INDIRECT_COMMAND_READ_BIT | SHADER_RW);
        break;
    case CVK_BARRIER_COMPUTE_TO_TRANSFER:
        cvk_cmd_barrier(cmd, COMPUTE, VK_ACCESS_SHADER_WRITE_BIT, TRANSFER,
                        VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
        break;
    case CVK_BARRIER_TRANSFER_TO_COMPUTE:
        cvk_cmd_barrier(cmd, TRANSFER, VK_ACCESS_TRANSFER_WRITE_BIT,
                        COMPUTE | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                        SHADER_RW | VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
        break;
    case CVK_BARRIER_TRANSFER_TO_TRANSFER:
        cvk_cmd_barrier(cmd, TRANSFER, VK_ACCESS_TRANSFER_WRITE_BIT, TRANSFER,
                        VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
        break;
    }
}

/* The opening barrier of a frame: earlier compute and transfer writes (the last frame, an
   upload) before anything this plan's first op may do. */
static void record_opening(const cvk_plan* plan, VkCommandBuffer cmd)
{
    VkPipelineStageFlags stages = COMPUTE;
    VkAccessFlags access = SHADER_RW;
    if (plan->has_transfer) {
        stages |= TRANSFER | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT;
        access |= VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                  VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
    }
    cvk_cmd_barrier(cmd, COMPUTE | TRANSFER, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                    stages, access);
}

/* The binding state of a recording, so unchanged pipelines and sets are not bound again. */
typedef struct binder {
    VkPipeline pipeline;
    VkPipelineLayout layout; /* the sets' layout: another (other push ranges) binds them again */
    VkDescriptorSet set, set1, set2;
} binder;

static void record_op(const cvk_op* op, const cvk_pipelines* pipelines, binder* bound,
                      VkCommandBuffer cmd)
{
    switch (op->kind) {
    case CVK_OP_FILL:
        vkCmdFillBuffer(cmd, op->buffer, op->offset, op->size, op->value);
        return;
    case CVK_OP_COPY: {
        VkBufferCopy region = {op->src_offset, op->offset, op->size};
        vkCmdCopyBuffer(cmd, op->src, op->buffer, 1, &region);
        return;
    }
    case CVK_OP_DISPATCH:
    case CVK_OP_DISPATCH_INDIRECT:
        break;
    }
    VkPipeline pipeline = pipelines->pipeline[op->pipeline];
    if (pipeline != bound->pipeline) {
        bound->pipeline = pipeline;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    }
    if (op->set != bound->set || op->layout != bound->layout) {
        bound->set = op->set;
        bound->layout = op->layout;
        /* another layout may have disturbed sets 1 and 2: bind them again */
        bound->set1 = bound->set2 = VK_NULL_HANDLE;
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, op->layout, 0, 1, &op->set, 0,
                                NULL);
    }
    if (op->set1 && op->set1 != bound->set1) {
        bound->set1 = op->set1;
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, op->layout, 1, 1, &op->set1,
                                0, NULL);
    }
    if (op->set2 && op->set2 != bound->set2) {
        bound->set2 = op->set2;
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, op->layout, 2, 1, &op->set2,
                                0, NULL);
    }
    if (op->push_bytes)
        vkCmdPushConstants(cmd, op->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, op->push_bytes,
                           op->push);
    if (op->kind == CVK_OP_DISPATCH)
        vkCmdDispatch(cmd, op->groups, 1, 1);
    else
        vkCmdDispatchIndirect(cmd, op->buffer, op->offset);
}

uint32_t cvk_plan_query_count(const cvk_plan* plan, uint32_t* pass_of)
{
    uint32_t per_substep = 0;
    for (uint32_t i = 0; i < plan->op_count; i++)
        per_substep += i + 1 == plan->op_count || plan->ops[i + 1].pass != plan->ops[i].pass;
    /* One query opens the frame; UINT32_MAX itself is never a valid count. */
    uint32_t total;
    if (!cvk_mul_u32(per_substep, plan->substeps, &total) || total >= UINT32_MAX - 1)
        return UINT32_MAX;
    if (pass_of) {
        uint32_t q = 1;
        for (uint32_t sub = 0; sub < plan->substeps; sub++)
            for (uint32_t i = 0; i < plan->op_count; i++)
                if (i + 1 == plan->op_count || plan->ops[i + 1].pass != plan->ops[i].pass)
                    pass_of[q++] = plan->ops[i].pass;
    }
    return total + 1;
}

void cvk_plan_record_frame(const cvk_plan* plan, const cvk_pipelines* pipelines,
                           const cvk_plan_queries* queries, VkCommandBuffer cmd)
{
    record_opening(plan, cmd);
    bool timed = queries && queries->pool;
    uint32_t query = 0;
    if (timed) {
        vkCmdResetQueryPool(cmd, queries->pool, 0, queries->count);
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries->pool, query++);
    }
    binder bound = {VK_NULL_HANDLE, VK_NULL_HANDLE, VK_NULL_HANDLE, VK_NULL_HANDLE, VK_NULL_HANDLE};
    for (uint32_t sub = 0; sub < plan->substeps; sub++) {
        for (uint32_t i = 0; i < plan->op_count; i++) {
            const cvk_op* op = &plan->ops[i];
            bool skip = !cvk_op_runs(op, sub);
            if (!skip)
                record_op(op, pipelines, &bound, cmd);
            bool pass_ends = i + 1 == plan->op_count || plan->ops[i + 1].pass != op->pass;
            if (timed && pass_ends)
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries->pool,
                                    query++);
            bool last = sub + 1 == plan->substeps && i + 1 == plan->op_count;
            if (!last && !skip)
                record_barrier(cmd, op->barrier);
        }
    }
}

void cvk_plan_record_warm_up(const cvk_plan* plan, cvk_pipelines* pipelines, VkCommandBuffer cmd)
{
    static const unsigned char zeros[CVK_PUSH_MAX_BYTES];
    for (uint32_t i = 0; i < plan->op_count; i++) {
        const cvk_op* op = &plan->ops[i];
        if (op->kind != CVK_OP_DISPATCH && op->kind != CVK_OP_DISPATCH_INDIRECT)
            continue;
        if (!pipelines->fresh[op->pipeline])
            continue;
        pipelines->fresh[op->pipeline] = false;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines->pipeline[op->pipeline]);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, op->layout, 0, 1, &op->set, 0,
                                NULL);
        if (op->set1)
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, op->layout, 1, 1,
                                    &op->set1, 0, NULL);
        if (op->set2)
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, op->layout, 2, 1,
                                    &op->set2, 0, NULL);
        if (op->push_bytes)
            vkCmdPushConstants(cmd, op->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, op->push_bytes,
                               zeros);
        vkCmdDispatch(cmd, 1, 1, 1);
        record_barrier(cmd, CVK_BARRIER_COMPUTE_TO_COMPUTE);
    }
}
