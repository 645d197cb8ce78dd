/* Picking on the device (lib/features/pick.h, shaders/features/pick.comp). */
#include <math.h>
#include <string.h>

#include "core/error.h"
#include "features/pick.h"
#include "shared/layout.h"
#include "plan/state.h"

#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
static const cvk_binding pick_bindings[CVK_PICK_BINDING_COUNT] = {
    [CVK_PICK_BINDING_POSITIONS] = STORAGE,
    [CVK_PICK_BINDING_USER_OF] = STORAGE,
    [CVK_PICK_BINDING_RESULT] = STORAGE,
};
#undef STORAGE

#define PICK_GROUP 64u /* local_size_x of pick.comp */

static cvk_result pick_create(cvk_sim* s, cvk_error* error)
{
    cvk_pick* k = s->pick;
    const cvk_build* b = &s->build;
    cvk_result r = cvk_device_make_buffer(&s->device, &k->user_of, 4u * (VkDeviceSize)b->particle_count,
                                       "pick: user order", b->user_of, error);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_create(s->device.context, sizeof(cvk_gpu_pick), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                              CVK_MEMORY_HOST, "pick result", &k->result, error);
    if (r == CVK_SUCCESS)
        r = cvk_descriptors_create(s->device.context, pick_bindings, CVK_PICK_BINDING_COUNT, 1,
                                   VK_SHADER_STAGE_COMPUTE_BIT, sizeof(cvk_pick_push),
                                   &k->descriptors, error);
    cvk_spec_inputs inputs = {.workgroup_size = PICK_GROUP};
    if (r == CVK_SUCCESS)
        r = cvk_pipelines_require(s->device.context, &s->pipelines, CVK_PIPE_PICK,
                                  k->descriptors.pipeline_layout, &inputs, error);
    if (r != CVK_SUCCESS) {
        cvk_pick_destroy(s);
        return r;
    }
    const cvk_resource res[CVK_PICK_BINDING_COUNT] = {
        [CVK_PICK_BINDING_POSITIONS] = {.buffer = &s->positions},
        [CVK_PICK_BINDING_USER_OF] = {.buffer = &k->user_of},
        [CVK_PICK_BINDING_RESULT] = {.buffer = &k->result},
    };
    cvk_descriptors_write(s->device.context, &k->descriptors, 0, res);
    k->ready = true;
    return CVK_SUCCESS;
}

void cvk_pick_destroy(cvk_sim* s)
{
    cvk_pick* k = s->pick;
    cvk_descriptors_destroy(s->device.context, &k->descriptors);
    cvk_buffer_destroy(s->device.context, &k->user_of);
    cvk_buffer_destroy(s->device.context, &k->result);
    k->ready = false;
}

/* The three stages, each after a barrier from the one before (the first after the frames that
   wrote the positions), then one from the last to the host's read. */
static void record_pick(cvk_sim* s, VkCommandBuffer cmd, cvk_pick_push push)
{
    cvk_pick* k = s->pick;
    uint32_t groups = (push.count + PICK_GROUP - 1) / PICK_GROUP;
    uint32_t limit = s->device.context->properties.limits.maxComputeWorkGroupCount[0];
    if (groups > limit)
        groups = limit; /* invocations stride over the rest */
    VkPipelineLayout layout = k->descriptors.pipeline_layout;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, s->pipelines.pipeline[CVK_PIPE_PICK]);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1,
                            &k->descriptors.sets[0], 0, NULL);
    for (uint32_t stage = 0; stage < 3; stage++) {
        cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                        VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
        push.stage = stage;
        vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
        vkCmdDispatch(cmd, groups, 1, 1);
    }
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

static bool finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* The arguments' checks, in the order a caller fixes them. */
static cvk_result check_ray(const float origin[3], const float direction[3], float radius,
                            cvk_error* error)
{
    if (!finite3(origin))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_pick: the ray's origin must be finite, got [%g, %g, %g]",
                        (double)origin[0], (double)origin[1], (double)origin[2]);
    double len2 = 0.0;
    for (int i = 0; i < 3; i++)
        len2 += (double)direction[i] * direction[i];
    if (!finite3(direction) || !(len2 > 0.0))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_pick: the ray's direction must be finite and not zero, got "
                        "[%g, %g, %g]",
                        (double)direction[0], (double)direction[1], (double)direction[2]);
    if (!isfinite(radius) || radius < 0.0f)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_pick: the radius must be finite and at least 0 m, got %g",
                        (double)radius);
    return CVK_SUCCESS;
}

static cvk_particle particle_of_user(const cvk_build* b, uint32_t user)
{
    uint32_t cloth = cvk_build_cloth_of_user(b, user);
    return (cvk_particle){cloth, user - b->cloths[cloth].first_user};
}

cvk_result cvk_sim_pick(cvk_sim* s, const float origin[3], const float direction[3],
                        float radius, cvk_pick_result* out, cvk_error* error)
{
    if (!s || !origin || !direction || !out)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_pick needs a simulation, a ray and a result");
    *out = (cvk_pick_result){0};
    cvk_result r = check_ray(origin, direction, radius, error);
    if (r == CVK_SUCCESS && !s->pick->ready)
        r = pick_create(s, error);
    if (r != CVK_SUCCESS)
        return r;
    double len = sqrt((double)direction[0] * direction[0] + (double)direction[1] * direction[1] +
                      (double)direction[2] * direction[2]);
    cvk_pick_push push = {.radius2 = radius * radius, .count = s->build.particle_count};
    for (int i = 0; i < 3; i++) {
        push.origin[i] = origin[i];
        push.direction[i] = (float)(direction[i] / len);
    }
    cvk_gpu_pick fresh = {.distance_bits = CVK_PICK_NONE, .user = CVK_PICK_NONE};
    memcpy(s->pick->result.mapped, &fresh, sizeof fresh);
    VkCommandBuffer cmd = s->device.transfer_cmd;
    r = cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, error);
    if (r != CVK_SUCCESS)
        return r;
    record_pick(s, cmd, push);
    r = cvk_command_buffer_end(cmd, error);
    if (r == CVK_SUCCESS)
        r = cvk_submit_and_wait(s->device.context, &s->device.submitter, &cmd, 1, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_gpu_pick found;
    memcpy(&found, s->pick->result.mapped, sizeof found);
    if (found.user == CVK_PICK_NONE || found.user >= s->build.particle_count)
        return CVK_SUCCESS; /* a miss */
    float distance;
    memcpy(&distance, &found.distance_bits, sizeof distance);
    out->hit = true;
    out->particle = particle_of_user(&s->build, found.user);
    out->distance = distance;
    for (int i = 0; i < 3; i++)
        out->position[i] = found.position[i];
    return CVK_SUCCESS;
}
