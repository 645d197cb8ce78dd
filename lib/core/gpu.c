#include "core/gpu.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* A failed Vulkan call, with what it was for in front: "positions (160000 bytes): ...". */
static int find_memory_type(const cvk_context* context, uint32_t allowed, VkMemoryPropertyFlags want)
{
    const VkPhysicalDeviceMemoryProperties* m = &context->memory;
    for (uint32_t i = 0; i < m->memoryTypeCount; i++)
        if ((allowed & (1u << i)) && (m->memoryTypes[i].propertyFlags & want) == want)
            return (int)i;
    return -1;
}

/* Device-local memory where the device has it (a CPU device may not), else any allowed type. */
static int device_memory_type(const cvk_context* context, uint32_t allowed)
{
    int type = find_memory_type(context, allowed, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    return type >= 0 ? type : find_memory_type(context, allowed, 0);
}

/* An allocation larger than the heap it would come from is invalid usage (Vulkan's
   VUID-vkAllocateMemory-pAllocateInfo-01713), not an out-of-memory error: refuse it first, as a
   limit of the device, with both figures. */
static cvk_result check_heap(const cvk_context* context, int type, VkDeviceSize size,
                             const char* what, cvk_error* error)
{
    const VkPhysicalDeviceMemoryProperties* m = &context->memory;
    uint32_t heap = m->memoryTypes[type].heapIndex;
    if (size <= m->memoryHeaps[heap].size)
        return CVK_SUCCESS;
    return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                    "%s needs %llu bytes (%.1f GiB) in one allocation; %s's memory heap %u holds "
                    "%llu bytes (%.1f GiB)", what, (unsigned long long)size,
                    (double)size / (1u << 30), context->properties.deviceName, heap,
                    (unsigned long long)m->memoryHeaps[heap].size,
                    (double)m->memoryHeaps[heap].size / (1u << 30));
}

/* Memory of `type` (-1: none suits) for a resource whose requirements are `req`, counted
   against the context; the caller binds it. On failure nothing is allocated; `for_what` names
   the call in the message ("allocating buffer memory"). */
static cvk_result allocate_memory(cvk_context* context, int type, const VkMemoryRequirements* req,
                                  const char* for_what, const char* what, VkDeviceMemory* memory,
                                  VkDeviceSize* allocated, cvk_error* error)
{
    if (type < 0)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "%s: no suitable memory type", what);
    cvk_result r = check_heap(context, type, req->size, what, error);
    if (r != CVK_SUCCESS)
        return r;
    VkMemoryAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .allocationSize = req->size,
        .memoryTypeIndex = (uint32_t)type,
    };
    VkResult vr = vkAllocateMemory(context->device, &alloc, NULL, memory);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk_for(error, for_what, vr, "%s (%llu bytes)", what,
                               (unsigned long long)req->size);
    *allocated = req->size;
    cvk_context_count_memory(context, (int64_t)req->size);
    return CVK_SUCCESS;
}

cvk_result cvk_buffer_create(cvk_context* context, VkDeviceSize size, VkBufferUsageFlags usage,
                             cvk_memory_kind kind, const char* what, cvk_buffer* out,
                             cvk_error* error)
{
    memset(out, 0, sizeof *out);
    out->size = size ? size : 16;
    VkBufferCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
        .size = out->size,
        .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
    };
    VkResult vr = vkCreateBuffer(context->device, &info, NULL, &out->buffer);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk_for(error, "vkCreateBuffer", vr, "%s (%llu bytes)", what,
                           (unsigned long long)out->size);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(context->device, out->buffer, &req);
    int type = -1;
    if (kind == CVK_MEMORY_HOST) {
        type = find_memory_type(context, req.memoryTypeBits,
                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                    VK_MEMORY_PROPERTY_HOST_COHERENT_BIT |
                                    VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
        if (type < 0)
            type = find_memory_type(context, req.memoryTypeBits,
                                    VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                        VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    } else {
        type = device_memory_type(context, req.memoryTypeBits);
    }
    cvk_result r = allocate_memory(context, type, &req, "allocating buffer memory", what,
                                   &out->memory, &out->allocated, error);
    if (r != CVK_SUCCESS) {
        cvk_buffer_destroy(context, out);
        return r;
    }
    vr = vkBindBufferMemory(context->device, out->buffer, out->memory, 0);
    if (vr == VK_SUCCESS && kind == CVK_MEMORY_HOST)
        vr = vkMapMemory(context->device, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped);
    if (vr != VK_SUCCESS) {
        cvk_buffer_destroy(context, out);
        return cvk_fail_vk_for(error, "allocating buffer memory", vr, "%s (%llu bytes)", what,
                           (unsigned long long)req.size);
    }
    return CVK_SUCCESS;
}

void cvk_buffer_destroy(cvk_context* context, cvk_buffer* buffer)
{
    if (buffer->buffer)
        vkDestroyBuffer(context->device, buffer->buffer, NULL);
    if (buffer->memory)
        vkFreeMemory(context->device, buffer->memory, NULL);
    cvk_context_count_memory(context, -(int64_t)buffer->allocated);
    memset(buffer, 0, sizeof *buffer);
}

cvk_result cvk_shader_module_create(cvk_context* context, const uint32_t* spirv, size_t spirv_bytes,
                                    const char* what, VkShaderModule* out, cvk_error* error)
{
    VkShaderModuleCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
        .codeSize = spirv_bytes,
        .pCode = spirv,
    };
    VkResult vr = vkCreateShaderModule(context->device, &info, NULL, out);
    return vr == VK_SUCCESS ? CVK_SUCCESS : cvk_fail_vk_for(error, "vkCreateShaderModule", vr, "%s", what);
}

