/* A frame of the renderer (render.c has the passes' design): its commands, recorded once at
   creation into one command buffer (the mesh generation, the shadow pass, the lit pass, the
   copy into the readback buffer, a timestamp after each), then drawn, and what a drawn frame
   gives: the image, the timings and the view. */
#include <stdint.h>
#include <string.h>

#include "core/error.h"
#include "render/render_internal.h"

/* ---- recording ----------------------------------------------------------------------------- */

static void timestamp(const cvk_renderer* rd, VkCommandBuffer cmd, uint32_t query)
{
    if (rd->queries)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, rd->queries, query);
}

/* Which of a cloth's parts a pass draws: the lit and shadow passes the whole slab, the
   wireframe its two faces. */
typedef enum cloth_parts { FACES, SLAB } cloth_parts;

/* The push constants of a cloth: its material, the slab's offset `offset` and thickness
   `through`, and its normal map's strength (0: none). */
static void push_cloth(const cvk_renderer* rd, VkCommandBuffer cmd, const cvk_cloth_range* cloth, bool textured,
                       float offset, float through, float normal_strength)
{
    bool back = cloth->back_color[0] >= 0.0f;
    cvk_render_material m = {
        {cloth->color[0], cloth->color[1], cloth->color[2], textured ? 1.0f : 0.0f},
        {back ? cloth->back_color[0] : 0.0f, back ? cloth->back_color[1] : 0.0f, back ? cloth->back_color[2] : 0.0f,
         back ? 1.0f : 0.0f},
        {cloth->sheen, cloth->roughness, 0.0f, 0.0f},
        {offset, through, normal_strength, 0.0f},
    };
    vkCmdPushConstants(cmd, rd->pipeline_layout, CVK_RENDER_PUSH_STAGES, 0, sizeof m, &m);
}

/* Binds `pipeline` unless it is bound already (*bound) or there is none to switch to. */
static void use(VkCommandBuffer cmd, VkPipeline pipeline, VkPipeline* bound)
{
    if (!pipeline || pipeline == *bound)
        return;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
    *bound = pipeline;
}

void cvk_render_bind_textures(const cvk_renderer* rd, VkCommandBuffer cmd, uint32_t set, uint32_t* bound)
{
    if (set == *bound)
        return;
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->pipeline_layout, 0, 1,
                            &rd->descriptors.sets[set], 0, NULL);
    *bound = set;
}

/* Each cloth's triangles; a cloth with a thickness twice, its faces moved half of it each way
   along the normals (lit_cloth.vert, shadow.vert), and with SLAB then every rim (render/mesh.h)
   from the rim's own buffers, whose vertices the mesh pass already placed. With `pipelines`
   (the lit pass: the bound pipeline, then rd->slab_pipelines) a slab's front face and rim are
   drawn culling back faces and its back face culling front faces, so each pixel of the closed
   slab is shaded once. */
