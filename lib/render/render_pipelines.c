/* The renderer's graphics pipelines, each from a recipe: shaders, vertex input, target pass
   and size, depth, stencil and bias. */
#include "core/error.h"
#include "render/render_internal.h"
#include "core/shaders.h"

/* Slope-scaled depth bias of the shadow pass (in units of the depth format's step). */
#define SHADOW_BIAS_CONSTANT 2.0f
#define SHADOW_BIAS_SLOPE 2.5f
/* The wireframe's bias towards the eye (reversed depth: larger is nearer). A line's sample and
   its triangle's nearest sample can lie a pixel apart across the edge: a slope factor above 1
   covers that difference in depth, and the constant the rounding of a float depth. */
#define WIRE_BIAS_CONSTANT 4.0f
#define WIRE_BIAS_SLOPE 1.5f
/* A multisampled line one pixel wide that runs between two pixel rows covers half the samples
   of each (a faint line beside a dark one); 1.5 pixels always cover three quarters of one. */
#define WIRE_WIDTH 1.5f

typedef struct pipeline_recipe {
    const char* what;
    cvk_shader_id vertex, fragment;  /* fragment CVK_SHADER_COUNT: none (depth only) */
    uint32_t attributes;             /* 0: no vertex buffer; 1: position; 2: position, normal;
                                        3: and texture coordinates (binding 1); colliders 4: and
                                        position and normal in the texture frame (binding 0) */
    bool colliders;                  /* the collider buffers' layout, not the cloth mesh's */
    VkPrimitiveTopology topology;
    VkRenderPass pass;
    uint32_t width, height;
    VkSampleCountFlagBits samples;
    bool depth_test;
    VkCompareOp depth_compare;
    bool depth_bias;
    int stencil;                     /* 1: write 1 everywhere drawn; -1: draw only where 0; 2: draw
                                        only where 0, and write 1 there (each pixel once) */
    uint32_t spec[4];                /* specialization constants 0 to 3 of both stages */
    bool lines;                      /* triangles drawn as their edges, depth tested, not written */
    bool curved;                     /* triangles as PN patches, tessellated (render.smooth) */
} pipeline_recipe;

static cvk_result create_module(cvk_context* ctx, cvk_shader_id id, VkShaderModule* out, cvk_error* error)
{
    cvk_spirv spirv = cvk_shader(id);
    return cvk_shader_module_create(ctx, spirv.code, spirv.bytes, spirv.name, out, error);
}

/* The fixed-function state of one recipe; pointers inside point into the struct itself. */
typedef struct fixed_state {
    VkVertexInputBindingDescription bindings[2];
    VkVertexInputAttributeDescription attributes[4];
    VkPipelineVertexInputStateCreateInfo vertex_input;
    VkPipelineInputAssemblyStateCreateInfo assembly;
    VkViewport viewport;
    VkRect2D scissor;
    VkPipelineViewportStateCreateInfo viewport_state;
    VkPipelineRasterizationStateCreateInfo raster;
    VkPipelineMultisampleStateCreateInfo multisample;
    VkPipelineDepthStencilStateCreateInfo depth;
    VkPipelineColorBlendAttachmentState blend_attachment;
    VkPipelineColorBlendStateCreateInfo blend;
} fixed_state;

