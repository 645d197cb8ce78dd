/* The cloths' and colliders' textures (cvk_cloth_desc.texture, cvk_collider_desc.texture):
   each file read with stb_image, its mip chain made on the host by averaging 2 x 2 texels in
   linear light, uploaded once into an R8G8B8A8_SRGB image (the sampler decodes sRGB to linear)
   together with the texture coordinates the cloth pass reads as its third vertex attribute (a
   collider has none: its fragment shader projects the texture, render_colliders.c); sampled
   trilinearly, and
   anisotropically on a GPU that allows it. Normal maps (material.normal_map) the same way into
   R8G8B8A8_UNORM images, their mips averaging the stored values. A 1 x 1 white texture and a
   1 x 1 flat normal stand in for the cloths without, so every descriptor set has both. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "render/render_internal.h"
#include "sim/sim.h"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO /* the file is read here, for its errno */
/* Static, so stb's unused functions are reported at the end of the file, past any pop. */
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#include <stb_image.h>
#pragma GCC diagnostic pop

#define TEXTURE_FORMAT VK_FORMAT_R8G8B8A8_SRGB
#define NORMAL_MAP_FORMAT VK_FORMAT_R8G8B8A8_UNORM

/* One decoded texture and its mip chain, level after level, 4 bytes per texel. */
typedef struct host_texture {
    uint8_t* texels;
    uint32_t width, height, levels;
    size_t bytes;
    bool normals;                /* a normal map: stored values, not sRGB */
} host_texture;

static double srgb_to_linear(double c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

static uint8_t linear_to_srgb(double c)
{
    double s = c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
    return (uint8_t)lround(fmin(fmax(s, 0.0), 1.0) * 255.0);
}

static uint32_t half(uint32_t n)
{
    return n > 1 ? n / 2 : 1;
}

/* Level l + 1 from level l: each texel the mean of the 2 x 2 texels above it (the last row or
   column repeated where the size is odd), colour in linear light, alpha as stored. */
static void downsample(const uint8_t* src, uint32_t w, uint32_t h, uint8_t* dst, const double* linear, bool normals)
{
    uint32_t dw = half(w), dh = half(h);
    for (uint32_t y = 0; y < dh; y++)
        for (uint32_t x = 0; x < dw; x++) {
            uint32_t xs[2] = {2 * x < w ? 2 * x : w - 1, 2 * x + 1 < w ? 2 * x + 1 : w - 1};
            uint32_t ys[2] = {2 * y < h ? 2 * y : h - 1, 2 * y + 1 < h ? 2 * y + 1 : h - 1};
            double sum[4] = {0, 0, 0, 0};
            for (int j = 0; j < 2; j++)
                for (int i = 0; i < 2; i++) {
                    const uint8_t* t = &src[4 * ((size_t)ys[j] * w + xs[i])];
                    for (int k = 0; k < 3; k++)
                        sum[k] += linear[t[k]];
                    sum[3] += t[3];
                }
            uint8_t* out = &dst[4 * ((size_t)y * dw + x)];
            for (int k = 0; k < 3; k++)
                out[k] = normals ? (uint8_t)lround(sum[k] / 4.0 * 255.0) : linear_to_srgb(sum[k] / 4.0);
            out[3] = (uint8_t)lround(sum[3] / 4.0);
        }
}

static bool make_mips(host_texture* t, const uint8_t* base)
{
    t->levels = 1;
    t->bytes = 4 * (size_t)t->width * t->height;
    for (uint32_t w = t->width, h = t->height; w > 1 || h > 1; w = half(w), h = half(h)) {
        t->levels++;
        t->bytes += 4 * (size_t)half(w) * half(h);
    }
    t->texels = malloc(t->bytes);
    if (!t->texels)
        return false;
    memcpy(t->texels, base, 4 * (size_t)t->width * t->height);
    double linear[256];
    for (int i = 0; i < 256; i++)
        linear[i] = t->normals ? i / 255.0 : srgb_to_linear(i / 255.0);
    uint8_t* level = t->texels;
    for (uint32_t w = t->width, h = t->height; w > 1 || h > 1; w = half(w), h = half(h)) {
        uint8_t* next = level + 4 * (size_t)w * h;
        downsample(level, w, h, next, linear, t->normals);
        level = next;
    }
    return true;
}

static cvk_result read_file(const char* key, const char* path, uint8_t** out, size_t* size, cvk_error* error)
{
    FILE* f = fopen(path, "rb");
    if (!f)
        return cvk_fail(error, CVK_ERROR_IO, "%s: %s: cannot open: %s", key, path, strerror(errno));
    uint8_t* data = NULL;
    size_t used = 0, capacity = 0;
    for (;;) {
        if (used == capacity) {
            size_t grown = capacity ? 2 * capacity : 65536;
            uint8_t* bigger = grown > (size_t)INT32_MAX ? NULL : realloc(data, grown);
            if (!bigger) {
                free(data);
                fclose(f);
                return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s: larger than 2 GiB, too large for an "
                                "image", key, path);
            }
            data = bigger;
            capacity = grown;
        }
        size_t n = fread(data + used, 1, capacity - used, f);
        used += n;
        if (n == 0)
            break;
    }
    int failed = ferror(f);
    int code = errno;
    fclose(f);
    if (failed) {
        free(data);
        return cvk_fail(error, CVK_ERROR_IO, "%s: %s: cannot read: %s", key, path, strerror(code));
    }
    *out = data;
    *size = used;
    return CVK_SUCCESS;
}