cvk_result cvk_compute_pipeline_create(cvk_context* context, const uint32_t* spirv,
                                       size_t spirv_bytes, VkPipelineLayout layout,
                                       const cvk_spec* spec, const char* what,
                                       VkPipeline* out, cvk_error* error)
{
    VkShaderModule module;
    cvk_result r = cvk_shader_module_create(context, spirv, spirv_bytes, what, &module, error);
    if (r != CVK_SUCCESS)
        return r;
    VkSpecializationMapEntry entries[CVK_SPEC_MAX];
    for (uint32_t i = 0; i < spec->count; i++)
        entries[i] = (VkSpecializationMapEntry){.constantID = i,
                                                .offset = i * (uint32_t)sizeof(uint32_t),
                                                .size = sizeof(uint32_t)};
    VkSpecializationInfo spec_info = {
        .mapEntryCount = spec->count,
        .pMapEntries = entries,
        .dataSize = spec->count * sizeof(uint32_t),
        .pData = spec->values,
    };
    VkComputePipelineCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
        .stage = {
            .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
            .stage = VK_SHADER_STAGE_COMPUTE_BIT,
            .module = module,
            .pName = "main",
            .pSpecializationInfo = &spec_info,
        },
        .layout = layout,
    };
    VkResult vr = vkCreateComputePipelines(context->device, VK_NULL_HANDLE, 1, &info, NULL, out);
    vkDestroyShaderModule(context->device, module, NULL);
    if (vr != VK_SUCCESS) {
        *out = VK_NULL_HANDLE;
        return cvk_fail_vk_for(error, "vkCreateComputePipelines", vr, "%s", what);
    }
    return CVK_SUCCESS;
}

cvk_result cvk_submitter_create(cvk_context* context, cvk_submitter* out, cvk_error* error)
{
    memset(out, 0, sizeof *out);
    VkCommandPoolCreateInfo pool = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
        .queueFamilyIndex = context->queue_family,
    };
    VkResult vr = vkCreateCommandPool(context->device, &pool, NULL, &out->pool);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkCreateCommandPool", vr);
    VkFenceCreateInfo fence = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    vr = vkCreateFence(context->device, &fence, NULL, &out->fence);
    if (vr != VK_SUCCESS) {
        cvk_submitter_destroy(context, out);
        return cvk_fail_vk(error, "vkCreateFence", vr);
    }
    return CVK_SUCCESS;
}

void cvk_submitter_destroy(cvk_context* context, cvk_submitter* submitter)
{
    if (submitter->fence)
        vkDestroyFence(context->device, submitter->fence, NULL);
    if (submitter->pool)
        vkDestroyCommandPool(context->device, submitter->pool, NULL);
    memset(submitter, 0, sizeof *submitter);
}

cvk_result cvk_command_buffer_allocate(cvk_context* context, cvk_submitter* submitter,
                                       VkCommandBuffer* out, cvk_error* error)
{
    VkCommandBufferAllocateInfo info = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = submitter->pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1,
    };
    VkResult vr = vkAllocateCommandBuffers(context->device, &info, out);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkAllocateCommandBuffers", vr);
    return CVK_SUCCESS;
}