/* Vertex input, assembly, viewport and scissor over the whole target. */
static void geometry_state(const cvk_renderer* rd, const pipeline_recipe* p, fixed_state* f)
{
    cvk_mesh_buffers mesh = cvk_mesh_get_buffers(rd->mesh);
    /* Collider vertices: position, normal, and both in the texture frame, 3 floats each
       (render_colliders.c). */
    uint32_t stride = p->colliders ? 12 * sizeof(float) : mesh.vertex_stride;
    uint32_t position = p->colliders ? 0 : mesh.position_offset;
    uint32_t normal = p->colliders ? 3 * sizeof(float) : mesh.normal_offset;
    f->bindings[0] = (VkVertexInputBindingDescription){0, stride, VK_VERTEX_INPUT_RATE_VERTEX};
    f->bindings[1] = (VkVertexInputBindingDescription){1, 2 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX};
    f->attributes[0] = (VkVertexInputAttributeDescription){0, 0, VK_FORMAT_R32G32B32_SFLOAT, position};
    f->attributes[1] = (VkVertexInputAttributeDescription){1, 0, VK_FORMAT_R32G32B32_SFLOAT, normal};
    f->attributes[2] = p->colliders ? (VkVertexInputAttributeDescription){2, 0, VK_FORMAT_R32G32B32_SFLOAT, 24}
                                    : (VkVertexInputAttributeDescription){2, 1, VK_FORMAT_R32G32_SFLOAT, 0};
    f->attributes[3] = (VkVertexInputAttributeDescription){3, 0, VK_FORMAT_R32G32B32_SFLOAT, 36};
    f->vertex_input = (VkPipelineVertexInputStateCreateInfo){
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
        .vertexBindingDescriptionCount = p->attributes == 0 ? 0 : p->attributes == 3 && !p->colliders ? 2 : 1,
        .pVertexBindingDescriptions = f->bindings,
        .vertexAttributeDescriptionCount = p->attributes,
        .pVertexAttributeDescriptions = f->attributes,
    };
    f->assembly = (VkPipelineInputAssemblyStateCreateInfo){
        .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
        .topology = p->curved ? VK_PRIMITIVE_TOPOLOGY_PATCH_LIST : p->topology,
    };
    f->viewport = (VkViewport){0.0f, 0.0f, (float)p->width, (float)p->height, 0.0f, 1.0f};
    f->scissor = (VkRect2D){{0, 0}, {p->width, p->height}};
    f->viewport_state = (VkPipelineViewportStateCreateInfo){
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
        .viewportCount = 1,
        .pViewports = &f->viewport,
        .scissorCount = 1,
        .pScissors = &f->scissor,
    };
}

/* Rasterisation, multisampling, depth, stencil and blending. */
static void raster_state(const pipeline_recipe* p, VkCullModeFlags cull, bool has_fragment, bool wide_lines,
                         fixed_state* f)
{
    /* No culling: both faces of the cloth are drawn, and both cast shadows. A slab (a cloth with
       a material thickness) is closed: each of its faces is drawn from outside only. */
    f->raster = (VkPipelineRasterizationStateCreateInfo){
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = p->lines ? VK_POLYGON_MODE_LINE : VK_POLYGON_MODE_FILL,
        .cullMode = cull,
        .frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE,
        .depthBiasEnable = p->depth_bias,
        .depthBiasConstantFactor = !p->depth_bias ? 0.0f : p->lines ? WIRE_BIAS_CONSTANT : SHADOW_BIAS_CONSTANT,
        .depthBiasSlopeFactor = !p->depth_bias ? 0.0f : p->lines ? WIRE_BIAS_SLOPE : SHADOW_BIAS_SLOPE,
        .lineWidth = p->lines && wide_lines ? WIRE_WIDTH : 1.0f,
    };
    f->multisample = (VkPipelineMultisampleStateCreateInfo){
        .sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
        .rasterizationSamples = p->samples,
    };
    VkStencilOpState stencil = {
        .failOp = VK_STENCIL_OP_KEEP,
        .passOp = p->stencil == 1 ? VK_STENCIL_OP_REPLACE
                  : p->stencil == 2 ? VK_STENCIL_OP_INCREMENT_AND_CLAMP
                                    : VK_STENCIL_OP_KEEP,
        .depthFailOp = VK_STENCIL_OP_KEEP,
        .compareOp = p->stencil == 1 ? VK_COMPARE_OP_ALWAYS : VK_COMPARE_OP_EQUAL,
        .compareMask = 0xff,
        .writeMask = 0xff,
        .reference = p->stencil == 1 ? 1u : 0u,
    };
    f->depth = (VkPipelineDepthStencilStateCreateInfo){
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
        .depthTestEnable = p->depth_test,
        .depthWriteEnable = p->depth_test && !p->lines,
        .depthCompareOp = p->depth_compare,
        .stencilTestEnable = p->stencil != 0,
        .front = stencil,
        .back = stencil,
    };
    f->blend_attachment = (VkPipelineColorBlendAttachmentState){
        .colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                          VK_COLOR_COMPONENT_A_BIT,
    };
    f->blend = (VkPipelineColorBlendStateCreateInfo){
        .sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
        .attachmentCount = has_fragment ? 1 : 0,
        .pAttachments = &f->blend_attachment,
    };
}