/* Reads a texture (or with t->normals a normal map) and makes its mips; the messages name the
   key path `key`. */
static cvk_result load_texture(const cvk_context* ctx, const char* key, const char* path, host_texture* t,
                               cvk_error* error)
{
    uint8_t* file = NULL;
    size_t size = 0;
    cvk_result r = read_file(key, path, &file, &size, error);
    if (r != CVK_SUCCESS)
        return r;
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_memory(file, (int)size, &w, &h, &channels)) {
        free(file);
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s: not an image stb_image can read (%s)", key,
                        path, stbi_failure_reason());
    }
    uint32_t max = cvk_context_max_image_size(ctx);
    if ((uint32_t)w > max || (uint32_t)h > max) {
        free(file);
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT, "%s: %s: %d x %d texels is more than %s allows (%u x %u)", key,
                        path, w, h, ctx->properties.deviceName, max, max);
    }
    uint8_t* base = stbi_load_from_memory(file, (int)size, &w, &h, &channels, 4);
    free(file);
    if (!base)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s: cannot decode it (%s)", key, path,
                        stbi_failure_reason());
    t->width = (uint32_t)w;
    t->height = (uint32_t)h;
    bool made = make_mips(t, base);
    stbi_image_free(base);
    return made ? CVK_SUCCESS
                : cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "%s: %s: out of host memory for %d x %d texels", key,
                           path, w, h);
}

/* Copies every level of every texture and the texture coordinates from `staging` (laid out
   in that order) and leaves the images ready to sample. */
static void record_upload(const cvk_render_textures* tx, const host_texture* host, const cvk_buffer* staging,
                          VkDeviceSize uv_bytes, VkCommandBuffer cmd)
{
    VkDeviceSize offset = 0;
    for (uint32_t i = 0; i < tx->count; i++) {
        const host_texture* t = &host[i];
        VkImageSubresourceRange all = {VK_IMAGE_ASPECT_COLOR_BIT, 0, t->levels, 0, 1};
        VkImageMemoryBarrier to_dst = {
            .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
            .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
            .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
            .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .image = tx->images[i].image,
            .subresourceRange = all,
        };
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0,
                             NULL, 1, &to_dst);
        uint32_t w = t->width, h = t->height;
        for (uint32_t l = 0; l < t->levels; l++, w = half(w), h = half(h)) {
            VkBufferImageCopy region = {
                .bufferOffset = offset,
                .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, l, 0, 1},
                .imageExtent = {w, h, 1},
            };
            vkCmdCopyBufferToImage(cmd, staging->buffer, tx->images[i].image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                   1, &region);
            offset += 4 * (VkDeviceSize)w * h;
        }
        VkImageMemoryBarrier to_read = to_dst;
        to_read.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        to_read.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
        to_read.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        to_read.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0, 0, NULL,
                             0, NULL, 1, &to_read);
    }
    if (uv_bytes) {
        VkBufferCopy copy = {offset, 0, uv_bytes};
        vkCmdCopyBuffer(cmd, staging->buffer, tx->uv.buffer, 1, &copy);
        cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT);
    }
}

