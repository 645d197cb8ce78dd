/* The Vulkan objects a context holds, created or adopted. */
#ifndef CVK_CONTEXT_H
#define CVK_CONTEXT_H

#include <stdatomic.h>

#include "clothvk.h"

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
    uint32_t subgroup_size;

    cvk_log_fn log;
    void* log_user;
    atomic_uint validation_messages;
};

/* Largest particle count whose per-particle arrays fit the device's buffer limits. */
uint64_t cvk_context_max_particles(const cvk_context* context);

/* Largest image width and height the renderer can draw: the smaller of maxImageDimension2D
   and the framebuffer limits. */
uint32_t cvk_context_max_image_size(const cvk_context* context);

#endif