/* The recipe's pipeline culling `cull` (none but for a slab's faces). */
static cvk_result create_culled(cvk_renderer* rd, const pipeline_recipe* p, VkCullModeFlags cull, VkPipeline* out,
                                cvk_error* error)
{
    VkShaderModule modules[4] = {VK_NULL_HANDLE, VK_NULL_HANDLE, VK_NULL_HANDLE, VK_NULL_HANDLE};
    bool has_fragment = p->fragment != CVK_SHADER_COUNT;
    cvk_result r = create_module(rd->context, p->vertex, &modules[0], error);
    if (r == CVK_SUCCESS && has_fragment)
        r = create_module(rd->context, p->fragment, &modules[1], error);
    if (r == CVK_SUCCESS && p->curved)
        r = create_module(rd->context, CVK_SHADER_PN_TESC, &modules[2], error);
    if (r == CVK_SUCCESS && p->curved)
        r = create_module(rd->context, CVK_SHADER_PN_TESE, &modules[3], error);
    if (r != CVK_SUCCESS) {
        for (int i = 0; i < 4; i++)
            if (modules[i])
                vkDestroyShaderModule(rd->context->device, modules[i], NULL);
        return r;
    }
    /* Constants 0 to 3: the recipe's; 4 to 8: what every pass shares (lighting.glsl,
       composite.frag, pn.tesc). */
    uint32_t values[9] = {p->spec[0], p->spec[1], p->spec[2], p->spec[3],
                          rd->desc.soft_shadows && rd->desc.key_angle > 0.0f, rd->desc.sky_light, rd->desc.tone_map,
                          rd->desc.smooth, rd->colliders.ground_texture != 0};
    VkSpecializationMapEntry entries[9];
    for (uint32_t i = 0; i < 9; i++)
        entries[i] = (VkSpecializationMapEntry){i, i * (uint32_t)sizeof(uint32_t), sizeof(uint32_t)};
    VkSpecializationInfo spec = {9, entries, sizeof values, values};
    VkPipelineShaderStageCreateInfo stages[4];
    uint32_t stage_count = 0;
    const VkShaderStageFlagBits kinds[4] = {VK_SHADER_STAGE_VERTEX_BIT, VK_SHADER_STAGE_FRAGMENT_BIT,
                                            VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT,
                                            VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT};
    for (int i = 0; i < 4; i++)
        if (modules[i])
            stages[stage_count++] = (VkPipelineShaderStageCreateInfo){
                .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, .stage = kinds[i],
                .module = modules[i], .pName = "main", .pSpecializationInfo = &spec};
    VkPipelineTessellationStateCreateInfo tessellation = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_TESSELLATION_STATE_CREATE_INFO,
        .patchControlPoints = 3,
    };
    fixed_state f;
    geometry_state(rd, p, &f);
    raster_state(p, cull, has_fragment, rd->context->wide_lines, &f);
    VkGraphicsPipelineCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
        .stageCount = stage_count,
        .pStages = stages,
        .pVertexInputState = &f.vertex_input,
        .pInputAssemblyState = &f.assembly,
        .pTessellationState = p->curved ? &tessellation : NULL,
        .pViewportState = &f.viewport_state,
        .pRasterizationState = &f.raster,
        .pMultisampleState = &f.multisample,
        .pDepthStencilState = &f.depth,
        .pColorBlendState = &f.blend,
        .layout = rd->pipeline_layout,
        .renderPass = p->pass,
    };
    VkResult vr = vkCreateGraphicsPipelines(rd->context->device, VK_NULL_HANDLE, 1, &info, NULL, out);
    for (int i = 0; i < 4; i++)
        if (modules[i])
            vkDestroyShaderModule(rd->context->device, modules[i], NULL);
    if (vr != VK_SUCCESS) {
        *out = VK_NULL_HANDLE;
        return cvk_fail_vk_for(error, "vkCreateGraphicsPipelines", vr, "%s", p->what);
    }
    return CVK_SUCCESS;
}

static cvk_result create_pipeline(cvk_renderer* rd, const pipeline_recipe* p, VkPipeline* out, cvk_error* error)
{
    return create_culled(rd, p, VK_CULL_MODE_NONE, out, error);
}

/* The colliders' lit pipeline (`recipe`) culling back faces, for closed solids, when there
   is one to draw. */
