/* The box the drawn things occupy, found on the device every frame (shaders/render/occupied.comp):
   it starts as the colliders' box (each at rest and at each keyframe), written by the frame's
   own commands, and grows by every cloth vertex the mesh pass placed. The ambient occlusion pass
   and the composite pass's costly part cover only its picture grown by what can darken
   (shaders/render/occupied.glsl): on a CPU device, where every pixel of a draw runs its whole
   shader, that is most of their cost. One small dispatch; no host work a frame. */
#include <string.h>

#include "core/error.h"
#include "core/shaders.h"
#include "render/render_internal.h"

/* Items a workgroup's invocation takes at least (few vertices: one workgroup). */
#define OCCUPIED_PER_INVOCATION 16u
#define OCCUPIED_WORKGROUP 64u
#define OCCUPIED_MAX_GROUPS 64u

/* A float's bits made to order as the floats do (occupied.comp's `ordered`). */
static uint32_t ordered(float f)
{
    uint32_t b;
    memcpy(&b, &f, sizeof b);
    return b & 0x80000000u ? ~b : b | 0x80000000u;
}

static const cvk_binding occupied_bindings[] = {
    {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0},
    {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0},
};

cvk_result cvk_render_occupied_create(cvk_renderer* rd, cvk_error* error)
{
    cvk_render_occupied* o = &rd->occupied;
    const cvk_box* drawn = &rd->colliders.framing.drawn;
    bool colliders = drawn->lo[0] <= drawn->hi[0];
    for (int k = 0; k < 3; k++) {
        o->start[k] = colliders ? ordered((float)drawn->lo[k]) : UINT32_MAX;
        o->start[3 + k] = colliders ? ordered((float)drawn->hi[k]) : 0u;
    }
    uint32_t n = rd->mesh->vertex_count;
    uint32_t groups = (n + OCCUPIED_WORKGROUP * OCCUPIED_PER_INVOCATION - 1) / (OCCUPIED_WORKGROUP * OCCUPIED_PER_INVOCATION);
    o->groups = groups < 1 ? 1 : (groups > OCCUPIED_MAX_GROUPS ? OCCUPIED_MAX_GROUPS : groups);
    cvk_result r = cvk_buffer_create(rd->context, sizeof o->start,
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     CVK_MEMORY_DEVICE, "occupied box", &o->box, error);
    if (r == CVK_SUCCESS)
        r = cvk_descriptors_create(rd->context, occupied_bindings, 2, 1, VK_SHADER_STAGE_COMPUTE_BIT,
                                   sizeof(uint32_t), &o->descriptors, error);
    if (r != CVK_SUCCESS)
        return r;
    const cvk_resource res[2] = {{.buffer = &rd->mesh->vertices}, {.buffer = &o->box}};
    cvk_descriptors_write(rd->context, &o->descriptors, 0, res);
    cvk_spirv spirv = cvk_shader(CVK_SHADER_OCCUPIED_COMP);
    const cvk_spec none = {.count = 0};
    return cvk_compute_pipeline_create(rd->context, spirv.code, spirv.bytes, o->descriptors.pipeline_layout, &none,
                                       spirv.name, &o->pipeline, error);
}

void cvk_render_occupied_record(const cvk_renderer* rd, VkCommandBuffer cmd)
{
    const cvk_render_occupied* o = &rd->occupied;
    /* The last frame's draws have read the box before it starts again. */
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_VERTEX_SHADER_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, 0);
    vkCmdUpdateBuffer(cmd, o->box.buffer, 0, sizeof o->start, o->start);
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, o->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, o->descriptors.pipeline_layout, 0, 1,
                            &o->descriptors.sets[0], 0, NULL);
    uint32_t count = rd->mesh->vertex_count;
    vkCmdPushConstants(cmd, o->descriptors.pipeline_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof count, &count);
    vkCmdDispatch(cmd, o->groups, 1, 1);
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_VERTEX_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
}

void cvk_render_occupied_destroy(cvk_renderer* rd)
{
    cvk_render_occupied* o = &rd->occupied;
    if (o->pipeline)
        vkDestroyPipeline(rd->context->device, o->pipeline, NULL);
    cvk_descriptors_destroy(rd->context, &o->descriptors);
    cvk_buffer_destroy(rd->context, &o->box);
    *o = (cvk_render_occupied){0};
}
