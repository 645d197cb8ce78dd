#include "plan/plan.h"

#include <stdlib.h>
#include <string.h>

#include "core/checked.h"
#include "core/error.h"
#include "scene/scene.h"

void cvk_plan_init(cvk_plan* plan, uint32_t substeps, uint32_t workgroup_size, uint32_t max_groups)
{
    *plan = (cvk_plan){
        .substeps = substeps,
        .workgroup_size = workgroup_size,
        .particle_workgroup_size = workgroup_size,
        .fused_workgroup_size = workgroup_size,
        .max_groups = max_groups ? max_groups : 1,
        .walk_items = 1,
    };
}

uint32_t cvk_plan_walk_group_items(const cvk_plan* plan)
{
    return plan->workgroup_size * (plan->walk_items > 1 ? plan->walk_items : 1);
}

#define WALK_MAX_GROUPS 65535u /* maxComputeWorkGroupCount[0] is at least this everywhere */
uint32_t cvk_plan_walk_groups(const cvk_plan* plan, uint32_t count)
{
    uint32_t per_group = cvk_plan_walk_group_items(plan);
    uint32_t groups = count / per_group + (count % per_group != 0);
    return groups < WALK_MAX_GROUPS ? groups : WALK_MAX_GROUPS;
}

void cvk_plan_destroy(cvk_plan* plan)
{
    free(plan->ops);
    free(plan->pass_names);
    free(plan->pass_dispatches);
    memset(plan, 0, sizeof *plan);
}

cvk_result cvk_plan_check(const cvk_plan* plan, cvk_error* error)
{
    if (plan->out_of_memory)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the step plan");
    /* The statistics list every pass (cvk_sim_stats.passes): a plan with more kinds of pass
       than they hold is a defect of the library, refused here rather than listed in part. */
    if (plan->pass_count > CVK_MAX_PASSES)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "the step plan has %u kinds of pass and the statistics list at most %u "
                        "(CVK_MAX_PASSES): a defect of clothvk, please report it",
                        plan->pass_count, CVK_MAX_PASSES);
    uint64_t per_frame = (uint64_t)plan->substeps * plan->op_count;
    if (per_frame > CVK_MAX_FRAME_DISPATCHES)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "substeps: %u substeps × %u operations per substep are %llu operations "
                        "per frame; a frame records at most %u (fewer substeps, sweeps or colours)",
                        plan->substeps, plan->op_count, (unsigned long long)per_frame,
                        CVK_MAX_FRAME_DISPATCHES);
    return CVK_SUCCESS;
}

uint32_t cvk_plan_find_pass(const cvk_plan* plan, const char* name)
{
    for (uint32_t p = 0; p < plan->pass_count; p++)
        if (strcmp(plan->pass_names[p], name) == 0)
            return p;
    return UINT32_MAX;
}

uint32_t cvk_plan_pass(cvk_plan* plan, const char* name)
{
    uint32_t found = cvk_plan_find_pass(plan, name);
    if (found != UINT32_MAX)
        return found;
    if (plan->pass_count == plan->pass_capacity) {
        uint32_t capacity = plan->pass_capacity ? 2 * plan->pass_capacity : 8;
        const char** names = cvk_realloc_array(plan->pass_names, capacity, sizeof *names);
        if (names)
            plan->pass_names = names;
        uint32_t* dispatches = cvk_realloc_array(plan->pass_dispatches, capacity, sizeof *dispatches);
        if (dispatches)
            plan->pass_dispatches = dispatches;
        if (!names || !dispatches) {
            plan->out_of_memory = true;
            return 0;
        }
        plan->pass_capacity = capacity;
    }
    plan->pass_names[plan->pass_count] = name;
    plan->pass_dispatches[plan->pass_count] = 0;
    return plan->pass_count++;
}