static void draw_cloths(const cvk_renderer* rd, VkCommandBuffer cmd, bool colored, cloth_parts parts,
                        const VkPipeline* pipelines)
{
    VkPipeline current = pipelines ? pipelines[0] : VK_NULL_HANDLE;
    cvk_mesh_buffers mesh = cvk_mesh_get_buffers(rd->mesh);
    VkBuffer buffers[2] = {mesh.vertex_buffer, rd->textures.uv.buffer};
    VkDeviceSize offsets[2] = {0, 0};
    /* The texture coordinates only for the lit pipelines, and only when a cloth has a texture. */
    uint32_t bindings = colored && rd->textures.uv.buffer ? 2 : 1;
    vkCmdBindVertexBuffers(cmd, 0, bindings, buffers, offsets);
    vkCmdBindIndexBuffer(cmd, mesh.index_buffer, 0, mesh.index_type);
    const cvk_build* b = &rd->mesh->sim->build;
    uint32_t bound = 0;
    for (uint32_t c = 0; c < mesh.cloth_count; c++) {
        if (mesh.cloths[c].index_count == 0)
            continue;
        if (colored)
            cvk_render_bind_textures(rd, cmd, rd->textures.set_of[c], &bound);
        float thickness = b->cloths[c].thickness;
        if (pipelines && thickness <= 0.0f)
            use(cmd, pipelines[0], &current);
        for (int side = 0; side < (thickness > 0.0f ? 2 : 1); side++) {
            if (pipelines && thickness > 0.0f)
                use(cmd, pipelines[1 + side], &current);
            push_cloth(rd, cmd, &b->cloths[c], b->cloths[c].texture != NULL,
                       side ? -0.5f * thickness : 0.5f * thickness, thickness,
                       b->cloths[c].normal_map ? b->cloths[c].normal_strength : 0.0f);
            vkCmdDrawIndexed(cmd, mesh.cloths[c].index_count, 1, mesh.cloths[c].first_index, 0, 0);
        }
    }
    if (parts == SLAB && rd->mesh->rim_edge_count > 0) {
        buffers[0] = rd->mesh->rim_vertices.buffer;
        offsets[1] = 2 * sizeof(float) * (VkDeviceSize)mesh.vertex_count;
        vkCmdBindVertexBuffers(cmd, 0, bindings, buffers, offsets);
        vkCmdBindIndexBuffer(cmd, rd->mesh->rim_indices.buffer, 0, VK_INDEX_TYPE_UINT32);
        for (uint32_t c = 0; c < mesh.cloth_count; c++) {
            const cvk_mesh_range* rim = &rd->mesh->rims[c];
            if (rim->index_count == 0)
                continue;
            if (colored)
                cvk_render_bind_textures(rd, cmd, rd->textures.set_of[c], &bound);
            push_cloth(rd, cmd, &b->cloths[c], b->cloths[c].texture != NULL, 0.0f, 0.0f, 0.0f);
            if (pipelines)
                use(cmd, pipelines[1], &current);
            vkCmdDrawIndexed(cmd, rim->index_count, 1, rim->first_index, 0, 0);
        }
    }
    if (bound != 0)
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->pipeline_layout, 0, 1, &rd->set, 0, NULL);
    if (pipelines)
        use(cmd, pipelines[0], &current);
}

static void begin_pass(VkCommandBuffer cmd, VkRenderPass pass, VkFramebuffer framebuffer, uint32_t width,
                       uint32_t height, const VkClearValue* clears, uint32_t clear_count)
{
    VkRenderPassBeginInfo begin = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
        .renderPass = pass,
        .framebuffer = framebuffer,
        .renderArea = {{0, 0}, {width, height}},
        .clearValueCount = clear_count,
        .pClearValues = clears,
    };
    vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
}

static void record_shadow_pass(const cvk_renderer* rd, VkCommandBuffer cmd)
{
    VkClearValue clear = {.depthStencil = {1.0f, 0}};
    begin_pass(cmd, rd->shadow_pass, rd->shadow_framebuffer, rd->desc.shadow_map_size,
               rd->desc.shadow_map_size, &clear, 1);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->shadow_pipeline);
    draw_cloths(rd, cmd, false, SLAB, NULL);
    if (rd->collider_shadow_pipeline) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->collider_shadow_pipeline);
        cvk_render_colliders_record(rd, cmd, false);
    }
    vkCmdEndRenderPass(cmd);
}

