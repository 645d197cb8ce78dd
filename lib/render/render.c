/* The offscreen renderer (seed 002 §5.4). A frame is, after the mesh generation:
   - the shadow pass: the cloth's and the colliders' depth from the key light;
   - the lit pass: the cloth and the colliders (render_colliders.c), lit and shadowed,
     multisampled over a transparent background; with render.ao the ambient occlusion at half
     resolution over the occupied rectangle (render_occupied.c), then blurred; then the
     composite, one sample per pixel: the ground and sky found from each pixel's ray (the
     shadow map read only over the occupied box's shadow on the ground) with the cloth pass's
     samples averaged over them in linear light (the resolve), into an sRGB image;
   - a copy of that image into a host-visible buffer.
   Multisampling only the cloth keeps the cost of 4x MSAA on a CPU device (lavapipe clears,
   tests and writes every sample) to the part of the image that has edges to smooth.
   Every object is made once at creation (here); a frame is one command buffer recorded once
   (render_frame.c). */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/cookie.h"
#include "core/error.h"
#include "render/render_internal.h"
#include "scene/scene.h"
#include "solvers/reference.h"
#include "topology/topology.h"

#define COLOR_FORMAT VK_FORMAT_R8G8B8A8_SRGB
/* The cloth pass stores the square root of half its linear colour (see lit_cloth.frag): about as
   fine as sRGB in the dark, and the composite pass decodes a sample with one multiply instead
   of an sRGB curve, four samples per pixel. */
#define CLOTH_FORMAT VK_FORMAT_R8G8B8A8_UNORM
#define DEPTH_FORMAT VK_FORMAT_D32_SFLOAT
/* Marks the pixels a draw of the composite pass has done, so the later ones skip them. */
#define STENCIL_FORMAT VK_FORMAT_S8_UINT
/* 16 bits cover a few metres of light depth in 0.1 mm steps, and the constant depth bias
   means a fixed distance, unlike with a float format. */
#define SHADOW_FORMAT VK_FORMAT_D16_UNORM
/* Ambient occlusion: the light left and the depth along the view, per half-resolution texel. */
#define OCCLUSION_FORMAT VK_FORMAT_R32G32_SFLOAT
/* How much of the occlusion darkens (1: a tap straight above hides all of its share), and the
   radius without render.ao_radius, as a share of the diagonal of what the camera frames. */
#define AO_STRENGTH 1.6
#define AO_RADIUS_SHARE 0.04
/* Sky light: the share of render.background the sky adds to render.ambient, and the share of
   the light reaching the ground that it sends back up. */
#define SKY_SHARE 0.12
#define BOUNCE_SHARE 0.15
/* Soft shadows: how far from a blocker (m) the search for it reaches at most, and the widest
   penumbra radius, in shadow-map texels (the search square's half side). */
#define SOFT_REACH 1.0
#define SOFT_MAX_TEXELS 24.0

/* ---- checks before anything is made ------------------------------------------------------ */

static void sample_counts(VkSampleCountFlags flags, char* out, size_t size)
{
    int count = 0;
    for (uint32_t s = 1; s <= 64; s *= 2)
        count += (flags & s) != 0;
    size_t used = 0;
    out[0] = '\0';
    int listed = 0;
    for (uint32_t s = 1; s <= 64 && used < size; s *= 2) {
        if (!(flags & s))
            continue;
        const char* separator = listed == 0 ? "" : listed == count - 1 ? " or " : ", ";
        used += (size_t)snprintf(out + used, size - used, "%s%u", separator, s);
        listed++;
    }
}

static cvk_result check_format(const cvk_context* ctx, VkFormat format, VkImageUsageFlags usage,
                               VkSampleCountFlagBits samples, const char* what, cvk_error* error)
{
    VkImageFormatProperties properties;
    VkResult vr = vkGetPhysicalDeviceImageFormatProperties(ctx->physical_device, format, VK_IMAGE_TYPE_2D,
                                                           VK_IMAGE_TILING_OPTIMAL, usage, 0, &properties);
    if (vr != VK_SUCCESS || !(properties.sampleCounts & samples))
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "%s cannot make the %s image it needs (format %d, %u samples)",
                        ctx->properties.deviceName, what, (int)format, (unsigned)samples);
    return CVK_SUCCESS;
}