void cvk_context_count_memory(cvk_context* context, int64_t bytes)
{
    uint64_t now = atomic_fetch_add(&context->device_bytes, (uint64_t)bytes) + (uint64_t)bytes;
    uint64_t peak = atomic_load(&context->device_peak_bytes);
    while (now > peak && !atomic_compare_exchange_weak(&context->device_peak_bytes, &peak, now)) {
    }
}

bool cvk_context_lost(const cvk_context* context)
{
    return atomic_load(&context->lost);
}

static cvk_result lost_already(cvk_error* error, const char* call)
{
    return cvk_fail(error, CVK_ERROR_DEVICE_LOST,
                    "the device was lost earlier (VK_ERROR_DEVICE_LOST); %s was not called: "
                    "objects on this context can only be destroyed", call);
}

static cvk_result device_lost(cvk_context* context, cvk_error* error, const char* call)
{
    atomic_store(&context->lost, true);
    return cvk_fail(error, CVK_ERROR_DEVICE_LOST,
                    "%s failed: the device was lost (VK_ERROR_DEVICE_LOST: a driver reset, a "
                    "removed GPU or a hung submission); nothing more is submitted to it",
                    call);
}

cvk_result cvk_queue_submit(cvk_context* context, const VkSubmitInfo* submit, VkFence fence,
                            cvk_error* error)
{
    if (cvk_context_lost(context))
        return lost_already(error, "vkQueueSubmit");
    VkResult vr = vkQueueSubmit(context->queue, 1, submit, fence);
    if (vr == VK_ERROR_DEVICE_LOST)
        return device_lost(context, error, "vkQueueSubmit");
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkQueueSubmit", vr);
    return CVK_SUCCESS;
}

cvk_result cvk_fence_wait(cvk_context* context, VkFence fence, cvk_error* error)
{
    if (cvk_context_lost(context))
        return lost_already(error, "vkWaitForFences");
    VkResult vr = vkWaitForFences(context->device, 1, &fence, VK_TRUE, UINT64_MAX);
    unsigned waits = atomic_fetch_add(&context->fence_waits, 1) + 1;
    if (vr == VK_SUCCESS && context->lose_at_wait && waits >= context->lose_at_wait)
        vr = VK_ERROR_DEVICE_LOST;
    if (vr == VK_ERROR_DEVICE_LOST)
        return device_lost(context, error, "vkWaitForFences");
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkWaitForFences", vr);
    return CVK_SUCCESS;
}

void cvk_queue_idle(cvk_context* context)
{
    if (!cvk_context_lost(context) && vkQueueWaitIdle(context->queue) == VK_ERROR_DEVICE_LOST)
        atomic_store(&context->lost, true);
}

cvk_result cvk_submit_and_wait(cvk_context* context, cvk_submitter* submitter,
                               const VkCommandBuffer* cmds, uint32_t count, cvk_error* error)
{
    VkSubmitInfo submit = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .commandBufferCount = count,
        .pCommandBuffers = cmds,
    };
    cvk_result r = cvk_queue_submit(context, &submit, submitter->fence, error);
    if (r == CVK_SUCCESS)
        r = cvk_fence_wait(context, submitter->fence, error);
    if (r != CVK_SUCCESS)
        return r;
    VkResult vr = vkResetFences(context->device, 1, &submitter->fence);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkResetFences", vr);
    return CVK_SUCCESS;
}

void cvk_cmd_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stage, VkAccessFlags src_access,
                     VkPipelineStageFlags dst_stage, VkAccessFlags dst_access)
{
    VkMemoryBarrier barrier = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = src_access,
        .dstAccessMask = dst_access,
    };
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 1, &barrier, 0, NULL, 0, NULL);
}

cvk_result cvk_command_buffer_begin(VkCommandBuffer cmd, VkCommandBufferUsageFlags flags,
                                    cvk_error* error)
{
    VkCommandBufferBeginInfo info = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = flags,
    };
    VkResult vr = vkBeginCommandBuffer(cmd, &info);
    return vr == VK_SUCCESS ? CVK_SUCCESS : cvk_fail_vk(error, "vkBeginCommandBuffer", vr);
}

cvk_result cvk_command_buffer_end(VkCommandBuffer cmd, cvk_error* error)
{
    VkResult vr = vkEndCommandBuffer(cmd);
    return vr == VK_SUCCESS ? CVK_SUCCESS : cvk_fail_vk(error, "vkEndCommandBuffer", vr);
}