static void record_lit_pass(const cvk_renderer* rd, VkCommandBuffer cmd)
{
    /* transparent black and the far depth (reversed z); the composite pass clears its stencil */
    VkClearValue clears[2] = {{.color = {{0.0f, 0.0f, 0.0f, 0.0f}}}, {.depthStencil = {0.0f, 0}}};
    uint32_t w = rd->desc.size[0], h = rd->desc.size[1];
    begin_pass(cmd, rd->cloth_pass, rd->cloth_framebuffer, w, h, clears, 2);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->cloth_pipeline);
    const VkPipeline lit[3] = {rd->cloth_pipeline, rd->slab_pipelines[0], rd->slab_pipelines[1]};
    draw_cloths(rd, cmd, true, SLAB, lit);
    if (rd->wireframe_pipeline) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->wireframe_pipeline);
        draw_cloths(rd, cmd, true, FACES, NULL);
    }
    if (rd->collider_pipeline) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->collider_pipeline);
        cvk_render_colliders_record(rd, cmd, true);
    }
    vkCmdEndRenderPass(cmd);
    timestamp(rd, cmd, 3);

    if (rd->occlusion_pipeline) {
        /* open (light 1) at depth 0 outside the rectangle ao.vert draws */
        VkClearValue open = {.color = {{1.0f, 0.0f, 0.0f, 0.0f}}};
        uint32_t ow = cvk_render_half(rd->desc.size[0]), oh = cvk_render_half(rd->desc.size[1]);
        begin_pass(cmd, rd->occlusion_pass, rd->occlusion_framebuffer, ow, oh, &open, 1);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->occlusion_pipeline);
        vkCmdDraw(cmd, 4, 1, 0, 0);
        vkCmdEndRenderPass(cmd);
        begin_pass(cmd, rd->blur_pass, rd->blur_framebuffer, ow, oh, &open, 1);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->blur_pipeline);
        vkCmdDraw(cmd, 4, 1, 0, 0);
        vkCmdEndRenderPass(cmd);
    }
    timestamp(rd, cmd, 4);

    begin_pass(cmd, rd->composite_pass, rd->composite_framebuffer, w, h, clears, 2);
    /* A textured ground reads its plane collider's texture set. */
    uint32_t bound = 0, ground = rd->colliders.ground_texture;
    if (ground)
        cvk_render_bind_textures(rd, cmd, rd->textures.collider_set_of[ground - 1], &bound);
    /* First where a shadow can fall on the ground (the occupied box's shadow: 12 triangles),
       the only draw that reads the shadow map; then the rest of the rectangle where the cloth
       pass drew and occlusion can darken; then everything else. Each marks its pixels and
       skips those marked. */
    if (rd->footprint_pipeline) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->footprint_pipeline);
        vkCmdDraw(cmd, 36, 1, 0, 0);
    }
    if (rd->rect_pipeline) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->rect_pipeline);
        vkCmdDraw(cmd, 4, 1, 0, 0);
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->background_pipeline);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRenderPass(cmd);
    if (bound != 0)
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->pipeline_layout, 0, 1, &rd->set, 0, NULL);
}

static void record_readback(const cvk_renderer* rd, VkCommandBuffer cmd)
{
    VkBufferImageCopy region = {
        .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .imageExtent = {rd->desc.size[0], rd->desc.size[1], 1},
    };
    vkCmdCopyImageToBuffer(cmd, rd->image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, rd->readback.buffer, 1,
                           &region);
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                    VK_ACCESS_HOST_READ_BIT);
}

cvk_result cvk_renderer_record(cvk_renderer* rd, VkCommandBuffer cmd, cvk_error* error)
{
    if (!rd || !cmd)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_renderer_record needs a renderer and a command buffer");
    if (rd->queries)
        vkCmdResetQueryPool(cmd, rd->queries, 0, CVK_RENDER_QUERY_COUNT);
    timestamp(rd, cmd, 0);
    cvk_result r = cvk_mesh_record(rd->mesh, cmd, error);
    if (r != CVK_SUCCESS)
        return r;
    timestamp(rd, cmd, 1);
    /* The colliders' vertex shaders also read the poses the simulation wrote. */
    /* The occupied box's dispatch reads the mesh too. */
    bool colliders = rd->colliders.draw_count > 0;
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                        (colliders ? VK_PIPELINE_STAGE_VERTEX_SHADER_BIT : 0),
                    VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
    cvk_render_occupied_record(rd, cmd);
    /* one set for every graphics pipeline of the frame; bindings outlive render passes */
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->pipeline_layout, 0, 1, &rd->set, 0, NULL);
    record_shadow_pass(rd, cmd);
    timestamp(rd, cmd, 2);
    record_lit_pass(rd, cmd);
    timestamp(rd, cmd, 5);
    record_readback(rd, cmd);
    timestamp(rd, cmd, 6);
    /* The next simulated frame rewrites the poses: these draws finish reading them first (the
       mesh generation's own barrier covers only vertex input). */
    if (colliders)
        cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_VERTEX_SHADER_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0);
    return CVK_SUCCESS;
}

