/* Tearing on the device: the table of springs that may tear, the pass's descriptor set and op,
   and the spring flags' readback and snapshot part (lib/features/tear.h). */
#include "features/tear.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/checked.h"
#include "core/error.h"
#include "scene/scene.h"
#include "shared/layout.h"
#include "plan/state.h"
#include "plan/family.h"

#define TEXEL {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 0}
#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
static const cvk_binding tear_bindings[CVK_TEAR_BINDING_COUNT] = {
    [CVK_TEAR_BINDING_POSITIONS] = TEXEL, [CVK_TEAR_BINDING_TABLE] = TEXEL,
    [CVK_TEAR_BINDING_ALIVE] = STORAGE,   [CVK_TEAR_BINDING_ADJACENCY] = STORAGE,
};
#undef TEXEL
#undef STORAGE

/* The element index of adjacency entry e's (slot · nf + p) k bits in the uint array, as
   projective dynamics packs it (pd_common.glsl's quads). */
static uint32_t pd_k_element(uint32_t e, uint32_t nf)
{
    uint32_t p = e % nf, slot = e / nf, q = slot / 4, j = slot % 4;
    return 4 * ((2 * q + 1) * nf + p) + j;
}

/* The table: 8 uints per spring that may tear (shaders/shared/layout.h); and the host's
   arrays of them in t. */
static uint32_t* make_table(const cvk_build* b, const cvk_scene_desc* scene, cvk_tear* t,
                            uint32_t* count)
{
    size_t entries = (size_t)b->max_degree * b->free_count;
    uint32_t* table = cvk_malloc_array(8 * (size_t)b->spring_count, sizeof *table);
    /* slot[2s + e]: the slot of end e of spring s, or UINT32_MAX (pinned) */
    uint32_t* slot = cvk_malloc_array(2 * (size_t)b->spring_count, sizeof *slot);
    t->spring = cvk_malloc_array(b->spring_count ? b->spring_count : 1, sizeof *t->spring);
    t->limit2 = cvk_malloc_array(b->spring_count ? b->spring_count : 1, sizeof *t->limit2);
    t->entry = cvk_malloc_array(2 * (size_t)(b->spring_count ? b->spring_count : 1),
                                sizeof *t->entry);
    if (!table || !slot || !t->spring || !t->limit2 || !t->entry) {
        free(table);
        free(slot);
        return NULL;
    }
    for (size_t i = 0; i < 2 * (size_t)b->spring_count; i++)
        slot[i] = UINT32_MAX;
    for (size_t e = 0; e < entries; e++) {
        uint32_t s = b->adj_spring[e], p = (uint32_t)(e % b->free_count);
        if (s != UINT32_MAX)
            slot[2 * (size_t)s + (b->springs[s].a == p ? 0 : 1)] = (uint32_t)(e / b->free_count);
    }
    uint32_t n = 0;
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        float stretch = scene->cloths[cvk_build_cloth_of(b, sp->a)].tearing.max_stretch;
        if (!(stretch > 0.0f))
            continue;
        double length = (double)sp->rest * (1.0 + (double)stretch);
        float limit2 = (float)(length * length);
        t->spring[n] = s;
        t->limit2[n] = limit2;
        uint32_t* row = &table[8 * (size_t)n];
        row[0] = sp->a;
        row[1] = sp->b;
        row[2] = s;
        memcpy(&row[3], &limit2, sizeof limit2);
        uint32_t ends[2] = {sp->a, sp->b};
        for (int e = 0; e < 2; e++) {
            uint32_t at = slot[2 * (size_t)s + e];
            uint32_t entry = at == UINT32_MAX ? UINT32_MAX : at * b->free_count + ends[e];
            t->entry[2 * (size_t)n + e] = entry;
            row[4 + e] = row[6 + e] = CVK_TEAR_NONE;
            if (entry == UINT32_MAX)
                continue;
            row[4 + e] = pd_k_element(entry, b->free_count);
            row[6 + e] = 4 * entry + 1; /* (neighbour, bits of k, bits of L, 0) */
        }
        n++;
    }
    free(slot);
    *count = n;
    return table;
}

cvk_result cvk_tear_create(cvk_sim* s, const cvk_scene_desc* scene, cvk_error* error)
{
    cvk_tear* t = s->tear;
    *t = (cvk_tear){0};
    if (!cvk_scene_tears(scene))
        return CVK_SUCCESS;
    uint32_t count = 0;
    uint32_t* table = make_table(&s->build, scene, t, &count);
    if (!table)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the tearing table");
    cvk_result r = cvk_device_make_buffer(&s->device, &t->table, 32u * (VkDeviceSize)count, "tearing springs",
                                       table, error);
    free(table);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_view_create(s->device.context, &t->table, VK_FORMAT_R32G32B32A32_UINT,
                                   &t->view_table, error);
    if (r == CVK_SUCCESS)
        r = cvk_descriptors_create(s->device.context, tear_bindings, CVK_TEAR_BINDING_COUNT,
                                   CVK_TEAR_FAMILIES, VK_SHADER_STAGE_COMPUTE_BIT,
                                   sizeof(cvk_tear_push), &t->descriptors, error);
    if (r == CVK_SUCCESS)
        t->count = count;
    return r; /* on failure cvk_sim_destroy calls cvk_tear_destroy */
}