static cvk_result check_device(const cvk_context* ctx, const cvk_render_desc* d, cvk_error* error)
{
    if (!ctx->graphics)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "rendering needs a queue that can draw; queue family %u of %s supports compute "
                        "only (cvk_mesh works there: draw its buffers on a graphics queue)",
                        ctx->queue_family, ctx->properties.deviceName);
    if (d->smooth > 1 && !ctx->tessellation)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "render.smooth: %s cannot tessellate (no tessellationShader)",
                        ctx->properties.deviceName);
    if (d->wireframe && !ctx->fill_mode_non_solid)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "render.wireframe: %s cannot draw triangles as lines (no fillModeNonSolid)",
                        ctx->properties.deviceName);
    uint32_t max = cvk_context_max_image_size(ctx);
    if (d->size[0] > max || d->size[1] > max)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "render.size: %u x %u pixels is more than %s allows (%u x %u)", d->size[0], d->size[1],
                        ctx->properties.deviceName, max, max);
    if (d->shadow_map_size > max)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "render.shadow_map_size: %u texels is more than %s allows (%u)", d->shadow_map_size,
                        ctx->properties.deviceName, max);
    const VkPhysicalDeviceLimits* limits = &ctx->properties.limits;
    VkSampleCountFlags supported = limits->framebufferColorSampleCounts & limits->framebufferDepthSampleCounts;
    if (!(supported & d->samples)) {
        char counts[64];
        sample_counts(supported, counts, sizeof counts);
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT, "render.samples: %s draws %s samples per pixel, not %u",
                        ctx->properties.deviceName, counts, d->samples);
    }
    VkSampleCountFlagBits samples = (VkSampleCountFlagBits)d->samples;
    if (!(limits->sampledImageColorSampleCounts & samples)) {
        char counts[64];
        sample_counts(limits->sampledImageColorSampleCounts, counts, sizeof counts);
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "render.samples: %s reads back %s samples per pixel, not %u",
                        ctx->properties.deviceName, counts, d->samples);
    }
    if (!(limits->sampledImageDepthSampleCounts & samples)) {
        char counts[64];
        sample_counts(limits->sampledImageDepthSampleCounts, counts, sizeof counts);
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "render.samples: %s reads back depths of %s samples per pixel, not %u",
                        ctx->properties.deviceName, counts, d->samples);
    }
    cvk_result r = check_format(ctx, CLOTH_FORMAT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                samples, "cloth", error);
    if (r == CVK_SUCCESS)
        r = check_format(ctx, STENCIL_FORMAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_SAMPLE_COUNT_1_BIT,
                         "stencil", error);
    if (r == CVK_SUCCESS)
        r = check_format(ctx, COLOR_FORMAT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                         VK_SAMPLE_COUNT_1_BIT, "final", error);
    if (r == CVK_SUCCESS)
        r = check_format(ctx, DEPTH_FORMAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                         samples, "depth", error);
    if (r == CVK_SUCCESS)
        r = check_format(ctx, OCCLUSION_FORMAT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                         VK_SAMPLE_COUNT_1_BIT, "ambient occlusion", error);
    if (r == CVK_SUCCESS)
        r = check_format(ctx, SHADOW_FORMAT,
                         VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                         VK_SAMPLE_COUNT_1_BIT, "shadow map", error);
    return r;
}

/* ---- images, render passes, framebuffers ---------------------------------------------- */

static cvk_result create_images(cvk_renderer* rd, cvk_error* error)
{
    cvk_context* ctx = rd->context;
    uint32_t w = rd->desc.size[0], h = rd->desc.size[1], s = rd->desc.shadow_map_size;
    cvk_result r = cvk_gpu_image_create(ctx, SHADOW_FORMAT, s, s, VK_SAMPLE_COUNT_1_BIT,
                                        VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                        VK_IMAGE_ASPECT_DEPTH_BIT, "shadow map", &rd->shadow_map, error);
    if (r == CVK_SUCCESS)
        r = cvk_gpu_image_create(ctx, CLOTH_FORMAT, w, h, rd->samples,
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                 VK_IMAGE_ASPECT_COLOR_BIT, "cloth image", &rd->cloth, error);
    if (r == CVK_SUCCESS)
        r = cvk_gpu_image_create(ctx, DEPTH_FORMAT, w, h, rd->samples,
                                 VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                 VK_IMAGE_ASPECT_DEPTH_BIT, "depth buffer", &rd->cloth_depth, error);
    uint32_t ow = cvk_render_half(rd->desc.size[0]), oh = cvk_render_half(rd->desc.size[1]);
    for (int i = 0; i < 2 && r == CVK_SUCCESS; i++)
        r = cvk_gpu_image_create(ctx, OCCLUSION_FORMAT, ow, oh, VK_SAMPLE_COUNT_1_BIT,
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                 VK_IMAGE_ASPECT_COLOR_BIT, i ? "blurred ambient occlusion image" : "ambient occlusion image",
                                 i ? &rd->occlusion : &rd->occlusion_raw, error);
    if (r == CVK_SUCCESS)
        r = cvk_gpu_image_create(ctx, COLOR_FORMAT, w, h, VK_SAMPLE_COUNT_1_BIT,
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                 VK_IMAGE_ASPECT_COLOR_BIT, "image", &rd->image, error);
    if (r == CVK_SUCCESS)
        r = cvk_gpu_image_create(ctx, STENCIL_FORMAT, w, h, VK_SAMPLE_COUNT_1_BIT,
                                 VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                     VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT,
                                 VK_IMAGE_ASPECT_STENCIL_BIT, "stencil", &rd->stencil, error);
    return r;
}

