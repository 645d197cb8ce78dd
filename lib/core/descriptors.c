/* Descriptor set layouts, pipeline layouts, pools, sets and their writes, from a binding
   table: the one place this boilerplate lives (the solver, mesh generation, rendering). */
#include "core/error.h"
#include "core/gpu.h"

static VkShaderStageFlags stages_of(const cvk_binding* b)
{
    return b->stages ? b->stages : VK_SHADER_STAGE_COMPUTE_BIT;
}

static cvk_result create_layouts(cvk_context* ctx, cvk_descriptors* d, VkShaderStageFlags push_stages,
                                 uint32_t push_bytes, const VkDescriptorSetLayout* extra,
                                 uint32_t extra_count, cvk_error* error)
{
    VkDescriptorSetLayoutBinding bindings[CVK_MAX_BINDINGS];
    for (uint32_t i = 0; i < d->binding_count; i++)
        bindings[i] = (VkDescriptorSetLayoutBinding){
            .binding = i,
            .descriptorType = d->bindings[i].type,
            .descriptorCount = 1,
            .stageFlags = stages_of(&d->bindings[i]),
        };
    cvk_result r = cvk_cached_set_layout(ctx, bindings, d->binding_count, &d->set_layout, error);
    if (r != CVK_SUCCESS)
        return r;
    VkDescriptorSetLayout layouts[1 + CVK_MAX_EXTRA_SETS];
    layouts[0] = d->set_layout;
    for (uint32_t i = 0; i < extra_count; i++)
        layouts[1 + i] = extra[i];
    return cvk_cached_pipeline_layout(ctx, layouts, 1 + extra_count, push_stages, push_bytes,
                                      &d->pipeline_layout, error);
}

/* One pool size per descriptor type the table uses, times the sets. */
static uint32_t pool_sizes(const cvk_descriptors* d, VkDescriptorPoolSize* sizes)
{
    uint32_t count = 0;
    for (uint32_t i = 0; i < d->binding_count; i++) {
        uint32_t k = 0;
        while (k < count && sizes[k].type != d->bindings[i].type)
            k++;
        if (k == count)
            sizes[count++] = (VkDescriptorPoolSize){d->bindings[i].type, 0};
        sizes[k].descriptorCount += d->set_count;
    }
    return count;
}

static cvk_result create_sets(cvk_context* ctx, cvk_descriptors* d, cvk_error* error)
{
    VkDescriptorPoolSize sizes[CVK_MAX_BINDINGS];
    VkDescriptorPoolCreateInfo pool_info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
        .maxSets = d->set_count,
        .poolSizeCount = pool_sizes(d, sizes),
        .pPoolSizes = sizes,
    };
    VkResult vr = vkCreateDescriptorPool(ctx->device, &pool_info, NULL, &d->pool);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkCreateDescriptorPool", vr);
    VkDescriptorSetLayout layouts[CVK_MAX_SETS];
    for (uint32_t i = 0; i < d->set_count; i++)
        layouts[i] = d->set_layout;
    VkDescriptorSetAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
        .descriptorPool = d->pool,
        .descriptorSetCount = d->set_count,
        .pSetLayouts = layouts,
    };
    vr = vkAllocateDescriptorSets(ctx->device, &alloc, d->sets);
    return vr == VK_SUCCESS ? CVK_SUCCESS : cvk_fail_vk(error, "vkAllocateDescriptorSets", vr);
}

/* The table against the device's per-stage limits: a device may hold as few as 4 storage
   images (storage texel buffers count among them), 4 storage buffers and 16 sampled images
   (uniform texel buffers among them) per stage, and a layout past them is invalid. Only this
   table's bindings are counted, not the other set layouts of the pipeline layout. */