static cvk_result create_collider_closed(cvk_renderer* rd, const pipeline_recipe* recipe, cvk_error* error)
{
    bool closed = false;
    for (uint32_t d = 0; d < rd->colliders.draw_count; d++)
        closed = closed || rd->colliders.draws[d].closed;
    if (!closed)
        return CVK_SUCCESS;
    pipeline_recipe p = *recipe;
    p.what = "collider pass (closed solids)";
    return create_culled(rd, &p, VK_CULL_MODE_BACK_BIT, &rd->collider_closed_pipeline, error);
}

/* The ambient occlusion pass's pipeline and its blur's, over the occupied rectangle (ao.vert). */
static cvk_result create_occlusion_pipelines(cvk_renderer* rd, bool single, cvk_error* error)
{
    uint32_t w = cvk_render_half(rd->desc.size[0]), h = cvk_render_half(rd->desc.size[1]);
    pipeline_recipe p = {
        "ambient occlusion pass", CVK_SHADER_AO_VERT, single ? CVK_SHADER_AO_1X_FRAG : CVK_SHADER_AO_FRAG, 0, false,
        VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP, rd->occlusion_pass, w, h, VK_SAMPLE_COUNT_1_BIT, false,
        VK_COMPARE_OP_ALWAYS, false, 0, {0}, false, false};
    cvk_result r = create_pipeline(rd, &p, &rd->occlusion_pipeline, error);
    if (r != CVK_SUCCESS)
        return r;
    p.what = "ambient occlusion blur pass";
    p.fragment = CVK_SHADER_AO_BLUR_FRAG;
    p.pass = rd->blur_pass;
    return create_pipeline(rd, &p, &rd->blur_pipeline, error);
}

/* The composite over where the ground can be in a shadow (the occupied box's shadow on it),
   the only one that reads the shadow map: the rectangle's recipe `rect` with the footprint's
   triangles and SHADOWED; none without shadows on the ground. */
static cvk_result create_footprint(cvk_renderer* rd, const pipeline_recipe* rect, cvk_error* error)
{
    if (!cvk_render_footprint_drawn(rd))
        return CVK_SUCCESS;
    pipeline_recipe p = *rect;
    p.what = "composite pass (the ground's shadows)";
    p.vertex = CVK_SHADER_COMPOSITE_FOOTPRINT_VERT;
    p.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    p.spec[1] = true;
    return create_pipeline(rd, &p, &rd->footprint_pipeline, error);
}