static cvk_result create_framebuffer(cvk_renderer* rd, VkRenderPass pass, const VkImageView* views, uint32_t count,
                                     uint32_t width, uint32_t height, VkFramebuffer* out, const char* what,
                                     cvk_error* error)
{
    VkFramebufferCreateInfo fb = {
        .sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
        .renderPass = pass,
        .attachmentCount = count,
        .pAttachments = views,
        .width = width,
        .height = height,
        .layers = 1,
    };
    VkResult vr = vkCreateFramebuffer(rd->context->device, &fb, NULL, out);
    if (vr != VK_SUCCESS) {
        return cvk_fail_vk_for(error, "vkCreateFramebuffer", vr, "%s", what);
    }
    return CVK_SUCCESS;
}

/* An attachment first used in its pass (initial layout undefined), stencil unused. */
static VkAttachmentDescription attachment(VkFormat format, VkSampleCountFlagBits samples,
                                          VkAttachmentLoadOp load, VkAttachmentStoreOp store,
                                          VkImageLayout final_layout)
{
    return (VkAttachmentDescription){
        .format = format,
        .samples = samples,
        .loadOp = load,
        .storeOp = store,
        .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
        .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
        .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
        .finalLayout = final_layout,
    };
}

/* A pass of one subpass over one attachment, two external dependencies, and its framebuffer of
   width x height on `view`. */
static cvk_result create_single_pass(cvk_renderer* rd, const VkAttachmentDescription* description,
                                     const VkSubpassDescription* subpass,
                                     const VkSubpassDependency dependencies[2], VkImageView view,
                                     uint32_t width, uint32_t height, VkRenderPass* pass,
                                     VkFramebuffer* framebuffer, const char* what, cvk_error* error)
{
    VkRenderPassCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO,
        .attachmentCount = 1,
        .pAttachments = description,
        .subpassCount = 1,
        .pSubpasses = subpass,
        .dependencyCount = 2,
        .pDependencies = dependencies,
    };
    VkResult vr = vkCreateRenderPass(rd->context->device, &info, NULL, pass);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk_for(error, "vkCreateRenderPass", vr, "%s", what);
    return create_framebuffer(rd, *pass, &view, 1, width, height, framebuffer, what, error);
}