static cvk_result upload(cvk_renderer* rd, const host_texture* host, cvk_error* error)
{
    cvk_context* ctx = rd->context;
    cvk_render_textures* tx = &rd->textures;
    const cvk_build* b = &rd->mesh->sim->build;
    /* The vertices', then the rim's (render/mesh.h): each rim vertex its edge end's. */
    const cvk_mesh* m = rd->mesh;
    VkDeviceSize vertex_uv_bytes = b->uv ? 2 * sizeof(float) * (VkDeviceSize)b->particle_count : 0;
    VkDeviceSize uv_bytes = b->uv ? vertex_uv_bytes + 8 * sizeof(float) * (VkDeviceSize)m->rim_edge_count : 0;
    VkDeviceSize bytes = uv_bytes;
    for (uint32_t i = 0; i < tx->count; i++)
        bytes += host[i].bytes;
    cvk_buffer staging = {0};
    cvk_submitter submitter = {0};
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    cvk_result r = cvk_buffer_create(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, CVK_MEMORY_HOST,
                                     "texture staging", &staging, error);
    if (r == CVK_SUCCESS && uv_bytes)
        r = cvk_buffer_create(ctx, uv_bytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              CVK_MEMORY_DEVICE, "texture coordinates", &tx->uv, error);
    if (r == CVK_SUCCESS) {
        uint8_t* at = staging.mapped;
        for (uint32_t i = 0; i < tx->count; i++) {
            memcpy(at, host[i].texels, host[i].bytes);
            at += host[i].bytes;
        }
        if (uv_bytes) {
            memcpy(at, b->uv, vertex_uv_bytes);
            float* rim = (float*)(at + vertex_uv_bytes);
            for (uint32_t k = 0; k < m->rim_edge_count; k++) {
                uint32_t ends[4] = {m->rim_ends[2 * k], m->rim_ends[2 * k + 1], m->rim_ends[2 * k + 1],
                                    m->rim_ends[2 * k]};
                for (int i = 0; i < 4; i++)
                    memcpy(&rim[2 * (4 * (size_t)k + i)], &b->uv[2 * (size_t)ends[i]], 2 * sizeof(float));
            }
        }
        r = cvk_submitter_create(ctx, &submitter, error);
    }
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_allocate(ctx, &submitter, &cmd, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, error);
    if (r == CVK_SUCCESS) {
        record_upload(tx, host, &staging, uv_bytes, cmd);
        r = cvk_command_buffer_end(cmd, error);
    }
    if (r == CVK_SUCCESS)
        r = cvk_submit_and_wait(ctx, &submitter, &cmd, 1, error);
    cvk_submitter_destroy(ctx, &submitter);
    cvk_buffer_destroy(ctx, &staging);
    return r;
}

