/* A family's buffers, views and readback command buffer from its table (family_objects.h). */
#include "solvers/family_objects.h"

cvk_result cvk_family_create(cvk_sim* s, const cvk_family_buffer* list, size_t count,
                             VkCommandBuffer* readback_cmd, cvk_error* error)
{
    for (size_t i = 0; i < count; i++) {
        cvk_result r = cvk_buffer_create(s->device.context, list[i].size, list[i].usage,
                                         list[i].memory, list[i].what, list[i].buffer, error);
        if (r == CVK_SUCCESS && list[i].view)
            r = cvk_buffer_view_create(s->device.context, list[i].buffer, list[i].format,
                                       list[i].view, error);
        if (r != CVK_SUCCESS)
            return r;
    }
    return cvk_command_buffer_allocate(s->device.context, &s->device.submitter, readback_cmd,
                                       error);
}

void cvk_family_destroy(cvk_sim* s, cvk_descriptors* const* sets, size_t set_count,
                        const cvk_family_buffer* list, size_t count, VkCommandBuffer readback_cmd)
{
    cvk_context* context = s->device.context;
    for (size_t i = 0; i < set_count; i++)
        cvk_descriptors_destroy(context, sets[i]);
    for (size_t i = 0; i < count; i++)
        if (list[i].view && *list[i].view)
            vkDestroyBufferView(context->device, *list[i].view, NULL);
    for (size_t i = 0; i < count; i++)
        cvk_buffer_destroy(context, list[i].buffer);
    if (readback_cmd)
        vkFreeCommandBuffers(context->device, s->device.submitter.pool, 1, &readback_cmd);
}