static cvk_result create_shadow_pass(cvk_renderer* rd, cvk_error* error)
{
    VkAttachmentDescription depth =
        attachment(SHADOW_FORMAT, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_CLEAR,
                   VK_ATTACHMENT_STORE_OP_STORE, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    VkAttachmentReference ref = {0, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass = {
        .pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
        .pDepthStencilAttachment = &ref,
    };
    VkPipelineStageFlags tests = VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    /* The lit pass samples it, in its fragment shaders and, lighting cloths at their vertices,
       in the cloth's vertex shader. */
    VkPipelineStageFlags readers = VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
    VkSubpassDependency dependencies[] = {
        /* The previous frame's lit pass has read the map before it is cleared again. */
        {VK_SUBPASS_EXTERNAL, 0, readers, tests, 0,
         VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, 0},
        {0, VK_SUBPASS_EXTERNAL, tests, readers, VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
         VK_ACCESS_SHADER_READ_BIT, 0},
    };
    return create_single_pass(rd, &depth, &subpass, dependencies, rd->shadow_map.view,
                              rd->desc.shadow_map_size, rd->desc.shadow_map_size, &rd->shadow_pass,
                              &rd->shadow_framebuffer, "shadow pass", error);
}


/* A pass of one subpass over a colour attachment (0) and a depth/stencil attachment (1), two
 * external dependencies, and its framebuffer on `views`. */
static cvk_result create_color_depth_pass(cvk_renderer* rd, const VkAttachmentDescription attachments[2],
                                          const VkSubpassDependency dependencies[2], const VkImageView views[2],
                                          VkRenderPass* pass, VkFramebuffer* framebuffer, const char* what,
                                          cvk_error* error)
{
    VkAttachmentReference color = {0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth = {1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass = {
        .pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
        .colorAttachmentCount = 1,
        .pColorAttachments = &color,
        .pDepthStencilAttachment = &depth,
    };
    VkRenderPassCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO,
        .attachmentCount = 2,
        .pAttachments = attachments,
        .subpassCount = 1,
        .pSubpasses = &subpass,
        .dependencyCount = 2,
        .pDependencies = dependencies,
    };
    VkResult vr = vkCreateRenderPass(rd->context->device, &info, NULL, pass);
    if (vr != VK_SUCCESS) {
        return cvk_fail_vk_for(error, "vkCreateRenderPass", vr, "%s", what);
    }
    return create_framebuffer(rd, *pass, views, 2, rd->desc.size[0], rd->desc.size[1], framebuffer, what, error);
}

/* Stages and accesses of a pass that writes colour and depth/stencil. */
#define PASS_OUTPUT_STAGES                                                                          \
    (VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |   \
     VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT)
#define PASS_WRITES (VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT)

/* The cloth, multisampled, over transparent black: the composite pass reads every sample. */
static cvk_result create_cloth_pass(cvk_renderer* rd, cvk_error* error)
{
    VkAttachmentDescription attachments[2] = {
        attachment(CLOTH_FORMAT, rd->samples, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE,
                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL),
        attachment(DEPTH_FORMAT, rd->samples, VK_ATTACHMENT_LOAD_OP_CLEAR,
                   rd->desc.ao ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE,
                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL),
    };
    VkPipelineStageFlags output = PASS_OUTPUT_STAGES;
    VkAccessFlags writes = PASS_WRITES;
    VkSubpassDependency dependencies[] = {
        /* The previous frame's writes, and its composite pass's reads of the cloth image. */
        {VK_SUBPASS_EXTERNAL, 0, output | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, output, writes,
         writes | VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT, 0},
        /* The occlusion and composite passes read the cloth image and its depths. */
        {0, VK_SUBPASS_EXTERNAL, output, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, writes, VK_ACCESS_SHADER_READ_BIT, 0},
    };
    VkImageView views[2] = {rd->cloth.view, rd->cloth_depth.view};
    return create_color_depth_pass(rd, attachments, dependencies, views, &rd->cloth_pass, &rd->cloth_framebuffer,
                                   "cloth pass", error);
}

/* Half resolution, one colour attachment, every texel drawn. */
static cvk_result create_occlusion_pass(cvk_renderer* rd, cvk_error* error)
{
    VkAttachmentDescription color =
        attachment(OCCLUSION_FORMAT, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_CLEAR,
                   VK_ATTACHMENT_STORE_OP_STORE, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    VkAttachmentReference ref = {0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass = {
        .pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
        .colorAttachmentCount = 1,
        .pColorAttachments = &ref,
    };
    VkSubpassDependency dependencies[] = {
        /* The previous reader (the blur, or the previous frame's composite pass) has read the
           image before it is drawn again. */
        {VK_SUBPASS_EXTERNAL, 0, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
         0, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, 0},
        /* The blur pass, then the composite pass, reads it. */
        {0, VK_SUBPASS_EXTERNAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
         VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT, 0},
    };
    /* The occlusion into its raw image, then the blur into the one the composite reads. */
    uint32_t w = cvk_render_half(rd->desc.size[0]), h = cvk_render_half(rd->desc.size[1]);
    cvk_result r = create_single_pass(rd, &color, &subpass, dependencies, rd->occlusion_raw.view, w, h,
                                      &rd->occlusion_pass, &rd->occlusion_framebuffer, "ambient occlusion pass", error);
    if (r != CVK_SUCCESS)
        return r;
    return create_single_pass(rd, &color, &subpass, dependencies, rd->occlusion.view, w, h, &rd->blur_pass,
                              &rd->blur_framebuffer, "ambient occlusion blur pass", error);
}

/* One sample per pixel: every pixel is drawn, so only the stencil is cleared. */
static cvk_result create_composite_pass(cvk_renderer* rd, cvk_error* error)
{
    VkAttachmentDescription attachments[2] = {
        attachment(COLOR_FORMAT, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                   VK_ATTACHMENT_STORE_OP_STORE, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL),
        attachment(STENCIL_FORMAT, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                   VK_ATTACHMENT_STORE_OP_DONT_CARE, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL),
    };
    attachments[1].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    VkPipelineStageFlags output = PASS_OUTPUT_STAGES;
    VkAccessFlags writes = PASS_WRITES;
    VkSubpassDependency dependencies[] = {
        /* The previous frame's copy out of the image, and its writes. */
        {VK_SUBPASS_EXTERNAL, 0, VK_PIPELINE_STAGE_TRANSFER_BIT | output, output, writes,
         writes | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT, 0},
        /* The image is copied out afterwards. */
        {0, VK_SUBPASS_EXTERNAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
         VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, 0},
    };
    VkImageView views[2] = {rd->image.view, rd->stencil.view};
    return create_color_depth_pass(rd, attachments, dependencies, views, &rd->composite_pass,
                                   &rd->composite_framebuffer, "composite pass", error);
}

/* ---- uniforms, descriptors ----------------------------------------------------------------- */

static void put3(float out[4], const double v[3], float w)
{
    out[0] = (float)v[0];
    out[1] = (float)v[1];
    out[2] = (float)v[2];
    out[3] = w;
}

static void put_color(float out[4], const float c[3])
{
    out[0] = c[0];
    out[1] = c[1];
    out[2] = c[2];
    out[3] = 1.0f;
}

/* The texture coordinates of the ground that plane collider `plane` is: its frame's x and z
   (cvk_render_plane_frame) in repeats, from its point. */
static void put_ground_texture(const cvk_collider_desc* plane, cvk_frame_uniforms* u)
{
    double axes[3][3];
    cvk_render_plane_frame(plane, axes[0], axes[1], axes[2]);
    double repeats = 1.0 / plane->texture_scale;
    for (int a = 0; a < 2; a++) {
        const double* axis = axes[2 * a];
        double offset = 0.0, scaled[3];
        for (int k = 0; k < 3; k++) {
            scaled[k] = axis[k] * repeats;
            offset -= (double)plane->point[k] * scaled[k];
        }
        put3(u->ground_texture[a], scaled, (float)offset);
    }
}

/* How far (m) the drawn cloth reaches beyond its vertices: half the thickest slab, and with
   render.smooth a curved triangle's bulge, under a third of its longest edge (a PN patch lies in
   the hull of control points set off the flat triangle by at most that); stretch is allowed
   for by taking half. */
static double drawn_reach(const cvk_renderer* rd)
{
    const cvk_build* b = &rd->mesh->sim->build;
    double reach = 0.0, edge = 0.0;
    for (uint32_t c = 0; c < b->cloth_count; c++)
        reach = fmax(reach, 0.5 * b->cloths[c].thickness);
    if (rd->desc.smooth > 1)
        for (uint32_t s = 0; s < b->spring_count; s++)
            if (b->springs[s].type != CVK_SPRING_BEND)
                edge = fmax(edge, b->springs[s].rest);
    return reach + 0.5 * edge;
}

static void fill_uniforms(const cvk_renderer* rd, cvk_frame_uniforms* u)
{
    const cvk_view* v = &rd->view;
    const cvk_render_desc* d = &rd->desc;
    memset(u, 0, sizeof *u);
    memcpy(u->view_proj, v->view_proj, sizeof u->view_proj);
    memcpy(u->light_view_proj, v->light_view_proj, sizeof u->light_view_proj);
    put3(u->eye, v->eye, 1.0f);
    put3(u->key_direction, v->key_direction, 0.0f);
    put_color(u->key_color, d->key.color);
    put3(u->fill_direction, v->fill_direction, 0.0f);
    put_color(u->fill_color, d->fill.color);
    put_color(u->ambient, d->ambient);
    put_color(u->background, d->background);
    put_color(u->ground_color, d->ground_color);
    put3(u->ground_plane, v->up, (float)v->ground_height);
    /* The ground's shading, as shaders/render/lighting.glsl computes it for a normal of up. */
    double key = fmax(0.0, v->key_direction[0] * v->up[0] + v->key_direction[1] * v->up[1] +
                               v->key_direction[2] * v->up[2]);
    double fill = fmax(0.0, v->fill_direction[0] * v->up[0] + v->fill_direction[1] * v->up[1] +
                                v->fill_direction[2] * v->up[2]);
    /* With sky light: the sky gives the ambient and a share of the background's colour from
       above; the ground sends up a share of what reaches it. */
    /* A ground with a texture (the plane collider it is has one): its light alone, which the
       composite pass multiplies by the texture's colour in place of ground_color. */
    uint32_t textured = rd->colliders.ground_texture;
    for (int k = 0; k < 3; k++) {
        double sky = d->ambient[k] + SKY_SHARE * d->background[k];
        double received = d->ambient[k] + fill * d->fill.color[k] + key * d->key.color[k];
        u->sky[k] = (float)sky;
        u->bounce[k] = (float)(BOUNCE_SHARE * d->ground_color[k] * received);
        double around = d->sky_light ? sky : d->ambient[k];
        double albedo = textured ? 1.0 : d->ground_color[k];
        u->ground_unlit[k] = (float)(albedo * (around + fill * d->fill.color[k]));
        u->ground_key[k] = (float)(albedo * key * d->key.color[k]);
    }
    if (textured)
        put_ground_texture(&rd->mesh->sim->collide->colliders[textured - 1], u);
    u->sky[3] = d->sky_light ? 1.0f : 0.0f;
    put3(u->ground_axes[0], v->ground_axes[0], 0.0f);
    put3(u->ground_axes[1], v->ground_axes[1], 0.0f);
    put3(u->ray_base, v->ray_base, 0.0f);
    put3(u->ray_dx, v->ray_dx, 0.0f);
    put3(u->ray_dy, v->ray_dy, 0.0f);
    u->fog[0] = (float)v->fog_start;
    u->fog[1] = (float)v->fog_end;
    u->fog[2] = d->ground ? 1.0f : 0.0f;
    u->fog[3] = (float)v->ground_tile;
    u->shadow[0] = (float)d->shadow_map_size;
    u->shadow[1] = (float)v->shadow_texel;
    /* Soft shadows: penumbra radius = distance to the blocker · tan(angle / 2), in texels; the
       search reaches the widest penumbra a blocker SOFT_REACH m away casts, within
       SOFT_MAX_TEXELS. */
    double spread = tan(0.5 * d->key_angle * 3.14159265358979 / 180.0) / v->shadow_texel;
    u->soft[0] = (float)spread;
    u->soft[1] = (float)fmin(fmax(spread * SOFT_REACH, 2.0), SOFT_MAX_TEXELS);
    u->soft[2] = (float)v->shadow_depth;
    u->soft[3] = d->soft_shadows && d->key_angle > 0.0f ? 1.0f : 0.0f;
    u->ao[0] = (float)(v->near * v->far);
    u->ao[1] = (float)(v->far - v->near);
    u->ao[2] = (float)v->near;
    double diagonal = 0.0;
    for (int k = 0; k < 3; k++)
        diagonal += (v->reach.hi[k] - v->reach.lo[k]) * (v->reach.hi[k] - v->reach.lo[k]);
    u->ao[3] = d->ao_radius > 0.0f ? d->ao_radius : (float)(AO_RADIUS_SHARE * sqrt(diagonal));
    u->ao_size[0] = (float)d->size[0];
    u->ao_size[1] = (float)d->size[1];
    u->ao_size[2] = (float)AO_STRENGTH;
    u->ao_size[3] = d->ao ? 1.0f : 0.0f;
    u->post[0] = d->tone_map ? 1.0f : 0.0f;
    u->post[1] = rd->drawn_reach;
}

void cvk_render_write_uniforms(cvk_renderer* rd)
{
    cvk_frame_uniforms u;
    fill_uniforms(rd, &u);
    memcpy(rd->uniforms.mapped, &u, sizeof u);
}

void cvk_renderer_set_time(cvk_renderer* rd, double seconds)
{
    if (!rd)
        return;
    rd->seconds = seconds;
    if (rd->eye_path.keyframe_count == 0)
        return;
    cvk_render_camera_resolve(rd, seconds);
    cvk_render_write_uniforms(rd);
}

/* The shadow map's two samplers (comparisons, raw depths) and the one for texel reads. */
static cvk_result create_samplers(cvk_renderer* rd, cvk_error* error)
{
    /* Outside the map (clamped to a border of depth 1) nothing casts a shadow. */
    VkSamplerCreateInfo sampler = {
        .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
        .magFilter = rd->shadow_filter,
        .minFilter = rd->shadow_filter,
        .mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST,
        .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
        .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
        .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
        .compareEnable = VK_TRUE,
        .compareOp = VK_COMPARE_OP_LESS_OR_EQUAL,
        .borderColor = VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE,
    };
    VkDevice dev = rd->context->device;
    VkResult vr = vkCreateSampler(dev, &sampler, NULL, &rd->shadow_sampler);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkCreateSampler", vr);
    /* The same map's raw depths, for the blocker search of the soft shadows. */
    sampler.compareEnable = VK_FALSE;
    sampler.magFilter = sampler.minFilter = VK_FILTER_NEAREST;
    vr = vkCreateSampler(dev, &sampler, NULL, &rd->shadow_depth_sampler);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkCreateSampler", vr);
    /* The cloth image is read with texelFetch: the sampler only has to exist. */
    VkSamplerCreateInfo texel = {
        .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
        .magFilter = VK_FILTER_NEAREST,
        .minFilter = VK_FILTER_NEAREST,
        .mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST,
        .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
        .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
        .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
    };
    vr = vkCreateSampler(dev, &texel, NULL, &rd->cloth_sampler);
    if (vr != VK_SUCCESS)
        return cvk_fail_vk(error, "vkCreateSampler", vr);
    return CVK_SUCCESS;
}

static cvk_result create_descriptors(cvk_renderer* rd, cvk_error* error)
{
    cvk_result r = cvk_buffer_create(rd->context, sizeof(cvk_frame_uniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                     CVK_MEMORY_HOST, "frame constants", &rd->uniforms, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_frame_uniforms u;
    fill_uniforms(rd, &u);
    memcpy(rd->uniforms.mapped, &u, sizeof u);

    r = create_samplers(rd, error);
    if (r != CVK_SUCCESS)
        return r;

    /* Binding 3: the cloth's texture, one set per cloth with a texture or a normal map (set 0:
       the white stand-in); 4: the shadow map's raw depths; 5: the cloth pass's depths; 6: the
       blurred ambient occlusion image; 7: the cloth's normal map (or the flat stand-in); 8: the
       occupied box (render_occupied.c); 9: the ambient occlusion image before the blur. The
       colliders' poses (binding 10) only where there are colliders to draw. */
    static const cvk_binding bindings[] = {
        {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
         VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT | VK_SHADER_STAGE_FRAGMENT_BIT},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_VERTEX_BIT},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_VERTEX_BIT},
    };
    uint32_t binding_count = rd->colliders.draw_count > 0 ? 11 : 10;
    r = cvk_descriptors_create(rd->context, bindings, binding_count, rd->textures.set_count,
                               CVK_RENDER_PUSH_STAGES, sizeof(cvk_render_material), &rd->descriptors, error);
    if (r != CVK_SUCCESS)
        return r;
    rd->pipeline_layout = rd->descriptors.pipeline_layout;
    rd->set = rd->descriptors.sets[0];
    for (uint32_t i = 0; i < rd->textures.set_count; i++) {
        const cvk_resource res[] = {
            {.buffer = &rd->uniforms},
            {.image = rd->shadow_map.view, .sampler = rd->shadow_sampler},
            {.image = rd->cloth.view, .sampler = rd->cloth_sampler},
            {.image = rd->textures.images[rd->textures.albedo_of_set[i]].view, .sampler = rd->textures.sampler},
            {.image = rd->shadow_map.view, .sampler = rd->shadow_depth_sampler},
            {.image = rd->cloth_depth.view, .sampler = rd->cloth_sampler},
            /* Without render.ao the composite pass never reads it: any image in the right
               layout will do (the white stand-in). */
            {.image = rd->desc.ao ? rd->occlusion.view : rd->textures.images[0].view, .sampler = rd->cloth_sampler},
            {.image = rd->textures.images[rd->textures.normal_of_set[i]].view, .sampler = rd->textures.sampler},
            {.buffer = &rd->occupied.box},
            {.image = rd->desc.ao ? rd->occlusion_raw.view : rd->textures.images[0].view, .sampler = rd->cloth_sampler},
            {.buffer = &rd->mesh->sim->collide->poses},
        };
        cvk_descriptors_write(rd->context, &rd->descriptors, i, res);
    }
    return CVK_SUCCESS;
}

/* ---- creation ------------------------------------------------------------------------------ */

static cvk_result create_frame_objects(cvk_renderer* rd, cvk_error* error)
{
    VkDeviceSize bytes = (VkDeviceSize)rd->desc.size[0] * rd->desc.size[1] * 4u;
    cvk_result r = cvk_buffer_create(rd->context, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, CVK_MEMORY_HOST,
                                     "image readback", &rd->readback, error);
    if (r == CVK_SUCCESS && rd->context->timestamp_valid_bits) {
        VkQueryPoolCreateInfo info = {
            .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
            .queryType = VK_QUERY_TYPE_TIMESTAMP,
            .queryCount = CVK_RENDER_QUERY_COUNT,
        };
        VkResult vr = vkCreateQueryPool(rd->context->device, &info, NULL, &rd->queries);
        if (vr != VK_SUCCESS)
            r = cvk_fail_vk(error, "vkCreateQueryPool", vr);
    }
    if (r == CVK_SUCCESS)
        r = cvk_submitter_create(rd->context, &rd->submitter, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_allocate(rd->context, &rd->submitter, &rd->frame_cmd, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_begin(rd->frame_cmd, VK_COMMAND_BUFFER_USAGE_SIMULTANEOUS_USE_BIT, error);
    if (r == CVK_SUCCESS)
        r = cvk_renderer_record(rd, rd->frame_cmd, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_end(rd->frame_cmd, error);
    return r;
}

static void gravity_of(const cvk_sim* sim, double out[3])
{
    cvk_ref_params ref = cvk_ref_params_of(&sim->params);
    for (int k = 0; k < 3; k++)
        out[k] = ref.gravity_h2[k];
}

cvk_result cvk_renderer_create(cvk_mesh* mesh, const cvk_render_desc* desc, cvk_renderer** out_renderer,
                               cvk_error* error)
{
    if (out_renderer)
        *out_renderer = NULL;
    if (!mesh || !desc || !out_renderer)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_renderer_create needs a mesh, a render description and an output pointer");
    if (desc->cookie_ != CVK_COOKIE_RENDER)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_renderer_create: the description "
                        "did not come from cvk_default_render_desc()");
    cvk_scene_issue issue;
    if (!cvk_render_desc_check(desc, &issue))
        return cvk_fail_issue(error, &issue);
    cvk_result r = check_device(mesh->context, desc, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_renderer* rd = calloc(1, sizeof *rd);
    if (!rd)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the renderer");
    rd->context = mesh->context;
    rd->mesh = mesh;
    rd->desc = *desc;
    rd->samples = (VkSampleCountFlagBits)desc->samples;
    VkFormatProperties shadow_props;
    vkGetPhysicalDeviceFormatProperties(mesh->context->physical_device, SHADOW_FORMAT, &shadow_props);
    rd->shadow_filter = (shadow_props.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT)
                            ? VK_FILTER_LINEAR
                            : VK_FILTER_NEAREST;
    gravity_of(mesh->sim, rd->gravity);
    r = cvk_render_camera_create(rd, desc, error);
    if (r == CVK_SUCCESS)
        r = cvk_render_colliders_create(rd, rd->gravity, error);
    if (r == CVK_SUCCESS && desc->fit)
        r = cvk_render_camera_fit_particles(rd, error);
    if (r == CVK_SUCCESS) {
        cvk_render_camera_resolve(rd, 0.0);
        rd->vertex_lit = cvk_render_vertex_lit(rd);
        rd->drawn_reach = (float)drawn_reach(rd);
        r = create_images(rd, error);
    }
    if (r == CVK_SUCCESS)
        r = cvk_render_textures_create(rd, error);
    if (r == CVK_SUCCESS)
        r = cvk_render_occupied_create(rd, error);
    if (r == CVK_SUCCESS)
        r = create_shadow_pass(rd, error);
    if (r == CVK_SUCCESS)
        r = create_cloth_pass(rd, error);
    if (r == CVK_SUCCESS)
        r = create_occlusion_pass(rd, error);
    if (r == CVK_SUCCESS)
        r = create_composite_pass(rd, error);
    if (r == CVK_SUCCESS)
        r = create_descriptors(rd, error);
    if (r == CVK_SUCCESS)
        r = cvk_renderer_create_pipelines(rd, error);
    if (r == CVK_SUCCESS)
        r = create_frame_objects(rd, error);
    /* Lavapipe compiles pipelines on first use: one frame now, so no timed frame pays. */
    if (r == CVK_SUCCESS)
        r = cvk_renderer_draw(rd, error);
    if (r != CVK_SUCCESS) {
        cvk_renderer_destroy(rd);
        return r;
    }
    *out_renderer = rd;
    return CVK_SUCCESS;
}

void cvk_renderer_destroy(cvk_renderer* rd)
{
    if (!rd)
        return;
    VkDevice dev = rd->context->device;
    if (rd->submitter.pool)
        cvk_queue_idle(rd->context);
    VkPipeline pipelines[] = {rd->shadow_pipeline,     rd->cloth_pipeline,           rd->background_pipeline,
                              rd->rect_pipeline,      rd->collider_shadow_pipeline, rd->collider_pipeline,
                              rd->footprint_pipeline,
                              rd->wireframe_pipeline,  rd->occlusion_pipeline,      rd->slab_pipelines[0],
                              rd->slab_pipelines[1],   rd->collider_closed_pipeline, rd->blur_pipeline};
    for (size_t i = 0; i < sizeof pipelines / sizeof pipelines[0]; i++)
        if (pipelines[i])
            vkDestroyPipeline(dev, pipelines[i], NULL);
    if (rd->queries)
        vkDestroyQueryPool(dev, rd->queries, NULL);
    cvk_descriptors_destroy(rd->context, &rd->descriptors);
    VkSampler samplers[] = {rd->shadow_sampler, rd->shadow_depth_sampler, rd->cloth_sampler};
    for (size_t i = 0; i < sizeof samplers / sizeof samplers[0]; i++)
        if (samplers[i])
            vkDestroySampler(dev, samplers[i], NULL);
    VkFramebuffer framebuffers[] = {rd->shadow_framebuffer, rd->cloth_framebuffer, rd->occlusion_framebuffer,
                                    rd->blur_framebuffer, rd->composite_framebuffer};
    for (size_t i = 0; i < sizeof framebuffers / sizeof framebuffers[0]; i++)
        if (framebuffers[i])
            vkDestroyFramebuffer(dev, framebuffers[i], NULL);
    VkRenderPass passes[] = {rd->shadow_pass, rd->cloth_pass, rd->occlusion_pass, rd->blur_pass, rd->composite_pass};
    for (size_t i = 0; i < sizeof passes / sizeof passes[0]; i++)
        if (passes[i])
            vkDestroyRenderPass(dev, passes[i], NULL);
    cvk_gpu_image* images[] = {&rd->shadow_map, &rd->cloth,  &rd->cloth_depth, &rd->occlusion,
                               &rd->occlusion_raw, &rd->image, &rd->stencil};
    for (size_t i = 0; i < sizeof images / sizeof images[0]; i++)
        cvk_gpu_image_destroy(rd->context, images[i]);
    cvk_buffer_destroy(rd->context, &rd->uniforms);
    cvk_buffer_destroy(rd->context, &rd->readback);
    cvk_render_colliders_destroy(rd);
    cvk_render_textures_destroy(rd);
    cvk_render_occupied_destroy(rd);
    cvk_submitter_destroy(rd->context, &rd->submitter);
    cvk_render_camera_destroy(rd);
    free(rd);
}