static cvk_result create_sampler(cvk_renderer* rd, cvk_error* error)
{
    /* Trilinear, repeating (texture_scale above 1 tiles the texture), and anisotropic (up to
       8 samples along a cloth seen at a slant) where the device enabled the feature, except on
       a CPU device: lavapipe has it, but its lit pass took 6x as long with it on plaid.json's
       first frame (1.34-1.37 s against 0.21-0.22 s, alternating runs on a loaded machine). */
    const cvk_context* ctx = rd->context;
    bool anisotropic = ctx->sampler_anisotropy && ctx->properties.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU;
    VkSamplerCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
        .magFilter = VK_FILTER_LINEAR,
        .minFilter = VK_FILTER_LINEAR,
        .mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR,
        .addressModeU = VK_SAMPLER_ADDRESS_MODE_REPEAT,
        .addressModeV = VK_SAMPLER_ADDRESS_MODE_REPEAT,
        .addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT,
        .anisotropyEnable = anisotropic,
        .maxAnisotropy = anisotropic ? fminf(8.0f, ctx->properties.limits.maxSamplerAnisotropy) : 1.0f,
        .maxLod = VK_LOD_CLAMP_NONE,
    };
    VkResult vr = vkCreateSampler(rd->context->device, &info, NULL, &rd->textures.sampler);
    return vr == VK_SUCCESS ? CVK_SUCCESS : cvk_fail_vk(error, "vkCreateSampler (textures)", vr);
}

static void free_host(host_texture* host, uint32_t count)
{
    for (uint32_t i = 0; host && i < count; i++)
        free(host[i].texels);
    free(host);
}

/* The key path of cloth c's texture or normal map, as its messages name it. */
static const char* cloth_key(char key[64], uint32_t c, const cvk_cloth_range* cloth, bool normals)
{
    snprintf(key, 64, "cloths.%u.%s", c,
             normals ? "material.normal_map" : cloth->material_texture ? "material.texture" : "texture");
    return key;
}

/* The first collider before `i` with the same texture file as collider i (which shares its
   image and set), or i itself. */
static uint32_t first_with_texture(const cvk_collide* collide, uint32_t i)
{
    for (uint32_t j = 0; j < i; j++)
        if (collide->colliders[j].texture && strcmp(collide->colliders[j].texture, collide->colliders[i].texture) == 0)
            return j;
    return i;
}

/* Each collider texture file into host[first], host[first + 1], ... with a set of its own. */
static cvk_result load_collider_textures(cvk_renderer* rd, host_texture* host, uint32_t first, cvk_error* error)
{
    const cvk_collide* collide = rd->mesh->sim->collide;
    cvk_render_textures* tx = &rd->textures;
    cvk_result r = CVK_SUCCESS;
    for (uint32_t c = 0, i = first; r == CVK_SUCCESS && c < collide->collider_count; c++) {
        const char* texture = collide->colliders[c].texture;
        if (!texture)
            continue;
        uint32_t same = first_with_texture(collide, c);
        if (same != c) {
            tx->collider_set_of[c] = tx->collider_set_of[same];
            continue;
        }
        uint32_t set = tx->set_count++;
        tx->collider_set_of[c] = set;
        tx->albedo_of_set[set] = i;
        tx->normal_of_set[set] = 1;
        char key[64];
        snprintf(key, sizeof key, "colliders.%u.material.texture", c);
        r = load_texture(rd->context, key, texture, &host[i++], error);
    }
    return r;
}