void cvk_tear_destroy(cvk_sim* s)
{
    cvk_tear* t = s->tear;
    cvk_descriptors_destroy(s->device.context, &t->descriptors);
    if (t->view_table)
        vkDestroyBufferView(s->device.context->device, t->view_table, NULL);
    cvk_buffer_destroy(s->device.context, &t->table);
    free(t->spring);
    free(t->limit2);
    free(t->entry);
    *t = (cvk_tear){0};
}

void cvk_tear_bind(cvk_sim* s, cvk_tear_family family, const cvk_buffer* adjacency)
{
    cvk_tear* t = s->tear;
    if (t->count == 0)
        return;
    const cvk_resource res[CVK_TEAR_BINDING_COUNT] = {
        [CVK_TEAR_BINDING_POSITIONS] = {.view = s->view_positions},
        [CVK_TEAR_BINDING_TABLE] = {.view = t->view_table},
        [CVK_TEAR_BINDING_ALIVE] = {.buffer = &s->spring_alive},
        [CVK_TEAR_BINDING_ADJACENCY] = {.buffer = adjacency},
    };
    cvk_descriptors_write(s->device.context, &t->descriptors, family, res);
    t->bound[family] = true;
}

cvk_result cvk_tear_add_passes(cvk_sim* s, cvk_tear_family family, cvk_plan* plan,
                               cvk_error* error)
{
    cvk_tear* t = s->tear;
    if (t->count == 0)
        return CVK_SUCCESS;
    if (!t->bound[family])
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "tearing: this solver does not tear springs");
    cvk_tear_push push = {t->count, family != CVK_TEAR_FOR_PD, 0, 0};
    uint32_t pass = cvk_plan_pass(plan, "tear");
    cvk_op* op = cvk_plan_dispatch(plan, pass, CVK_PIPE_TEAR, t->descriptors.pipeline_layout,
                                   t->descriptors.sets[family], CVK_DOMAIN_SPRINGS, 0, t->count,
                                   &push, sizeof push);
    if (op)
        snprintf(op->note, sizeof op->note, "%u springs of tearing cloths, final positions",
                 t->count);
    return cvk_plan_check(plan, error);
}

cvk_result cvk_tear_copy_flags(cvk_sim* s, uint32_t** out, cvk_error* error)
{
    *out = NULL;
    uint32_t* alive = cvk_malloc_array(s->build.spring_count ? s->build.spring_count : 1,
                                       sizeof *alive);
    if (!alive)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the spring flags");
    cvk_result r = cvk_tear_read_flags(s, alive, error);
    if (r != CVK_SUCCESS) {
        free(alive);
        return r;
    }
    *out = alive;
    return CVK_SUCCESS;
}

cvk_result cvk_tear_read_flags(cvk_sim* s, uint32_t* alive, cvk_error* error)
{
    VkDeviceSize bytes = (VkDeviceSize)s->build.spring_count * sizeof(uint32_t);
    if (bytes == 0)
        return CVK_SUCCESS;
    return cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd, &s->spring_alive,
                               alive, bytes, error);
}

uint32_t cvk_tear_host(const cvk_sim* s, const double* x, uint32_t* alive, float* adj_k)
{
    const cvk_tear* t = s->tear;
    uint32_t torn = 0;
    for (uint32_t i = 0; i < t->count; i++) {
        uint32_t spring = t->spring[i];
        if (!alive[spring])
            continue;
        const cvk_spring* sp = &s->build.springs[spring];
        const double* xa = &x[3 * (size_t)sp->a];
        const double* xb = &x[3 * (size_t)sp->b];
        double d[3] = {xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2]};
        if (!(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > (double)t->limit2[i]))
            continue;
        alive[spring] = 0;
        for (int e = 0; e < 2; e++)
            if (t->entry[2 * (size_t)i + e] != UINT32_MAX)
                adj_k[t->entry[2 * (size_t)i + e]] = 0.0f;
        torn++;
    }
    return torn;
}

bool cvk_tear_entry_torn(const cvk_build* b, const uint32_t* alive, size_t entry)
{
    uint32_t s = b->adj_spring[entry];
    return alive && s != UINT32_MAX && !alive[s];
}

void cvk_tear_host_adjacency(const cvk_build* b, const uint32_t* alive, float* adj_k)
{
    size_t entries = (size_t)b->max_degree * b->free_count;
    for (size_t e = 0; e < entries; e++)
        adj_k[e] = cvk_tear_entry_torn(b, alive, e) ? 0.0f : b->adj_k[e];
}

uint64_t cvk_tear_snapshot_size(const cvk_sim* s)
{
    return s->tear->count ? (uint64_t)s->build.spring_count * sizeof(uint32_t) : 0;
}

cvk_result cvk_tear_save_snapshot(cvk_sim* s, void* data, cvk_error* error)
{
    return s->tear->count ? cvk_tear_read_flags(s, data, error) : CVK_SUCCESS;
}

cvk_result cvk_tear_load_snapshot(cvk_sim* s, const void* data, cvk_error* error)
{
    if (s->tear->count == 0)
        return CVK_SUCCESS;
    size_t n = s->build.spring_count;
    uint32_t* alive = cvk_malloc_array(n, sizeof *alive);
    if (!alive)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the spring flags");
    memcpy(alive, data, n * sizeof *alive);
    for (size_t i = 0; i < n; i++)
        alive[i] = alive[i] != 0; /* a flag is 1 or 0, whatever the bytes said */
    cvk_result r = s->family->set_torn(s, s->family_state, alive, error);
    free(alive);
    return r;
}