cvk_result cvk_buffer_view_create(cvk_context* context, const cvk_buffer* buffer, VkFormat format,
                                  VkBufferView* out, cvk_error* error)
{
    VkBufferViewCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO,
        .buffer = buffer->buffer,
        .format = format,
        .range = VK_WHOLE_SIZE,
    };
    VkResult vr = vkCreateBufferView(context->device, &info, NULL, out);
    return vr == VK_SUCCESS ? CVK_SUCCESS : cvk_fail_vk(error, "vkCreateBufferView", vr);
}

cvk_result cvk_buffer_upload(cvk_context* context, cvk_submitter* submitter, VkCommandBuffer cmd,
                             cvk_buffer* dst, const void* data, VkDeviceSize size, cvk_error* error)
{
    if (size == 0)
        return CVK_SUCCESS;
    cvk_buffer staging;
    cvk_result r = cvk_buffer_create(context, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, CVK_MEMORY_HOST,
                                     "staging", &staging, error);
    if (r != CVK_SUCCESS)
        return r;
    memcpy(staging.mapped, data, size);
    r = cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, error);
    if (r == CVK_SUCCESS) {
        VkBufferCopy region = {0, 0, size};
        vkCmdCopyBuffer(cmd, staging.buffer, dst->buffer, 1, &region);
        cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
        r = cvk_command_buffer_end(cmd, error);
    }
    if (r == CVK_SUCCESS)
        r = cvk_submit_and_wait(context, submitter, &cmd, 1, error);
    cvk_buffer_destroy(context, &staging);
    return r;
}

/* Bytes per sample of the formats clothvk draws to; 16, the most any format takes, for others. */
static VkDeviceSize sample_bytes(VkFormat format)
{
    switch (format) {
    case VK_FORMAT_S8_UINT: return 1;
    case VK_FORMAT_D16_UNORM: return 2;
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_D32_SFLOAT: return 4;
    default: return 16;
    }
}

/* An image larger than the device allows for its format (maxResourceSize; 4 GiB − 1 on
   lavapipe) is invalid usage, found only by the validation layer: refuse it before creating it,
   as a limit of the device, with the figures. */
static cvk_result check_image_size(const cvk_context* context, VkFormat format, uint32_t width,
                                   uint32_t height, VkSampleCountFlagBits samples,
                                   VkImageUsageFlags usage, const char* what, cvk_error* error)
{
    VkImageFormatProperties properties;
    VkResult vr = vkGetPhysicalDeviceImageFormatProperties(
        context->physical_device, format, VK_IMAGE_TYPE_2D, VK_IMAGE_TILING_OPTIMAL, usage, 0,
        &properties);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk_for(error, "vkGetPhysicalDeviceImageFormatProperties", vr, "%s", what);
    VkDeviceSize bytes = (VkDeviceSize)width * height * (VkDeviceSize)samples * sample_bytes(format);
    if (bytes <= properties.maxResourceSize)
        return CVK_SUCCESS;
    return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                    "%s: %u x %u pixels at %u samples take %llu bytes (%.1f GiB); %s allows "
                    "%llu bytes for one image (maxResourceSize)", what, width, height,
                    (unsigned)samples, (unsigned long long)bytes, (double)bytes / (1u << 30),
                    context->properties.deviceName,
                    (unsigned long long)properties.maxResourceSize);
}

cvk_result cvk_gpu_image_create(cvk_context* context, VkFormat format, uint32_t width, uint32_t height,
                                VkSampleCountFlagBits samples, VkImageUsageFlags usage,
                                VkImageAspectFlags aspect, const char* what, cvk_gpu_image* out,
                                cvk_error* error)
{
    return cvk_gpu_image_create_mipped(context, format, width, height, 1, samples, usage, aspect, what, out,
                                       error);
}

