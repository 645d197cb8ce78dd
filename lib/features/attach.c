/* Attachments on the device: the tables the attach pass reads, its descriptor set and its
   op (lib/features/attach.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "features/attach.h"
#include "core/error.h"
#include "scene/motion.h"
#include "shared/layout.h"
#include "contact/collide.h"
#include "plan/state.h"

#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
static const cvk_binding attach_bindings[CVK_ATTACH_BINDING_COUNT] = {
    [CVK_ATTACH_BINDING_FRAME] = STORAGE,     [CVK_ATTACH_BINDING_KEYFRAMES] = STORAGE,
    [CVK_ATTACH_BINDING_ATTACHMENTS] = STORAGE, [CVK_ATTACH_BINDING_ATTACHED] = STORAGE,
    [CVK_ATTACH_BINDING_POSITIONS] = STORAGE, [CVK_ATTACH_BINDING_U0] = STORAGE,
    [CVK_ATTACH_BINDING_U1] = STORAGE,
};
#undef STORAGE

/* Deep copies of the motions, all keyframes in one block (motions[0].keyframes). */
static cvk_result copy_motions(cvk_attach* a, const cvk_scene_desc* scene, uint32_t* keyframes,
                               cvk_error* error)
{
    uint32_t total = 0;
    for (uint32_t i = 0; i < scene->attachment_count; i++)
        total += scene->attachments[i].motion.keyframe_count; /* each ≤ CVK_MAX_KEYFRAMES */
    a->motions = calloc(scene->attachment_count, sizeof *a->motions);
    cvk_keyframe* block = malloc((total ? total : 1) * sizeof *block);
    if (!a->motions || !block) {
        free(block);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the attachments");
    }
    uint32_t k = 0;
    for (uint32_t i = 0; i < scene->attachment_count; i++) {
        const cvk_motion* m = &scene->attachments[i].motion;
        if (m->keyframe_count)
            memcpy(&block[k], m->keyframes, m->keyframe_count * sizeof *block);
        a->motions[i] = (cvk_motion){&block[k], m->keyframe_count, m->loop};
        k += m->keyframe_count;
    }
    a->motions[0].keyframes = block; /* owns the block, even with no keyframes */
    *keyframes = total;
    return CVK_SUCCESS;
}

static cvk_result upload_tables(cvk_sim* s, cvk_attach* a, uint32_t keyframe_count,
                                cvk_error* error)
{
    const cvk_build* b = &s->build;
    float* packed = calloc(8 * (size_t)(keyframe_count ? keyframe_count : 1), sizeof(float));
    cvk_gpu_attachment* table = calloc(a->attachment_count, sizeof *table);
    cvk_gpu_attached* attached = calloc(b->attached_count ? b->attached_count : 1, sizeof *attached);
    cvk_result r = packed && table && attached
                       ? CVK_SUCCESS
                       : cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                                  "out of host memory for the attachment tables");
    for (uint32_t i = 0, k = 0; r == CVK_SUCCESS && i < a->attachment_count; i++) {
        cvk_motion_pack(&a->motions[i], &packed[8 * (size_t)k]);
        table[i] = (cvk_gpu_attachment){k, a->motions[i].keyframe_count, a->motions[i].loop, 0};
        k += a->motions[i].keyframe_count;
    }
    for (uint32_t i = 0; r == CVK_SUCCESS && i < b->attached_count; i++) {
        const float* x = &b->position[3 * (size_t)b->attached[i]];
        attached[i] = (cvk_gpu_attached){{x[0], x[1], x[2], 0.0f}, b->attached[i],
                                         b->attached_to[i], 0, 0};
    }
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &a->keyframes, 32u * (VkDeviceSize)keyframe_count,
                                "attachment keyframes", packed, error);
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &a->attachments, sizeof *table * (VkDeviceSize)a->attachment_count,
                                "attachments", table, error);
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &a->attached, sizeof *attached * (VkDeviceSize)b->attached_count,
                                "attached particles", attached, error);
    free(packed);
    free(table);
    free(attached);
    return r;
}

cvk_result cvk_attach_create(cvk_sim* s, const cvk_scene_desc* scene, cvk_error* error)
{
    cvk_attach* a = s->attach;
    *a = (cvk_attach){0};
    if (scene->attachment_count == 0)
        return CVK_SUCCESS;
    a->attachment_count = scene->attachment_count;
    uint32_t keyframes = 0;
    cvk_result r = copy_motions(a, scene, &keyframes, error);
    if (r == CVK_SUCCESS)
        r = upload_tables(s, a, keyframes, error);
    if (r == CVK_SUCCESS)
        r = cvk_descriptors_create(s->device.context, attach_bindings, CVK_ATTACH_BINDING_COUNT,
                                   CVK_ATTACH_FAMILIES,
                                   VK_SHADER_STAGE_COMPUTE_BIT, sizeof(cvk_attach_push),
                                   &a->descriptors, error);
    return r; /* on failure cvk_sim_destroy calls cvk_attach_destroy */
}