cvk_result cvk_renderer_create_pipelines(cvk_renderer* rd, cvk_error* error)
{
    uint32_t w = rd->desc.size[0], h = rd->desc.size[1], s = rd->desc.shadow_map_size;
    bool single = rd->samples == VK_SAMPLE_COUNT_1_BIT;
    /* With a textured cloth, the cloth's lit pipelines read texture coordinates too. */
    bool textured = rd->textures.uv.buffer != VK_NULL_HANDLE;
    cvk_shader_id cloth_vert = textured ? CVK_SHADER_LIT_CLOTH_TEXTURED_VERT : CVK_SHADER_LIT_CLOTH_VERT;
    /* render.vertex_lighting: the cloth's light found at its vertices (not in the wireframe). */
    cvk_shader_id lit_vert = !rd->vertex_lit ? cloth_vert
                             : textured      ? CVK_SHADER_LIT_CLOTH_TEXTURED_VERTEX_LIT_VERT
                                             : CVK_SHADER_LIT_CLOTH_VERTEX_LIT_VERT;
    cvk_shader_id lit_frag = rd->vertex_lit ? CVK_SHADER_LIT_CLOTH_VERTEX_LIT_FRAG : CVK_SHADER_LIT_CLOTH_FRAG;
    uint32_t cloth_attributes = textured ? 3 : 2;
    cvk_shader_id composite = single ? CVK_SHADER_COMPOSITE_1X_FRAG : CVK_SHADER_COMPOSITE_FRAG;
    /* With a textured collider, the colliders' lit pipeline reads their textures. */
    bool collider_textured = false;
    for (uint32_t d = 0; d < rd->colliders.draw_count; d++)
        collider_textured = collider_textured || rd->colliders.draws[d].textured;
    const pipeline_recipe recipes[] = {
        {"shadow pass", CVK_SHADER_SHADOW_VERT, CVK_SHADER_COUNT, 2, false, VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
         rd->shadow_pass, s, s, VK_SAMPLE_COUNT_1_BIT, true, VK_COMPARE_OP_LESS_OR_EQUAL, true, 0, {0}, false, false},
        /* Reversed depth: nearer is greater. */
        {"cloth pass", lit_vert, lit_frag, cloth_attributes, false,
         VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, rd->cloth_pass, w, h, rd->samples, true, VK_COMPARE_OP_GREATER_OR_EQUAL,
         false, 0, {rd->desc.ground, textured, true}, false, rd->desc.smooth > 1},
        /* The image outside the occupied rectangle, where it is drawn: nothing there is shadowed,
           occluded or drawn by the cloth pass. */
        {"composite pass", CVK_SHADER_COMPOSITE_VERT, composite, 0, false, VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
         rd->composite_pass, w, h, VK_SAMPLE_COUNT_1_BIT, false, VK_COMPARE_OP_ALWAYS, false, -1,
         {cvk_render_rect_drawn(rd), false, rd->desc.samples, false}, false, false},
        /* The cloth pass's rectangle, with the occlusion; the ground's shadows drawn before
           (create_footprint) are skipped. */
        {"composite pass (cloth and occlusion)", CVK_SHADER_COMPOSITE_RECT_VERT, composite, 0, false,
         VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP, rd->composite_pass, w, h, VK_SAMPLE_COUNT_1_BIT, false,
         VK_COMPARE_OP_ALWAYS, false, 2, {false, false, rd->desc.samples, rd->desc.ao}, false, false},
        /* The colliders: shaded like the cloth (lit_cloth.frag with COLLIDER), posed in the
           vertex shader. */
        {"collider shadow pass", CVK_SHADER_COLLIDER_SHADOW_VERT, CVK_SHADER_COUNT, 1, true,
         VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, rd->shadow_pass, s, s, VK_SAMPLE_COUNT_1_BIT, true,
         VK_COMPARE_OP_LESS_OR_EQUAL, true, 0, {0}, false, false},
        {"collider pass", CVK_SHADER_COLLIDER_VERT, CVK_SHADER_LIT_COLLIDER_FRAG, 4, true,
         VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, rd->cloth_pass, w, h, rd->samples, true,
         VK_COMPARE_OP_GREATER_OR_EQUAL, false, 0, {rd->desc.ground, collider_textured, false}, false, false},
    };
    VkPipeline* outs[] = {&rd->shadow_pipeline,     &rd->cloth_pipeline,           &rd->background_pipeline,
                          &rd->rect_pipeline,      &rd->collider_shadow_pipeline, &rd->collider_pipeline};
    size_t count = rd->colliders.draw_count > 0 ? 6 : 4;
    cvk_result r = create_collider_closed(rd, &recipes[5], error);
    for (size_t i = 0; i < count && r == CVK_SUCCESS; i++)
        if (i != 3 || cvk_render_rect_drawn(rd)) /* the rectangle apart only where it is drawn */
            r = create_pipeline(rd, &recipes[i], outs[i], error);
    if (r != CVK_SUCCESS)
        return r;
    r = create_footprint(rd, &recipes[3], error);
    if (rd->desc.ao && r == CVK_SUCCESS)
        r = create_occlusion_pipelines(rd, single, error);
    if (r != CVK_SUCCESS)
        return r;
    const cvk_build* b = &rd->mesh->sim->build;
    bool slab = false;
    for (uint32_t c = 0; c < b->cloth_count; c++)
        slab = slab || b->cloths[c].thickness > 0.0f;
    for (int side = 0; slab && side < 2; side++) {
        pipeline_recipe p = recipes[1];
        p.what = side == 0 ? "cloth pass (front faces)" : "cloth pass (back faces)";
        r = create_culled(rd, &p, side == 0 ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_FRONT_BIT,
                          &rd->slab_pipelines[side], error);
        if (r != CVK_SUCCESS)
            return r;
    }
    if (!rd->desc.wireframe)
        return CVK_SUCCESS;
    const pipeline_recipe wireframe = {
        "wireframe pass", cloth_vert, CVK_SHADER_WIREFRAME_FRAG, cloth_attributes, false,
        VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, rd->cloth_pass, w, h, rd->samples, true,
        VK_COMPARE_OP_GREATER_OR_EQUAL, true, 0, {rd->desc.ground}, true, false};
    return create_pipeline(rd, &wireframe, &rd->wireframe_pipeline, error);
}