static cvk_result check_limits(const cvk_context* ctx, const cvk_binding* bindings,
                               uint32_t binding_count, cvk_error* error)
{
    const VkPhysicalDeviceLimits* limits = &ctx->properties.limits;
    static const VkShaderStageFlagBits stages[] = {
        VK_SHADER_STAGE_COMPUTE_BIT, VK_SHADER_STAGE_VERTEX_BIT, VK_SHADER_STAGE_FRAGMENT_BIT,
        VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT, VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT};
    for (size_t s = 0; s < sizeof stages / sizeof stages[0]; s++) {
        uint32_t storage_images = 0, storage_buffers = 0, sampled = 0;
        for (uint32_t i = 0; i < binding_count; i++) {
            if (!(stages_of(&bindings[i]) & stages[s]))
                continue;
            VkDescriptorType t = bindings[i].type;
            storage_images += t == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE ||
                              t == VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
            storage_buffers += t == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            sampled += t == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER ||
                       t == VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE ||
                       t == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
        }
        const char* kind = NULL;
        uint32_t used = 0, most = 0;
        if (storage_images > limits->maxPerStageDescriptorStorageImages)
            kind = "storage images and storage texel buffers", used = storage_images,
            most = limits->maxPerStageDescriptorStorageImages;
        else if (storage_buffers > limits->maxPerStageDescriptorStorageBuffers)
            kind = "storage buffers", used = storage_buffers,
            most = limits->maxPerStageDescriptorStorageBuffers;
        else if (sampled > limits->maxPerStageDescriptorSampledImages)
            kind = "sampled images and uniform texel buffers", used = sampled,
            most = limits->maxPerStageDescriptorSampledImages;
        if (kind)
            return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                            "a descriptor set of %u %s for one shader stage is more than %s "
                            "allows (maxPerStageDescriptor*: %u)",
                            used, kind, ctx->properties.deviceName, most);
    }
    return CVK_SUCCESS;
}

cvk_result cvk_descriptors_create(cvk_context* ctx, const cvk_binding* bindings,
                                  uint32_t binding_count, uint32_t set_count,
                                  VkShaderStageFlags push_stages, uint32_t push_bytes,
                                  cvk_descriptors* out, cvk_error* error)
{
    return cvk_descriptors_create_with(ctx, bindings, binding_count, set_count, push_stages,
                                       push_bytes, NULL, 0, out, error);
}

cvk_result cvk_descriptors_create_with(cvk_context* ctx, const cvk_binding* bindings,
                                       uint32_t binding_count, uint32_t set_count,
                                       VkShaderStageFlags push_stages, uint32_t push_bytes,
                                       const VkDescriptorSetLayout* extra_layouts,
                                       uint32_t extra_count, cvk_descriptors* out,
                                       cvk_error* error)
{
    *out = (cvk_descriptors){.bindings = bindings, .binding_count = binding_count,
                             .set_count = set_count};
    if (set_count == 0 || set_count > CVK_MAX_SETS || binding_count == 0 ||
        binding_count > CVK_MAX_BINDINGS || extra_count > CVK_MAX_EXTRA_SETS)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "a descriptor table needs 1 to %u sets, 1 to %u bindings and at most %u "
                        "other set layouts", CVK_MAX_SETS, CVK_MAX_BINDINGS, CVK_MAX_EXTRA_SETS);
    cvk_result r = check_limits(ctx, bindings, binding_count, error);
    if (r != CVK_SUCCESS)
        return r;
    r = create_layouts(ctx, out, push_stages, push_bytes, extra_layouts, extra_count, error);
    if (r == CVK_SUCCESS)
        r = create_sets(ctx, out, error);
    if (r != CVK_SUCCESS)
        cvk_descriptors_destroy(ctx, out);
    return r;
}

void cvk_descriptors_write(cvk_context* ctx, const cvk_descriptors* d, uint32_t set,
                           const cvk_resource* resources)
{
    uint32_t n = d->binding_count;
    VkWriteDescriptorSet writes[CVK_MAX_BINDINGS];
    VkDescriptorBufferInfo buffers[CVK_MAX_BINDINGS];
    VkDescriptorImageInfo images[CVK_MAX_BINDINGS];
    for (uint32_t i = 0; i < n; i++) {
        const cvk_resource* res = &resources[i];
        writes[i] = (VkWriteDescriptorSet){
            .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
            .dstSet = d->sets[set],
            .dstBinding = i,
            .descriptorCount = 1,
            .descriptorType = d->bindings[i].type,
        };
        switch (d->bindings[i].type) {
        case VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER:
        case VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER:
            writes[i].pTexelBufferView = &res->view;
            break;
        case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER:
        case VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE:
        case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
            images[i] = (VkDescriptorImageInfo){res->sampler, res->image,
                                                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
            writes[i].pImageInfo = &images[i];
            break;
        default:
            buffers[i] = (VkDescriptorBufferInfo){res->buffer->buffer, 0, VK_WHOLE_SIZE};
            writes[i].pBufferInfo = &buffers[i];
            break;
        }
    }
    vkUpdateDescriptorSets(ctx->device, n, writes, 0, NULL);
}

void cvk_descriptors_destroy(cvk_context* ctx, cvk_descriptors* d)
{
    if (d->pool)
        vkDestroyDescriptorPool(ctx->device, d->pool, NULL);
    /* The layouts are the context's (cvk_cached_set_layout, cvk_cached_pipeline_layout). */
    *d = (cvk_descriptors){0};
}