void cvk_attach_destroy(cvk_sim* s)
{
    cvk_attach* a = s->attach;
    cvk_descriptors_destroy(s->device.context, &a->descriptors);
    cvk_buffer* buffers[] = {&a->keyframes, &a->attachments, &a->attached};
    for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; i++)
        cvk_buffer_destroy(s->device.context, buffers[i]);
    if (a->motions)
        free((cvk_keyframe*)a->motions[0].keyframes);
    free(a->motions);
    *a = (cvk_attach){0};
}

void cvk_attach_bind(cvk_sim* s, cvk_attach_family family, const cvk_buffer* u0,
                     const cvk_buffer* u1)
{
    cvk_attach* a = s->attach;
    if (a->attachment_count == 0)
        return;
    const cvk_resource res[CVK_ATTACH_BINDING_COUNT] = {
        [CVK_ATTACH_BINDING_FRAME] = {.buffer = &s->collide->frame},
        [CVK_ATTACH_BINDING_KEYFRAMES] = {.buffer = &a->keyframes},
        [CVK_ATTACH_BINDING_ATTACHMENTS] = {.buffer = &a->attachments},
        [CVK_ATTACH_BINDING_ATTACHED] = {.buffer = &a->attached},
        [CVK_ATTACH_BINDING_POSITIONS] = {.buffer = &s->positions},
        [CVK_ATTACH_BINDING_U0] = {.buffer = u0},
        [CVK_ATTACH_BINDING_U1] = {.buffer = u1},
    };
    cvk_descriptors_write(s->device.context, &a->descriptors, family, res);
    a->bound[family] = true;
}

/* One attach dispatch of `family`'s pipeline and set (implicit: the velocity or the place
   pass); the first of a substep counts it when no collider pass did. */
static cvk_result add_pass(cvk_sim* s, cvk_plan* plan, cvk_attach_family family, bool place,
                           const char* what, cvk_error* error)
{
    cvk_attach* a = s->attach;
    if (a->attachment_count == 0 || s->build.attached_count == 0)
        return CVK_SUCCESS;
    if (!a->bound[family])
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "attachments: this solver does not move attached particles");
    /* The collider pass, when there is one, has counted this substep already. */
    bool counted = place || (s->collide->colliding && s->collide->collider_count > 0);
    cvk_attach_push push = {s->build.attached_count, counted ? 0u : 1u, s->params.dt,
                            place ? 1u : 0u};
    uint32_t pass = cvk_plan_pass(plan, "attach");
    cvk_pipeline_id pipeline = family == CVK_ATTACH_FOR_PD ? CVK_PIPE_ATTACH
                                                           : CVK_PIPE_ATTACH_IMPLICIT;
    cvk_op* op = cvk_plan_dispatch(plan, pass, pipeline, a->descriptors.pipeline_layout,
                                   a->descriptors.sets[family], CVK_DOMAIN_PARTICLES, 0,
                                   s->build.attached_count, &push, sizeof push);
    if (op) {
        op->groups = 1; /* one workgroup: it may advance the frame state */
        snprintf(op->note, sizeof op->note, "%u particles, %s%s", s->build.attached_count, what,
                 counted ? "" : ", step += 1");
    }
    return cvk_plan_check(plan, error);
}

cvk_result cvk_attach_add_passes(cvk_sim* s, cvk_plan* plan, cvk_error* error)
{
    return add_pass(s, plan, CVK_ATTACH_FOR_PD, false, "u = pose(t + dt) start - x", error);
}

cvk_result cvk_attach_add_implicit_pass(cvk_sim* s, cvk_plan* plan, bool place, cvk_error* error)
{
    return add_pass(s, plan, CVK_ATTACH_FOR_IMPLICIT, place,
                    place ? "x = pose(t + h) start" : "v = (pose(t + h) start - x) / h", error);
}

void cvk_attach_position(const cvk_sim* s, uint32_t i, double t, float out[3])
{
    const cvk_build* b = &s->build;
    cvk_pose pose = cvk_motion_pose(&s->attach->motions[b->attached_to[i]], t);
    cvk_pose_apply(&pose, &b->position[3 * (size_t)b->attached[i]], out);
}