/* ---- frames -------------------------------------------------------------------------------- */

cvk_result cvk_renderer_draw(cvk_renderer* rd, cvk_error* error)
{
    if (!rd)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_renderer_draw needs a renderer");
    cvk_result r = cvk_submit_and_wait(rd->context, &rd->submitter, &rd->frame_cmd, 1, error);
    if (r == CVK_SUCCESS && rd->desc.overlay)
        cvk_render_overlay_draw(rd);
    return r;
}

cvk_image cvk_renderer_get_image(const cvk_renderer* rd)
{
    return (cvk_image){
        .pixels = rd->readback.mapped,
        .width = rd->desc.size[0],
        .height = rd->desc.size[1],
        .row_bytes = 4u * rd->desc.size[0],
    };
}

cvk_render_timing cvk_renderer_get_timing(const cvk_renderer* rd)
{
    cvk_render_timing t = {-1.0, -1.0, -1.0, -1.0, -1.0, -1.0, rd->overlay_ms, -1.0};
    if (!rd->queries)
        return t;
    uint64_t data[2 * CVK_RENDER_QUERY_COUNT];
    VkResult vr = vkGetQueryPoolResults(rd->context->device, rd->queries, 0, CVK_RENDER_QUERY_COUNT, sizeof data, data,
                                        2 * sizeof(uint64_t),
                                        VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
    if (vr != VK_SUCCESS)
        return t;
    for (int q = 0; q < CVK_RENDER_QUERY_COUNT; q++)
        if (!data[2 * q + 1])
            return t;
    uint32_t bits = rd->context->timestamp_valid_bits;
    uint64_t mask = bits >= 64 ? UINT64_MAX : ((uint64_t)1 << bits) - 1;
    double period_ms = rd->context->properties.limits.timestampPeriod * 1e-6;
    double ms[CVK_RENDER_QUERY_COUNT - 1];
    for (int q = 1; q < CVK_RENDER_QUERY_COUNT; q++)
        ms[q - 1] = (double)((data[2 * q] - data[2 * (q - 1)]) & mask) * period_ms;
    t.mesh_ms = ms[0];
    t.shadow_ms = ms[1];
    t.lit_ms = ms[2] + ms[4];
    t.composite_ms = ms[4];
    t.ao_ms = ms[3];
    t.readback_ms = ms[5];
    t.total_ms = (double)((data[2 * (CVK_RENDER_QUERY_COUNT - 1)] - data[0]) & mask) * period_ms;
    return t;
}

cvk_render_view cvk_renderer_get_view(const cvk_renderer* rd)
{
    const cvk_view* v = &rd->view;
    cvk_render_view out = {.fov_y = (float)v->fov_y, .ground_height = (float)v->ground_height};
    for (int k = 0; k < 3; k++) {
        out.eye[k] = (float)v->eye[k];
        out.target[k] = (float)v->target[k];
        out.up[k] = (float)v->up[k];
        out.reach_min[k] = (float)v->reach.lo[k];
        out.reach_max[k] = (float)v->reach.hi[k];
    }
    memcpy(out.view_proj, v->view_proj, sizeof out.view_proj);
    return out;
}
