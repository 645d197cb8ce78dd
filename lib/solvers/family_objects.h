/* The device objects every solver family holds, made and destroyed from one table per family:
   its buffers, each with an optional texel view, and the command buffer that reads its state
   back; destroying also frees its descriptor sets. A buffer added to a family's table is
   created and destroyed without another line. */
#ifndef CVK_FAMILY_OBJECTS_H
#define CVK_FAMILY_OBJECTS_H

#include "plan/state.h"

/* One buffer of a family: its size, usage and memory, the name its errors give, and a texel
   view over all of it (view NULL: none). */
typedef struct cvk_family_buffer {
    cvk_buffer* buffer;
    VkDeviceSize size;
    VkBufferUsageFlags usage;
    cvk_memory_kind memory;
    const char* what;
    VkBufferView* view;
    VkFormat format; /* the view's */
} cvk_family_buffer;

/* The most buffers a family's table holds. */
#define CVK_FAMILY_MAX_BUFFERS 16

/* Creates the buffers of `list` in order, each view right after its buffer, then allocates
   `readback_cmd`. Stops at the first failure; what was made is for cvk_family_destroy. */
cvk_result cvk_family_create(cvk_sim* sim, const cvk_family_buffer* list, size_t count,
                             VkCommandBuffer* readback_cmd, cvk_error* error);
/* Destroys the `set_count` descriptor sets, the views then the buffers of `list` and
   `readback_cmd`, any of them made or not (zero). */
void cvk_family_destroy(cvk_sim* sim, cvk_descriptors* const* sets, size_t set_count,
                        const cvk_family_buffer* list, size_t count, VkCommandBuffer readback_cmd);

#endif
