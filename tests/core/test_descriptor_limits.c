/* A descriptor table past the device's per-stage limits is refused with a sentence naming the
   kind of descriptor, the count, the device and the limit, before Vulkan sees the layout:
   lavapipe's limits are far above the tables clothvk makes, so the test lowers the context's
   copy of them (storage images to the Vulkan minimum, 4) and creates a table of five storage
   texel buffers, then of five storage buffers with that limit at 4, then a table within both
   limits, which is made. */
#include <stdio.h>
#include <string.h>

#include "core/context.h"
#include "core/gpu.h"
#include "harness.h"

int main(void)
{
    cvk_context* ctx = harness_context();
    VkPhysicalDeviceLimits saved = ctx->properties.limits;
    ctx->properties.limits.maxPerStageDescriptorStorageImages = 4;
    ctx->properties.limits.maxPerStageDescriptorStorageBuffers = 4;
    cvk_error err = {0};
    cvk_descriptors d;
    char want[512];

    const cvk_binding texels[] = {
        {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, 0}, {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, 0},
        {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, 0}, {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, 0},
        {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, 0},
    };
    cvk_result r = cvk_descriptors_create(ctx, texels, 5, 1, 0, 0, &d, &err);
    snprintf(want, sizeof want, "a descriptor set of 5 storage images and storage texel buffers "
             "for one shader stage is more than %s allows (maxPerStageDescriptor*: 4)",
             ctx->properties.deviceName);
    CHECK(r == CVK_ERROR_DEVICE_LIMIT && strcmp(err.message, want) == 0,
          "five storage texel buffers under a limit of 4: result %d, message \"%s\"", (int)r, err.message);

    const cvk_binding buffers[] = {
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0},
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0},
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0},
    };
    r = cvk_descriptors_create(ctx, buffers, 5, 1, 0, 0, &d, &err);
    snprintf(want, sizeof want, "a descriptor set of 5 storage buffers for one shader stage is "
             "more than %s allows (maxPerStageDescriptor*: 4)", ctx->properties.deviceName);
    CHECK(r == CVK_ERROR_DEVICE_LIMIT && strcmp(err.message, want) == 0,
          "five storage buffers under a limit of 4: result %d, message \"%s\"", (int)r, err.message);

    r = cvk_descriptors_create(ctx, texels, 4, 1, 0, 0, &d, &err);
    CHECK(r == CVK_SUCCESS, "four storage texel buffers under a limit of 4: %s", err.message);
    if (r == CVK_SUCCESS)
        cvk_descriptors_destroy(ctx, &d);
    ctx->properties.limits = saved;
    return harness_finish(ctx);
}