/* A zeroed op at the end of the list, which doubles when full. */
static cvk_op* append(cvk_plan* plan, cvk_op_kind kind, uint32_t pass, cvk_barrier barrier)
{
    if (plan->out_of_memory || pass >= plan->pass_count) {
        plan->out_of_memory = true;
        return NULL;
    }
    if (plan->op_count == plan->op_capacity) {
        uint32_t capacity = plan->op_capacity ? 2 * plan->op_capacity : 16;
        cvk_op* ops = capacity > plan->op_capacity ? cvk_realloc_array(plan->ops, capacity, sizeof *ops) : NULL;
        if (!ops) {
            plan->out_of_memory = true;
            return NULL;
        }
        plan->ops = ops;
        plan->op_capacity = capacity;
    }
    cvk_op* op = &plan->ops[plan->op_count++];
    memset(op, 0, sizeof *op);
    op->kind = kind;
    op->pass = pass;
    op->barrier = barrier;
    plan->pass_dispatches[pass]++;
    if (kind != CVK_OP_DISPATCH)
        plan->has_transfer = true;
    return op;
}

static void set_dispatch(cvk_plan* plan, cvk_op* op, cvk_pipeline_id pipeline,
                         VkPipelineLayout layout, VkDescriptorSet set, cvk_domain domain,
                         const void* push, uint32_t push_bytes)
{
    op->pipeline = pipeline;
    op->layout = layout;
    op->set = set;
    op->domain = domain;
    op->push_bytes = push_bytes < CVK_PUSH_MAX_BYTES ? push_bytes : CVK_PUSH_MAX_BYTES;
    if (push)
        memcpy(op->push, push, op->push_bytes);
    plan->uses[pipeline] = true;
}

cvk_op* cvk_plan_dispatch(cvk_plan* plan, uint32_t pass, cvk_pipeline_id pipeline,
                          VkPipelineLayout layout, VkDescriptorSet set, cvk_domain domain,
                          uint32_t first, uint32_t count, const void* push, uint32_t push_bytes)
{
    if (count == 0)
        return NULL;
    cvk_op* op = append(plan, CVK_OP_DISPATCH, pass, CVK_BARRIER_COMPUTE_TO_COMPUTE);
    if (!op)
        return NULL;
    set_dispatch(plan, op, pipeline, layout, set, domain, push, push_bytes);
    op->first = first;
    op->count = count;
    op->groups = cvk_plan_groups_of(plan, pipeline, count);
    return op;
}

static uint32_t groups_of_size(const cvk_plan* plan, uint32_t size, uint32_t count)
{
    uint32_t groups = (count + size - 1) / size;
    return groups < plan->max_groups ? groups : plan->max_groups;
}

uint32_t cvk_plan_groups(const cvk_plan* plan, uint32_t count)
{
    return groups_of_size(plan, plan->workgroup_size, count);
}

uint32_t cvk_plan_groups_of(const cvk_plan* plan, cvk_pipeline_id pipeline, uint32_t count)
{
    if (!cvk_pipeline_streams_particles(pipeline))
        return groups_of_size(plan, plan->workgroup_size, count);
    uint32_t groups = groups_of_size(plan, plan->particle_workgroup_size, count);
    uint32_t items = plan->particle_group_items;
    if (items > 1) {
        uint32_t floor_groups = count / items + (count % items != 0);
        if (floor_groups == 0)
            floor_groups = 1;
        if (groups > floor_groups)
            groups = floor_groups;
    }
    return groups;
}

cvk_op* cvk_plan_dispatch_indirect(cvk_plan* plan, uint32_t pass, cvk_pipeline_id pipeline,
                                   VkPipelineLayout layout, VkDescriptorSet set,
                                   cvk_domain domain, VkBuffer buffer, VkDeviceSize offset,
                                   const void* push, uint32_t push_bytes)
{
    cvk_op* op = append(plan, CVK_OP_DISPATCH_INDIRECT, pass, CVK_BARRIER_COMPUTE_TO_COMPUTE);
    if (!op)
        return NULL;
    set_dispatch(plan, op, pipeline, layout, set, domain, push, push_bytes);
    op->buffer = buffer;
    op->offset = offset;
    return op;
}

