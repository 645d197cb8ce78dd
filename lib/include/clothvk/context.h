/* clothvk/context.h — step 1: the Vulkan instance, device and queue the library works with.
 *
 * Either the library creates a headless instance and device (the first device, or the one
 * $CLOTHVK_DEVICE names by index or name substring), or it adopts yours: fill instance,
 * physical_device, device, queue_family and queue in cvk_context_desc. The library never
 * destroys what it adopted. Everything else is made on a context and destroyed before it.
 *
 *     cvk_context_desc desc = cvk_default_context_desc();
 *     desc.validation = 1;                   // change only what you need
 *     cvk_error err;
 *     cvk_context* ctx;
 *     if (cvk_context_create(&desc, &ctx, &err) != CVK_SUCCESS)
 *         fprintf(stderr, "%s\n", err.message);
 */
#ifndef CLOTHVK_CONTEXT_H
#define CLOTHVK_CONTEXT_H

#include "base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ----------------------------------------------------------------------------------------
 * Context: the Vulkan instance, device and queue the library works with
 * ------------------------------------------------------------------------------------- */

typedef struct cvk_context cvk_context;

/* Receives each validation-layer message (warnings and errors) while validation is on. */
typedef void (*cvk_log_fn)(void* user, const char* message);

/* Start from cvk_default_context_desc(): the library's own instance and device, the validation
   layer as $CLOTHVK_VALIDATION says, no log callback. */
typedef struct cvk_context_desc {
    /* Khronos validation layer: 0 = on when $CLOTHVK_VALIDATION is "1", 1 = on, -1 = off.
       Ignored when adopting (enable the layer on your own instance). */
    int validation;
    /* Device to use: an index ("1") or a substring of the device name ("llvmpipe").
       NULL: $CLOTHVK_DEVICE, else the first device. Ignored when adopting. */
    const char* device_name;
    /* Called for every validation message; may be NULL (messages are still counted). */
    cvk_log_fn log;
    void* log_user;

    /* Adoption: set instance, physical_device, device and queue (queue_family is read only
       then; 0 is a valid family) to use the application's objects. The queue family must
       support compute; timestamps are used when it supports them. The library submits to
       that queue (and waits for it) in cvk_sim_step, cvk_sim_get_stats, the read, write and
       set calls, cvk_sim_pick, a simulation's first cvk_sim_grab, cvk_mesh_create,
       cvk_renderer_create and cvk_renderer_draw, and waits for it in every destroy call: like
       any Vulkan queue it must not be used from another thread at the same time. */
    VkInstance instance;
    VkPhysicalDevice physical_device;
    VkDevice device;
    uint32_t queue_family;
    VkQueue queue;
    uint32_t cookie_;            /* set by cvk_default_context_desc; do not touch */
} cvk_context_desc;

/* The defaults: every field above 0 or NULL (each field says what that means). */
CVK_API cvk_context_desc cvk_default_context_desc(void);

/* desc must come from cvk_default_context_desc(): one that did not (a zero-initialised struct)
   is refused with CVK_ERROR_INVALID_ARGUMENT, as is NULL. */
CVK_API cvk_result cvk_context_create(const cvk_context_desc* desc, cvk_context** out_context,
                              cvk_error* error);
CVK_API void cvk_context_destroy(cvk_context* context);

/* What the library found out about its device. */
typedef struct cvk_context_info {
    const char* device_name;      /* e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" */
    uint32_t api_version;         /* VK_MAKE_API_VERSION of the device */
    bool adopted;                 /* true when the application's device is used */
    bool validation;              /* true when the validation layer is on */
    bool timestamps;              /* true when GPU pass times can be measured */
    uint32_t subgroup_size;       /* informative only; the kernels do not depend on it */
    uint64_t max_particles;       /* largest particle count the device's buffer limits allow */
    bool graphics;                /* true when the queue can draw: the renderer needs it */
    uint32_t max_image_size;      /* largest image width and height the renderer can make */
    uint64_t device_bytes;        /* device memory held now by everything made on this context */
    uint64_t device_peak_bytes;   /* the most it has held at once */
} cvk_context_info;

CVK_API cvk_context_info cvk_context_get_info(const cvk_context* context);

/* Validation messages (warnings and errors) received so far; tests fail when non-zero. */
CVK_API uint32_t cvk_context_validation_message_count(const cvk_context* context);

#ifdef __cplusplus
}
#endif
#endif /* CLOTHVK_CONTEXT_H */