cvk_result cvk_gpu_image_create_mipped(cvk_context* context, VkFormat format, uint32_t width, uint32_t height,
                                       uint32_t levels, VkSampleCountFlagBits samples, VkImageUsageFlags usage,
                                       VkImageAspectFlags aspect, const char* what, cvk_gpu_image* out,
                                       cvk_error* error)
{
    memset(out, 0, sizeof *out);
    VkImageCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
        .imageType = VK_IMAGE_TYPE_2D,
        .format = format,
        .extent = {width, height, 1},
        .mipLevels = levels,
        .arrayLayers = 1,
        .samples = samples,
        .tiling = VK_IMAGE_TILING_OPTIMAL,
        .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
        .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
    };
    cvk_result checked = check_image_size(context, format, width, height, samples, usage, what,
                                          error);
    if (checked != CVK_SUCCESS)
        return checked;
    VkResult vr = vkCreateImage(context->device, &info, NULL, &out->image);
    if (vr != VK_SUCCESS) {
        return cvk_fail_vk_for(error, "vkCreateImage", vr, "%s (%u x %u)", what, width, height);
    }
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(context->device, out->image, &req);
    int type = device_memory_type(context, req.memoryTypeBits);
    cvk_result r = allocate_memory(context, type, &req, "allocating image memory", what,
                                   &out->memory, &out->allocated, error);
    if (r != CVK_SUCCESS) {
        cvk_gpu_image_destroy(context, out);
        return r;
    }
    vr = vkBindImageMemory(context->device, out->image, out->memory, 0);
    if (vr != VK_SUCCESS) {
        cvk_gpu_image_destroy(context, out);
        return cvk_fail_vk_for(error, "allocating image memory", vr, "%s (%llu bytes)", what,
                               (unsigned long long)req.size);
    }
    VkImageViewCreateInfo view = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
        .image = out->image,
        .viewType = VK_IMAGE_VIEW_TYPE_2D,
        .format = format,
        .subresourceRange = {aspect, 0, levels, 0, 1},
    };
    vr = vkCreateImageView(context->device, &view, NULL, &out->view);
    if (vr != VK_SUCCESS) {
        cvk_gpu_image_destroy(context, out);
        return cvk_fail_vk_for(error, "vkCreateImageView", vr, "%s", what);
    }
    return CVK_SUCCESS;
}

void cvk_gpu_image_destroy(cvk_context* context, cvk_gpu_image* image)
{
    if (image->view)
        vkDestroyImageView(context->device, image->view, NULL);
    if (image->image)
        vkDestroyImage(context->device, image->image, NULL);
    if (image->memory)
        vkFreeMemory(context->device, image->memory, NULL);
    cvk_context_count_memory(context, -(int64_t)image->allocated);
    memset(image, 0, sizeof *image);
}

cvk_result cvk_buffer_download(cvk_context* context, cvk_submitter* submitter, VkCommandBuffer cmd,
                               const cvk_buffer* src, void* data, VkDeviceSize size,
                               cvk_error* error)
{
    if (size == 0)
        return CVK_SUCCESS;
    if (size > src->size)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cannot read %llu bytes back from a buffer of %llu bytes",
                        (unsigned long long)size, (unsigned long long)src->size);
    cvk_buffer readback;
    cvk_result r = cvk_buffer_create(context, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     CVK_MEMORY_HOST, "readback", &readback, error);
    if (r != CVK_SUCCESS)
        return r;
    r = cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, error);
    if (r == CVK_SUCCESS) {
        cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                        VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
        VkBufferCopy region = {0, 0, size};
        vkCmdCopyBuffer(cmd, src->buffer, readback.buffer, 1, &region);
        cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
        r = cvk_command_buffer_end(cmd, error);
    }
    if (r == CVK_SUCCESS)
        r = cvk_submit_and_wait(context, submitter, &cmd, 1, error);
    if (r == CVK_SUCCESS)
        memcpy(data, readback.mapped, size);
    cvk_buffer_destroy(context, &readback);
    return r;
}

/* ---- the context's shared objects (gpu_cache.h) ---- */

/* The longest key: a set layout of CVK_MAX_BINDINGS bindings, 1 + 2 words a binding. */
#define KEY_WORDS (1 + 2 * CVK_MAX_BINDINGS)

/* A key: the words of an object's definition, Vulkan handles as two words each. */
typedef struct key {
    uint32_t words[KEY_WORDS];
    uint32_t count;
} key;

static void put(key* k, uint32_t word)
{
    if (k->count < KEY_WORDS)
        k->words[k->count] = word;
    k->count++;
}

/* A non-dispatchable handle (a pointer or a uint64_t, by platform) as two words. */
static void put_handle(key* k, const void* handle, size_t size)
{
    uint64_t bits = 0;
    memcpy(&bits, handle, size < sizeof bits ? size : sizeof bits);
    put(k, (uint32_t)bits);
    put(k, (uint32_t)(bits >> 32));
}

/* Keeps a new object under its key, or destroys it when the table cannot grow (and clears
   *handle, where the caller put it). */