cvk_op* cvk_plan_fill(cvk_plan* plan, uint32_t pass, VkBuffer buffer, VkDeviceSize offset,
                      VkDeviceSize size, uint32_t value)
{
    cvk_op* op = append(plan, CVK_OP_FILL, pass, CVK_BARRIER_TRANSFER_TO_COMPUTE);
    if (!op)
        return NULL;
    op->buffer = buffer;
    op->offset = offset;
    op->size = size;
    op->value = value;
    return op;
}

cvk_op* cvk_plan_copy(cvk_plan* plan, uint32_t pass, VkBuffer src, VkDeviceSize src_offset,
                      VkBuffer dst, VkDeviceSize dst_offset, VkDeviceSize size)
{
    cvk_op* op = append(plan, CVK_OP_COPY, pass, CVK_BARRIER_TRANSFER_TO_COMPUTE);
    if (!op)
        return NULL;
    op->src = src;
    op->src_offset = src_offset;
    op->buffer = dst;
    op->offset = dst_offset;
    op->size = size;
    return op;
}

static bool is_dispatch(const cvk_op* op)
{
    return op->kind == CVK_OP_DISPATCH || op->kind == CVK_OP_DISPATCH_INDIRECT;
}

cvk_result cvk_plan_require_pipelines(const cvk_plan* plan, cvk_context* context,
                                      cvk_pipelines* pipelines, const cvk_spec_inputs* inputs,
                                      bool* created, cvk_error* error)
{
    *created = false;
    for (uint32_t i = 0; i < plan->op_count; i++) {
        const cvk_op* op = &plan->ops[i];
        if (!is_dispatch(op) || pipelines->pipeline[op->pipeline])
            continue;
        cvk_result r = cvk_pipelines_require(context, pipelines, op->pipeline, op->layout, inputs,
                                             error);
        if (r != CVK_SUCCESS)
            return r;
        *created = true;
    }
    return CVK_SUCCESS;
}

const char* cvk_op_kind_name(cvk_op_kind kind)
{
    switch (kind) {
    case CVK_OP_DISPATCH: return "dispatch";
    case CVK_OP_DISPATCH_INDIRECT: return "indirect";
    case CVK_OP_FILL: return "fill";
    case CVK_OP_COPY: return "copy";
    }
    return "?";
}

const char* cvk_domain_name(cvk_domain domain)
{
    switch (domain) {
    case CVK_DOMAIN_PARTICLES: return "particles";
    case CVK_DOMAIN_SPRINGS: return "springs";
    case CVK_DOMAIN_TRIANGLES: return "triangles";
    case CVK_DOMAIN_CELLS: return "cells";
    }
    return "?";
}

const char* cvk_barrier_name(cvk_barrier barrier)
{
    switch (barrier) {
    case CVK_BARRIER_NONE: return "none";
    case CVK_BARRIER_COMPUTE_TO_COMPUTE: return "compute->compute";
    case CVK_BARRIER_COMPUTE_TO_INDIRECT: return "compute->indirect";
    case CVK_BARRIER_COMPUTE_TO_TRANSFER: return "compute->transfer";
    case CVK_BARRIER_TRANSFER_TO_COMPUTE: return "transfer->compute";
    case CVK_BARRIER_TRANSFER_TO_TRANSFER: return "transfer->transfer";
    }
    return "?";
}

uint32_t cvk_plan_frame_ops(const cvk_plan* plan, uint32_t pass)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < plan->op_count; i++)
        if (pass == UINT32_MAX || plan->ops[i].pass == pass)
            for (uint32_t sub = 0; sub < plan->substeps; sub++)
                n += cvk_op_runs(&plan->ops[i], sub);
    return n;
}

bool cvk_op_runs(const cvk_op* op, uint32_t sub)
{
    return op->every <= 1 || sub % op->every == 0;
}
