/* The device-buffer layer (core/device.h). */
#include "core/device.h"

#include <string.h>

/* One transfer submit, waited for: the staging copies, or (fill non-NULL) every word of one
   buffer set to `value`; earlier GPU work on them finishes first, later work sees them. */
static cvk_result transfer(cvk_device* d, const cvk_staging_copy* jobs, uint32_t count,
                           const cvk_buffer* fill, uint32_t value, cvk_error* error)
{
    VkCommandBuffer cmd = d->transfer_cmd;
    cvk_result r = cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                    VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    for (uint32_t i = 0; i < count; i++) {
        VkBufferCopy region = {jobs[i].src_offset, jobs[i].dst_offset, jobs[i].size};
        vkCmdCopyBuffer(cmd, d->staging.buffer, jobs[i].dst->buffer, 1, &region);
    }
    if (fill)
        vkCmdFillBuffer(cmd, fill->buffer, 0, VK_WHOLE_SIZE, value);
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                        VK_ACCESS_TRANSFER_READ_BIT);
    if (d->unreset_queries)
        vkCmdResetQueryPool(cmd, d->unreset_queries, 0, d->unreset_query_count);
    r = cvk_command_buffer_end(cmd, error);
    if (r == CVK_SUCCESS)
        r = cvk_submit_and_wait(d->context, &d->submitter, &cmd, 1, error);
    if (r == CVK_SUCCESS)
        d->unreset_queries = VK_NULL_HANDLE;
    return r;
}

cvk_result cvk_device_copy_from_staging(cvk_device* d, const cvk_staging_copy* jobs,
                                        uint32_t count, cvk_error* error)
{
    return transfer(d, jobs, count, NULL, 0, error);
}

cvk_result cvk_device_make_buffer(cvk_device* d, cvk_buffer* buffer, VkDeviceSize size,
                                  const char* what, const void* data, cvk_error* error)
{
    VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                               VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                               VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                               VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
    VkDeviceSize bytes = size; /* what `data` holds; the buffer is never empty */
    if (size < 16)
        size = 16;
    cvk_result r = cvk_buffer_create(d->context, size, usage, CVK_MEMORY_DEVICE, what, buffer,
                                     error);
    if (r == CVK_SUCCESS && data)
        r = cvk_device_upload(d, buffer, data, bytes, error);
    return r;
}

cvk_result cvk_device_fill_buffer(cvk_device* d, cvk_buffer* buffer, unsigned char byte,
                                  cvk_error* error)
{
    return transfer(d, NULL, 0, buffer, byte * 0x01010101u, error);
}

cvk_result cvk_device_clear_buffer(cvk_device* d, cvk_buffer* buffer, cvk_error* error)
{
    return cvk_device_fill_buffer(d, buffer, 0, error);
}

cvk_result cvk_device_upload(cvk_device* d, cvk_buffer* dst, const void* data, VkDeviceSize size,
                             cvk_error* error)
{
    for (VkDeviceSize at = 0; at < size;) {
        VkDeviceSize chunk = size - at < d->staging.size ? size - at : d->staging.size;
        memcpy(d->staging.mapped, (const char*)data + at, chunk);
        cvk_staging_copy job = {dst, 0, at, chunk};
        cvk_result r = cvk_device_copy_from_staging(d, &job, 1, error);
        if (r != CVK_SUCCESS)
            return r;
        at += chunk;
    }
    return CVK_SUCCESS;
}
