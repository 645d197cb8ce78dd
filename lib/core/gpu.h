/* Thin helpers over Vulkan: buffers, compute pipelines from embedded SPIR-V, one-off
   submissions. Every function reports failure through cvk_error. */
#ifndef CVK_GPU_H
#define CVK_GPU_H

#include "core/context.h"
#include "core/shaders.h"

typedef struct cvk_buffer {
    VkBuffer buffer;
    VkDeviceMemory memory;
    VkDeviceSize size;
    VkDeviceSize allocated; /* bytes of device memory behind it (counted by the context) */
    void* mapped; /* non-NULL for host-visible buffers */
} cvk_buffer;

typedef enum cvk_memory_kind {
    CVK_MEMORY_DEVICE,   /* fastest for the GPU; may not be mappable */
    CVK_MEMORY_HOST,     /* host-visible and coherent, persistently mapped: staging, readback */
} cvk_memory_kind;

cvk_result cvk_buffer_create(cvk_context* context, VkDeviceSize size, VkBufferUsageFlags usage,
                             cvk_memory_kind kind, const char* what, cvk_buffer* out,
                             cvk_error* error);
void cvk_buffer_destroy(cvk_context* context, cvk_buffer* buffer);

/* A device-local image with one view over all of it. */
typedef struct cvk_gpu_image {
    VkImage image;
    VkDeviceMemory memory;
    VkImageView view;
    VkDeviceSize allocated; /* bytes of device memory behind it (counted by the context) */
} cvk_gpu_image;

cvk_result cvk_gpu_image_create(cvk_context* context, VkFormat format, uint32_t width, uint32_t height,
                                VkSampleCountFlagBits samples, VkImageUsageFlags usage,
                                VkImageAspectFlags aspect, const char* what, cvk_gpu_image* out,
                                cvk_error* error);
/* The same with `levels` mip levels (the view covers them all). */
cvk_result cvk_gpu_image_create_mipped(cvk_context* context, VkFormat format, uint32_t width, uint32_t height,
                                       uint32_t levels, VkSampleCountFlagBits samples, VkImageUsageFlags usage,
                                       VkImageAspectFlags aspect, const char* what, cvk_gpu_image* out,
                                       cvk_error* error);
void cvk_gpu_image_destroy(cvk_context* context, cvk_gpu_image* image);

/* Specialization constants are consecutive uint32 values with ids 0, 1, 2, ... */
#define CVK_SPEC_MAX 10
typedef struct cvk_spec {
    uint32_t values[CVK_SPEC_MAX];
    uint32_t count;
} cvk_spec;

/* A shader module from SPIR-V; `what` names it in the error. */
cvk_result cvk_shader_module_create(cvk_context* context, const uint32_t* spirv, size_t spirv_bytes,
                                    const char* what, VkShaderModule* out, cvk_error* error);

cvk_result cvk_compute_pipeline_create(cvk_context* context, const uint32_t* spirv,
                                       size_t spirv_bytes, VkPipelineLayout layout,
                                       const cvk_spec* spec, const char* what,
                                       VkPipeline* out, cvk_error* error);

/* The context's shared objects (lib/core/gpu_cache.h): the one of this definition, made on
   first request. The context owns them; the caller never destroys them. */
cvk_result cvk_cached_set_layout(cvk_context* context, const VkDescriptorSetLayoutBinding* bindings,
                                 uint32_t binding_count, VkDescriptorSetLayout* out,
                                 cvk_error* error);
/* push_bytes 0: no push constants. */
cvk_result cvk_cached_pipeline_layout(cvk_context* context, const VkDescriptorSetLayout* sets,
                                      uint32_t set_count, VkShaderStageFlags push_stages,
                                      uint32_t push_bytes, VkPipelineLayout* out,
                                      cvk_error* error);
cvk_result cvk_cached_compute_pipeline(cvk_context* context, cvk_shader_id shader,
                                       VkPipelineLayout layout, const cvk_spec* spec,
                                       VkPipeline* out, cvk_error* error);

/* Descriptor boilerplate from one binding table (lib/core/descriptors.c): binding i of the set has
   bindings[i].type and is read by bindings[i].stages (0: the compute stage). */
typedef struct cvk_binding {
    VkDescriptorType type;
    VkShaderStageFlags stages;
} cvk_binding;

/* What one binding points at: a whole buffer (storage, uniform), a texel view, or an image
   in VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL with its sampler. */
typedef struct cvk_resource {
    const cvk_buffer* buffer;
    VkBufferView view;
    VkImageView image;
    VkSampler sampler;
} cvk_resource;

#define CVK_MAX_SETS 8
#define CVK_MAX_BINDINGS 40
#define CVK_MAX_EXTRA_SETS 2 /* other modules' set layouts after a table's own (set 0) */

/* A set layout, a pipeline layout over it with one push-constant range, a pool and
   `set_count` sets of that layout. */