cvk_result cvk_render_textures_create(cvk_renderer* rd, cvk_error* error)
{
    const cvk_build* b = &rd->mesh->sim->build;
    const cvk_collide* collide = rd->mesh->sim->collide;
    cvk_render_textures* tx = &rd->textures;
    /* Image 0 is the white stand-in, 1 the flat normal, then each texture and normal map. Set 0
       draws the cloths and colliders with neither; a cloth with either draws with a set of its
       own, and so does each collider texture file (colliders naming the same file share it). */
    uint32_t count = 2, sets = 1;
    for (uint32_t c = 0; c < b->cloth_count; c++) {
        count += (b->cloths[c].texture != NULL) + (b->cloths[c].normal_map != NULL);
        sets += b->cloths[c].texture || b->cloths[c].normal_map;
    }
    if (sets > CVK_MAX_SETS)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cloths: %u cloths have a texture or a normal map; the "
                        "renderer draws at most %d", sets - 1, CVK_MAX_SETS - 1);
    uint32_t cloth_sets = sets;
    for (uint32_t i = 0; i < collide->collider_count; i++) {
        if (!collide->colliders[i].texture || first_with_texture(collide, i) != i)
            continue;
        if (sets == CVK_MAX_SETS)
            return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "colliders.%u.material.texture: %u cloths with a "
                            "texture or a normal map and %u collider texture files before this one; the renderer "
                            "draws at most %d in all", i, cloth_sets - 1, sets - cloth_sets, CVK_MAX_SETS - 1);
        count++;
        sets++;
    }
    tx->set_of = calloc(b->cloth_count ? b->cloth_count : 1, sizeof *tx->set_of);
    tx->collider_set_of = calloc(collide->collider_count ? collide->collider_count : 1, sizeof *tx->collider_set_of);
    tx->images = calloc(count, sizeof *tx->images);
    host_texture* host = calloc(count, sizeof *host);
    if (!tx->set_of || !tx->collider_set_of || !tx->images || !host) {
        free(host);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the textures");
    }
    static const uint8_t white[4] = {255, 255, 255, 255}, flat[4] = {128, 128, 255, 255};
    host[0] = (host_texture){.width = 1, .height = 1};
    host[1] = (host_texture){.width = 1, .height = 1, .normals = true};
    cvk_result r = make_mips(&host[0], white) && make_mips(&host[1], flat)
                       ? CVK_SUCCESS
                       : cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory");
    tx->set_count = 1;
    char key[64];
    uint32_t i = 2;
    for (uint32_t c = 0; r == CVK_SUCCESS && c < b->cloth_count; c++) {
        const cvk_cloth_range* cloth = &b->cloths[c];
        if (!cloth->texture && !cloth->normal_map)
            continue;
        uint32_t set = tx->set_count++;
        tx->set_of[c] = set;
        tx->albedo_of_set[set] = 0;
        tx->normal_of_set[set] = 1;
        if (cloth->texture) {
            r = load_texture(rd->context, cloth_key(key, c, cloth, false), cloth->texture, &host[i], error);
            tx->albedo_of_set[set] = i++;
        }
        if (r == CVK_SUCCESS && cloth->normal_map) {
            host[i].normals = true;
            r = load_texture(rd->context, cloth_key(key, c, cloth, true), cloth->normal_map, &host[i], error);
            tx->normal_of_set[set] = i++;
        }
    }
    if (r == CVK_SUCCESS)
        r = load_collider_textures(rd, host, i, error);
    for (uint32_t i = 0; r == CVK_SUCCESS && i < count; i++) {
        r = cvk_gpu_image_create_mipped(rd->context, host[i].normals ? NORMAL_MAP_FORMAT : TEXTURE_FORMAT,
                                        host[i].width, host[i].height, host[i].levels, VK_SAMPLE_COUNT_1_BIT,
                                        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                        VK_IMAGE_ASPECT_COLOR_BIT, "texture", &tx->images[i], error);
        tx->count = r == CVK_SUCCESS ? i + 1 : i;
    }
    if (r == CVK_SUCCESS)
        r = upload(rd, host, error);
    if (r == CVK_SUCCESS)
        r = create_sampler(rd, error);
    free_host(host, count);
    return r;
}

void cvk_render_textures_destroy(cvk_renderer* rd)
{
    cvk_render_textures* tx = &rd->textures;
    if (tx->sampler)
        vkDestroySampler(rd->context->device, tx->sampler, NULL);
    for (uint32_t i = 0; tx->images && i < tx->count; i++)
        cvk_gpu_image_destroy(rd->context, &tx->images[i]);
    cvk_buffer_destroy(rd->context, &tx->uv);
    free(tx->images);
    free(tx->set_of);
    free(tx->collider_set_of);
    memset(tx, 0, sizeof *tx);
}
