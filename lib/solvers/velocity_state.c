/* Positions and velocities through the staging buffer, and the adjacency upload, for the
   families that keep velocities (velocity_state.h). */
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "solvers/velocity_state.h"
#include "features/tear.h"

cvk_result cvk_vstate_upload_adjacency(cvk_sim* s, cvk_buffer* adjacency, const uint32_t* alive,
                                       cvk_error* error)
{
    const cvk_build* b = &s->build;
    size_t entries = (size_t)b->max_degree * b->free_count;
    if (entries == 0)
        return CVK_SUCCESS;
    uint32_t* data = malloc(entries * 4 * sizeof(uint32_t));
    if (!data)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the adjacency");
    for (size_t e = 0; e < entries; e++) {
        float k = cvk_tear_entry_torn(b, alive, e) ? 0.0f : b->adj_k[e];
        data[4 * e] = b->adj_index[e];
        memcpy(&data[4 * e + 1], &k, 4);
        memcpy(&data[4 * e + 2], &b->adj_rest[e], 4);
        data[4 * e + 3] = 0;
    }
    cvk_result r = cvk_device_upload(&s->device, adjacency, data, entries * 16, error);
    free(data);
    return r;
}

cvk_result cvk_vstate_set_torn(cvk_sim* s, cvk_buffer* adjacency, const uint32_t* alive,
                               cvk_error* error)
{
    cvk_result r = cvk_device_upload(&s->device, &s->spring_alive, alive,
                                  (size_t)s->build.spring_count * sizeof *alive, error);
    return r == CVK_SUCCESS ? cvk_vstate_upload_adjacency(s, adjacency, alive, error) : r;
}

cvk_result cvk_vstate_record_readback(cvk_sim* s, VkCommandBuffer cmd, const cvk_buffer* v,
                                      cvk_error* error)
{
    cvk_result r = cvk_command_buffer_begin(cmd, 0, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                    VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    VkDeviceSize n16 = (VkDeviceSize)s->build.particle_count * 16u;
    VkBufferCopy positions = {0, 0, n16}, velocities = {0, n16, n16};
    vkCmdCopyBuffer(cmd, s->positions.buffer, s->device.staging.buffer, 1, &positions);
    vkCmdCopyBuffer(cmd, v->buffer, s->device.staging.buffer, 1, &velocities);
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    return cvk_command_buffer_end(cmd, error);
}

cvk_result cvk_vstate_upload_staged(cvk_sim* s, cvk_buffer* v, cvk_error* error)
{
    VkDeviceSize n16 = (VkDeviceSize)s->build.particle_count * 16u;
    cvk_staging_copy jobs[] = {{&s->positions, 0, 0, n16}, {v, n16, 0, n16}};
    return cvk_device_copy_from_staging(&s->device, jobs, 2, error);
}

cvk_result cvk_vstate_write(cvk_sim* s, cvk_buffer* v, const float* xyz, const float* velocity,
                            cvk_error* error)
{
    const cvk_build* b = &s->build;
    float* xs = s->device.staging.mapped;
    float* vs = xs + 4 * (size_t)b->particle_count;
    for (uint32_t p = 0; p < b->particle_count; p++) {
        bool free_particle = p < b->free_count;
        for (int c = 0; c < 3; c++) {
            xs[4 * p + c] = xyz[3 * (size_t)p + c];
            vs[4 * p + c] = velocity && free_particle ? velocity[3 * (size_t)p + c] : 0.0f;
        }
        xs[4 * p + 3] = 0.0f;
        vs[4 * p + 3] = b->mass[p];
    }
    return cvk_vstate_upload_staged(s, v, error);
}

cvk_result cvk_vstate_read(cvk_sim* s, VkCommandBuffer cmd, float* xyz, float* velocity,
                           cvk_error* error)
{
    cvk_result r = cvk_submit_and_wait(s->device.context, &s->device.submitter, &cmd, 1, error);
    if (r != CVK_SUCCESS)
        return r;
    size_t n = s->build.particle_count;
    const float* x = s->device.staging.mapped;
    const float* v = x + 4 * n;
    for (size_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++) {
            if (xyz)
                xyz[3 * p + c] = x[4 * p + c];
            if (velocity)
                velocity[3 * p + c] = v[4 * p + c];
        }
    return CVK_SUCCESS;
}

cvk_result cvk_vstate_start(cvk_sim* s, cvk_buffer* v, cvk_buffer* adjacency,
                            VkCommandBuffer readback_cmd, cvk_error* error)
{
    cvk_result r = cvk_vstate_upload_adjacency(s, adjacency, NULL, error);
    if (r == CVK_SUCCESS)
        r = cvk_vstate_write(s, v, s->build.position, NULL, error);
    if (r == CVK_SUCCESS)
        r = cvk_vstate_record_readback(s, readback_cmd, v, error);
    return r;
}

cvk_result cvk_vstate_save(cvk_sim* s, VkCommandBuffer readback_cmd, void* data,
                           cvk_error* error)
{
    cvk_result r = cvk_submit_and_wait(s->device.context, &s->device.submitter, &readback_cmd, 1,
                                       error);
    if (r == CVK_SUCCESS)
        memcpy(data, s->device.staging.mapped, 32u * (size_t)s->build.particle_count);
    return r;
}

cvk_result cvk_vstate_load(cvk_sim* s, cvk_buffer* v, const void* data, cvk_error* error)
{
    memcpy(s->device.staging.mapped, data, 32u * (size_t)s->build.particle_count);
    return cvk_vstate_upload_staged(s, v, error);
}
