/* The device-buffer layer: what every module of a simulation makes, fills and uploads its
   device buffers through. One blocking transfer submission at a time, through one staging
   buffer; for set-up and occasional writes, never inside a recorded frame. */
#ifndef CVK_DEVICE_H
#define CVK_DEVICE_H

#include "core/gpu.h"

typedef struct cvk_device {
    cvk_context* context;
    cvk_submitter submitter;
    VkCommandBuffer transfer_cmd; /* re-recorded for each transfer */
    cvk_buffer staging;           /* host-visible, 2 vec4 per particle: uploads and readback */
    /* Timestamp queries the next transfer resets before anything else (VK_NULL_HANDLE: none),
       so that timings read before the first frame find them reset, not undefined. */
    VkQueryPool unreset_queries;
    uint32_t unreset_query_count;
} cvk_device;

/* One region of the staging buffer into a device buffer. */
typedef struct cvk_staging_copy {
    cvk_buffer* dst;
    VkDeviceSize src_offset, dst_offset, size;
} cvk_staging_copy;

/* Copies staging regions into buffers and waits; earlier GPU work on them finishes first, and
   compute and transfer work after sees them. */
cvk_result cvk_device_copy_from_staging(cvk_device* device, const cvk_staging_copy* jobs,
                                        uint32_t count, cvk_error* error);

/* A device buffer for a module's tables (storage, uniform, texel, indirect and transfer use;
   at least 16 bytes), filled with `size` bytes of `data` unless data is NULL. */
cvk_result cvk_device_make_buffer(cvk_device* device, cvk_buffer* buffer, VkDeviceSize size,
                                  const char* what, const void* data, cvk_error* error);

/* Fills every byte of a device buffer (a size of whole words) with `byte` (clear: with
   zeros) on the device, and waits. */
cvk_result cvk_device_fill_buffer(cvk_device* device, cvk_buffer* buffer, unsigned char byte,
                                  cvk_error* error);
cvk_result cvk_device_clear_buffer(cvk_device* device, cvk_buffer* buffer, cvk_error* error);

/* Uploads a host array into a device buffer through the staging buffer, in chunks. */
cvk_result cvk_device_upload(cvk_device* device, cvk_buffer* dst, const void* data,
                             VkDeviceSize size, cvk_error* error);

#endif