typedef struct cvk_descriptors {
    const cvk_binding* bindings; /* the table it was made from; must outlive it */
    uint32_t binding_count;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout pipeline_layout;
    VkDescriptorPool pool;
    VkDescriptorSet sets[CVK_MAX_SETS];
    uint32_t set_count;
} cvk_descriptors;

/* push_bytes 0: no push constants. On failure nothing is left to destroy. */
cvk_result cvk_descriptors_create(cvk_context* context, const cvk_binding* bindings,
                                  uint32_t binding_count, uint32_t set_count,
                                  VkShaderStageFlags push_stages, uint32_t push_bytes,
                                  cvk_descriptors* out, cvk_error* error);
/* The same, with a pipeline layout of set 0 = this table's layout followed by extra_layouts
   (sets 1, 2, ...: another module's sets that its shaders also read, such as the contact set
   of lib/contact/collide.h). The caller keeps the extra layouts alive. */
cvk_result cvk_descriptors_create_with(cvk_context* context, const cvk_binding* bindings,
                                       uint32_t binding_count, uint32_t set_count,
                                       VkShaderStageFlags push_stages, uint32_t push_bytes,
                                       const VkDescriptorSetLayout* extra_layouts,
                                       uint32_t extra_count, cvk_descriptors* out,
                                       cvk_error* error);
/* Points every binding of set `set` at resources[binding]. */
void cvk_descriptors_write(cvk_context* context, const cvk_descriptors* descriptors, uint32_t set,
                           const cvk_resource* resources);
void cvk_descriptors_destroy(cvk_context* context, cvk_descriptors* descriptors);

/* A command buffer and fence for blocking submissions of the library's own work. */
typedef struct cvk_submitter {
    VkCommandPool pool;
    VkFence fence;
} cvk_submitter;

cvk_result cvk_submitter_create(cvk_context* context, cvk_submitter* out, cvk_error* error);
void cvk_submitter_destroy(cvk_context* context, cvk_submitter* submitter);
cvk_result cvk_command_buffer_allocate(cvk_context* context, cvk_submitter* submitter,
                                       VkCommandBuffer* out, cvk_error* error);
/* Submits `count` command buffers (one batch, in order) and waits for them. */
/* vkQueueSubmit and vkWaitForFences (no timeout) through the context's device-loss state: once
   the device is lost (by either call, or earlier) they return CVK_ERROR_DEVICE_LOST without
   calling Vulkan. Every submit and wait of the library goes through these two. */
cvk_result cvk_queue_submit(cvk_context* context, const VkSubmitInfo* submit, VkFence fence,
                            cvk_error* error);
cvk_result cvk_fence_wait(cvk_context* context, VkFence fence, cvk_error* error);

/* vkQueueWaitIdle before destroying objects the queue may still use; skipped once the device
   is lost (destroying is all that is left to do, and the spec allows it then). */
void cvk_queue_idle(cvk_context* context);

cvk_result cvk_submit_and_wait(cvk_context* context, cvk_submitter* submitter,
                               const VkCommandBuffer* cmds, uint32_t count, cvk_error* error);

/* Copies `size` bytes from the host into `dst` through a temporary staging buffer and waits;
   compute shaders may read them afterwards. For tables written once at creation. */
cvk_result cvk_buffer_upload(cvk_context* context, cvk_submitter* submitter, VkCommandBuffer cmd,
                             cvk_buffer* dst, const void* data, VkDeviceSize size, cvk_error* error);

/* A buffer view over a whole buffer (texel buffers). */
cvk_result cvk_buffer_view_create(cvk_context* context, const cvk_buffer* buffer, VkFormat format,
                                  VkBufferView* out, cvk_error* error);

/* vkBeginCommandBuffer and vkEndCommandBuffer, reporting failure through cvk_error. */
cvk_result cvk_command_buffer_begin(VkCommandBuffer cmd, VkCommandBufferUsageFlags flags,
                                    cvk_error* error);
cvk_result cvk_command_buffer_end(VkCommandBuffer cmd, cvk_error* error);

/* One global memory barrier between two stages. */
void cvk_cmd_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stage, VkAccessFlags src_access,
                     VkPipelineStageFlags dst_stage, VkAccessFlags dst_access);

/* Copies `size` bytes of `src` (which needs VK_BUFFER_USAGE_TRANSFER_SRC_BIT) into host
   memory through a temporary host-visible buffer and waits. Earlier compute-shader and
   transfer writes to `src` are made visible to the copy first. `cmd` is a command buffer of
   `submitter`'s pool that is not in use. For occasional reads of what the device keeps, such
   as the spring flags an export needs; the per-frame state has its own readback. */
cvk_result cvk_buffer_download(cvk_context* context, cvk_submitter* submitter, VkCommandBuffer cmd,
                               const cvk_buffer* src, void* data, VkDeviceSize size,
                               cvk_error* error);

#endif