static cvk_result keep(cvk_context* context, cvk_cached_kind kind, const key* k,
                       cvk_cached_object object, void* handle, size_t handle_size,
                       cvk_error* error)
{
    if (cvk_gpu_cache_add(&context->cache, kind, k->words, k->count, object))
        return CVK_SUCCESS;
    cvk_gpu_cache_destroy_object(context->device, kind, object);
    memset(handle, 0, handle_size);
    return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the context's "
                    "pipeline table");
}

cvk_result cvk_cached_set_layout(cvk_context* context, const VkDescriptorSetLayoutBinding* bindings,
                                 uint32_t binding_count, VkDescriptorSetLayout* out,
                                 cvk_error* error)
{
    key k = {.count = 0};
    put(&k, binding_count);
    for (uint32_t i = 0; i < binding_count; i++) {
        /* create_layouts (descriptors.c) numbers bindings 0, 1, ..., one descriptor each, no
           immutable samplers: the type and stages are the definition. */
        put(&k, (uint32_t)bindings[i].descriptorType);
        put(&k, bindings[i].stageFlags);
    }
    if (k.count > KEY_WORDS)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "a set layout of %u bindings is "
                        "more than the pipeline table keeps", binding_count);
    const cvk_cached_object* found =
        cvk_gpu_cache_find(&context->cache, CVK_CACHED_SET_LAYOUT, k.words, k.count);
    if (found) {
        *out = found->set_layout;
        return CVK_SUCCESS;
    }
    VkDescriptorSetLayoutCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .bindingCount = binding_count,
        .pBindings = bindings,
    };
    VkResult vr = vkCreateDescriptorSetLayout(context->device, &info, NULL, out);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkCreateDescriptorSetLayout", vr);
    return keep(context, CVK_CACHED_SET_LAYOUT, &k, (cvk_cached_object){.set_layout = *out}, out,
                sizeof *out, error);
}

cvk_result cvk_cached_pipeline_layout(cvk_context* context, const VkDescriptorSetLayout* sets,
                                      uint32_t set_count, VkShaderStageFlags push_stages,
                                      uint32_t push_bytes, VkPipelineLayout* out,
                                      cvk_error* error)
{
    key k = {.count = 0};
    put(&k, set_count);
    put(&k, push_bytes ? push_stages : 0);
    put(&k, push_bytes);
    for (uint32_t i = 0; i < set_count; i++)
        put_handle(&k, &sets[i], sizeof sets[i]);
    if (k.count > KEY_WORDS)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "a pipeline layout of %u sets is "
                        "more than the pipeline table keeps", set_count);
    const cvk_cached_object* found =
        cvk_gpu_cache_find(&context->cache, CVK_CACHED_PIPELINE_LAYOUT, k.words, k.count);
    if (found) {
        *out = found->pipeline_layout;
        return CVK_SUCCESS;
    }
    VkPushConstantRange push = {push_stages, 0, push_bytes};
    VkPipelineLayoutCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = set_count,
        .pSetLayouts = sets,
        .pushConstantRangeCount = push_bytes ? 1 : 0,
        .pPushConstantRanges = push_bytes ? &push : NULL,
    };
    VkResult vr = vkCreatePipelineLayout(context->device, &info, NULL, out);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkCreatePipelineLayout", vr);
    return keep(context, CVK_CACHED_PIPELINE_LAYOUT, &k,
                (cvk_cached_object){.pipeline_layout = *out}, out, sizeof *out, error);
}

cvk_result cvk_cached_compute_pipeline(cvk_context* context, cvk_shader_id shader,
                                       VkPipelineLayout layout, const cvk_spec* spec,
                                       VkPipeline* out, cvk_error* error)
{
    key k = {.count = 0};
    put(&k, (uint32_t)shader);
    put_handle(&k, &layout, sizeof layout);
    put(&k, spec->count);
    for (uint32_t i = 0; i < spec->count; i++)
        put(&k, spec->values[i]);
    const cvk_cached_object* found =
        cvk_gpu_cache_find(&context->cache, CVK_CACHED_PIPELINE, k.words, k.count);
    if (found) {
        *out = found->pipeline;
        return CVK_SUCCESS;
    }
    cvk_spirv spirv = cvk_shader(shader);
    cvk_result r = cvk_compute_pipeline_create(context, spirv.code, spirv.bytes, layout, spec,
                                               spirv.name, out, error);
    if (r != CVK_SUCCESS)
        return r;
    return keep(context, CVK_CACHED_PIPELINE, &k, (cvk_cached_object){.pipeline = *out}, out,
                sizeof *out, error);
}
