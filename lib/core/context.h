/* The Vulkan objects a context holds, created or adopted. */
#ifndef CVK_CONTEXT_H
#define CVK_CONTEXT_H

#include <stdatomic.h>

#include "clothvk.h"
#include "core/gpu_cache.h"

struct cvk_context {
    VkInstance instance;
    VkPhysicalDevice physical_device;
    VkDevice device;
    uint32_t queue_family;
    VkQueue queue;
    bool adopted;
    bool validation;
    VkDebugUtilsMessengerEXT messenger;

    VkPhysicalDeviceProperties properties;
    VkPhysicalDeviceMemoryProperties memory;
    uint32_t timestamp_valid_bits; /* 0: the queue family cannot write timestamps */
    bool graphics;                 /* the queue family can draw (the renderer needs it) */
    bool fill_mode_non_solid;      /* triangles can be drawn as lines (render.wireframe) */
    bool wide_lines;               /* lines can be wider than a pixel */
    bool tessellation;             /* tessellation shaders (render.smooth) */
    bool sampler_anisotropy;       /* samplers may filter anisotropically (cloth textures) */
    uint32_t subgroup_size;

    cvk_log_fn log;
    void* log_user;
    atomic_uint validation_messages;

    /* Device loss: set when a submit or wait returned VK_ERROR_DEVICE_LOST. From then on the
       library submits and waits no more on this device (cvk_queue_submit, cvk_fence_wait); it
       only destroys what it made. */
    atomic_bool lost;

    /* Device memory allocated through this context (buffers and images of every object on
       it), now and at most so far: what cvk_context_info reports. */
    _Atomic uint64_t device_bytes;
    _Atomic uint64_t device_peak_bytes;
    /* Set layouts, pipeline layouts and compute pipelines shared by everything made on this
       context (lib/core/gpu_cache.h). */
    cvk_gpu_cache cache;
    atomic_uint fence_waits; /* fence waits so far, for the injection below */
    /* Test builds only: the lose_at_wait-th fence wait (counting from 1) reports
       VK_ERROR_DEVICE_LOST as a real loss would. 0: never. */
    uint32_t lose_at_wait;
};

/* Counts an allocation of `bytes` (negative: a release) of device memory. */
void cvk_context_count_memory(cvk_context* context, int64_t bytes);

/* True once the device has been lost. */
bool cvk_context_lost(const cvk_context* context);

/* Largest particle count whose per-particle arrays fit the device's buffer limits. */
uint64_t cvk_context_max_particles(const cvk_context* context);

/* Largest image width and height the renderer can draw: the smaller of maxImageDimension2D
   and the framebuffer limits. */
uint32_t cvk_context_max_image_size(const cvk_context* context);

#endif
