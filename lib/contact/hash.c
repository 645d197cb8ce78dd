/* The uniform-grid spatial hash on the device (hash.h): buffers, the set, and the build as plan
   operations. The build is a counting sort by slot:

     clear     params (cell size, table size, count); with no points, starts := 0
     count     per point: keys[p] = slot, counts[slot]++ (atomic)
     scan      exclusive prefix sum of the counts into starts, in three dispatches: the sum of
               each chunk of slots (one invocation per chunk), a serial scan of the chunk sums
               (one invocation), then each chunk's own scan from its offset
     scatter   per point: entries[starts[slot] + --counts[slot]] = (p's point, p) (atomic),
               which leaves every count 0 for the next build (they are zeroed once, at
               creation); a slot's points in the order the atomics took them, which no reader
               depends on (hash.h). A sort of each slot by index, the build's last pass until
               2026-12-08, was a quarter or more of the build's time on lavapipe; without it
               the contact drape's and the pile's positions kept every bit
               (docs/performance.md).

   All are dispatches ordered by compute barriers; with no points only the clear is recorded.
   The number of operations never depends on the points, so the build needs no host round trip. The three-dispatch scan uses no shared memory and no
   workgroup barrier, which lavapipe makes expensive.

   lavapipe (gallivm) ends a shader's loops silently after 65535 iterations in all, counted over
   every loop of an invocation batch. Passes whose items loop over a slot (queries such as
   hash_neighbours.comp) therefore get at most the plan's walk_items items per
   invocation rather than its few strided workgroups; see cvk_plan_walk_groups. */
#include "contact/hash.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "shared/layout.h"

_Static_assert(sizeof(cvk_hash_params) == 32, "cvk_hash_params: 32 bytes in GLSL");
_Static_assert(sizeof(cvk_hash_params) == CVK_HASH_COMMANDS_OFFSET,
               "the build's commands follow the parameters");
_Static_assert(sizeof(cvk_hash_commands_push) == sizeof(cvk_hash_push),
               "the commands pass shares the build's push range");
_Static_assert(sizeof(cvk_hash_push) == 32, "cvk_hash_push: 32 bytes in GLSL");
_Static_assert(sizeof(cvk_hash_query_push) == 8, "cvk_hash_query_push: 8 bytes in GLSL");

#define MAX_CAPACITY (1u << 30) /* table_size = 2^31 slots at most: it must fit a uint */

#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
#define TEXEL {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, 0}
static const cvk_binding hash_bindings[CVK_HASH_BINDING_COUNT] = {
    [CVK_HASH_BINDING_PARAMS] = STORAGE,     [CVK_HASH_BINDING_POINTS] = TEXEL,
    [CVK_HASH_BINDING_KEYS] = STORAGE,       [CVK_HASH_BINDING_STARTS] = STORAGE,
    [CVK_HASH_BINDING_ENTRIES] = STORAGE,    [CVK_HASH_BINDING_SCRATCH] = STORAGE,
    [CVK_HASH_BINDING_STARTS_READ] = TEXEL,  [CVK_HASH_BINDING_ENTRIES_READ] = TEXEL,
    [CVK_HASH_BINDING_PARAMS_READ] = {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 0},
    [CVK_HASH_BINDING_SALTS] = TEXEL,      [CVK_HASH_BINDING_SCRATCH_READ] = TEXEL,
};
#undef STORAGE
#undef TEXEL

/* The smallest power of two ≥ 2 · capacity. */
static uint32_t table_size_for(uint32_t capacity)
{
    uint32_t size = 2;
    while (size < 2 * capacity)
        size *= 2;
    return size;
}

/* Slots per chunk of the scan: the power of two nearest sqrt(table_size) from above, so the
   chunks and the slots of a chunk are about as many (both serial loops stay short). */
static uint32_t chunk_for(uint32_t table_size)
{
    uint32_t bits = 0;
    while ((1u << bits) < table_size)
        bits++;
    return 1u << ((bits + 1) / 2);
}

static uint32_t chunk_count(const cvk_hash* hash)
{
    return hash->table_size / chunk_for(hash->table_size);
}

static cvk_result check_desc(const cvk_context* context, const cvk_hash_desc* desc,
                             cvk_error* error)
{
    if (desc->capacity < 1 || desc->capacity > MAX_CAPACITY)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "hash: capacity is %u points; it must be 1 to %u", desc->capacity,
                        MAX_CAPACITY);
    if (!(desc->cell_size > 0.0f) || !isfinite(desc->cell_size) ||
        !isfinite(1.0f / desc->cell_size))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "hash: cell size is %g m; it must be positive and finite with a finite "
                        "reciprocal", (double)desc->cell_size);
    if (!desc->points || desc->points->size < (VkDeviceSize)desc->capacity * 16)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "hash: the points buffer must hold a vec4 per point (%u points)",
                        desc->capacity);
    uint64_t slots = (uint64_t)table_size_for(desc->capacity) + 1;
    uint64_t limit = context->properties.limits.maxStorageBufferRange;
    uint64_t texels = context->properties.limits.maxTexelBufferElements;
    if (4 * slots > limit || slots > texels)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "hash: %u points need a table of %llu slots; the device's buffers hold at "
                        "most %llu (storage) and %llu (texel)", desc->capacity,
                        (unsigned long long)slots, (unsigned long long)limit / 4,
                        (unsigned long long)texels);
    return CVK_SUCCESS;
}

static cvk_result create_buffers(cvk_context* context, cvk_hash* hash, const cvk_buffer* points,
                                 const cvk_buffer* salts, cvk_error* error)
{
    VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                               VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    uint64_t slots = hash->table_size;
    struct {
        cvk_buffer* buffer;
        VkDeviceSize bytes;
        const char* what;
    } list[] = {
        /* the parameters, then a build's indirect commands (shaders/shared/layout.h) */
        {&hash->params, CVK_HASH_COMMANDS_OFFSET + 12 * CVK_HASH_BUILD_PASSES, "hash parameters"},
        {&hash->keys, 4 * (VkDeviceSize)hash->capacity, "hash keys"},
        {&hash->starts, 4 * (slots + 1), "hash slot starts"},
        {&hash->scratch, 4 * (slots + chunk_count(hash)), "hash scratch"},
        {&hash->entries, 16 * (VkDeviceSize)hash->capacity, "hash points by slot"},
        {&hash->zero_salt, 16, "hash zero salt"},
    };
    for (size_t i = 0; i < sizeof list / sizeof list[0]; i++) {
        VkBufferUsageFlags extra = list[i].buffer == &hash->params
                                       ? VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT : 0;
        cvk_result r = cvk_buffer_create(context, list[i].bytes, usage | extra, CVK_MEMORY_DEVICE,
                                         list[i].what, list[i].buffer, error);
        if (r != CVK_SUCCESS)
            return r;
    }
    cvk_result r = cvk_buffer_view_create(context, points, VK_FORMAT_R32G32B32A32_SFLOAT,
                                          &hash->points_view, error);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_view_create(context, &hash->starts, VK_FORMAT_R32_UINT,
                                   &hash->starts_view, error);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_view_create(context, &hash->entries, VK_FORMAT_R32G32B32A32_UINT,
                                   &hash->entries_view, error);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_view_create(context, salts ? salts : &hash->zero_salt, VK_FORMAT_R32_UINT,
                                   &hash->salts_view, error);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_view_create(context, &hash->scratch, VK_FORMAT_R32_UINT,
                                   &hash->scratch_view, error);
    return r;
}

static cvk_result create_set(cvk_context* context, cvk_hash* hash, cvk_error* error)
{
    cvk_descriptors d;
    cvk_result r = cvk_descriptors_create(context, hash_bindings, CVK_HASH_BINDING_COUNT, 1,
                                          VK_SHADER_STAGE_COMPUTE_BIT, sizeof(cvk_hash_push), &d,
                                          error);
    if (r != CVK_SUCCESS)
        return r;
    hash->set_layout = d.set_layout;
    hash->layout = d.pipeline_layout;
    hash->pool = d.pool;
    hash->set = d.sets[0];
    const cvk_resource res[CVK_HASH_BINDING_COUNT] = {
        [CVK_HASH_BINDING_PARAMS] = {.buffer = &hash->params},
        [CVK_HASH_BINDING_POINTS] = {.view = hash->points_view},
        [CVK_HASH_BINDING_KEYS] = {.buffer = &hash->keys},
        [CVK_HASH_BINDING_STARTS] = {.buffer = &hash->starts},
        [CVK_HASH_BINDING_ENTRIES] = {.buffer = &hash->entries},
        [CVK_HASH_BINDING_SCRATCH] = {.buffer = &hash->scratch},
        [CVK_HASH_BINDING_STARTS_READ] = {.view = hash->starts_view},
        [CVK_HASH_BINDING_ENTRIES_READ] = {.view = hash->entries_view},
        [CVK_HASH_BINDING_PARAMS_READ] = {.buffer = &hash->params},
        [CVK_HASH_BINDING_SALTS] = {.view = hash->salts_view},
        [CVK_HASH_BINDING_SCRATCH_READ] = {.view = hash->scratch_view},
    };
    cvk_descriptors_write(context, &d, 0, res);
    return CVK_SUCCESS;
}

/* Zeroes scratch once (from then on every build leaves the counts at 0, see the top) and opens
   the build (params.build = 1). */
static cvk_result zero_counts(cvk_context* context, cvk_hash* hash, cvk_error* error)
{
    cvk_submitter submitter;
    VkCommandBuffer cmd;
    cvk_result r = cvk_submitter_create(context, &submitter, error);
    if (r != CVK_SUCCESS)
        return r;
    r = cvk_command_buffer_allocate(context, &submitter, &cmd, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, error);
    if (r == CVK_SUCCESS) {
        vkCmdFillBuffer(cmd, hash->scratch.buffer, 0, VK_WHOLE_SIZE, 0);
        vkCmdFillBuffer(cmd, hash->zero_salt.buffer, 0, VK_WHOLE_SIZE, 0);
        cvk_hash_params params = {.cell_size = hash->cell_size,
                                  .inv_cell = 1.0f / hash->cell_size,
                                  .table_size = hash->table_size,
                                  .build = 1};
        vkCmdUpdateBuffer(cmd, hash->params.buffer, 0, sizeof params, &params);
        /* for whatever reads first (a frame opens with its own barrier, but not every user's) */
        cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
        r = cvk_command_buffer_end(cmd, error);
    }
    if (r == CVK_SUCCESS)
        r = cvk_submit_and_wait(context, &submitter, &cmd, 1, error);
    cvk_submitter_destroy(context, &submitter);
    return r;
}

cvk_result cvk_hash_create(cvk_context* context, const cvk_hash_desc* desc, cvk_hash* out,
                           cvk_error* error)
{
    memset(out, 0, sizeof *out);
    cvk_result r = check_desc(context, desc, error);
    if (r != CVK_SUCCESS)
        return r;
    out->capacity = desc->capacity;
    out->table_size = table_size_for(desc->capacity);
    out->cell_size = desc->cell_size;
    out->cell_on_device = desc->cell_on_device;
    r = create_buffers(context, out, desc->points, desc->salts, error);
    if (r == CVK_SUCCESS)
        r = zero_counts(context, out, error);
    if (r == CVK_SUCCESS)
        r = create_set(context, out, error);
    if (r != CVK_SUCCESS)
        cvk_hash_destroy(context, out);
    return r;
}

void cvk_hash_destroy(cvk_context* context, cvk_hash* hash)
{
    if (hash->pool)
        vkDestroyDescriptorPool(context->device, hash->pool, NULL);
    if (hash->points_view)
        vkDestroyBufferView(context->device, hash->points_view, NULL);
    if (hash->starts_view)
        vkDestroyBufferView(context->device, hash->starts_view, NULL);
    if (hash->entries_view)
        vkDestroyBufferView(context->device, hash->entries_view, NULL);
    if (hash->salts_view)
        vkDestroyBufferView(context->device, hash->salts_view, NULL);
    if (hash->scratch_view)
        vkDestroyBufferView(context->device, hash->scratch_view, NULL);
    cvk_buffer_destroy(context, &hash->params);
    cvk_buffer_destroy(context, &hash->keys);
    cvk_buffer_destroy(context, &hash->starts);
    cvk_buffer_destroy(context, &hash->entries);
    cvk_buffer_destroy(context, &hash->scratch);
    cvk_buffer_destroy(context, &hash->zero_salt);
    memset(hash, 0, sizeof *hash);
}

/* The push constants of a build of `count` points, or a failure where the hash holds fewer. */
cvk_result cvk_hash_build_push(const cvk_hash* hash, uint32_t count, cvk_hash_push* push,
                               cvk_error* error)
{
    if (count > hash->capacity)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "hash: %u points to hash; the hash was made for at most %u", count,
                        hash->capacity);
    uint32_t chunk = chunk_for(hash->table_size);
    *push = (cvk_hash_push){count, hash->table_size, chunk, hash->table_size / chunk,
                            hash->cell_on_device ? 0.0f : hash->cell_size,
                            hash->cell_on_device ? 0.0f : 1.0f / hash->cell_size, 0, 0};
    return CVK_SUCCESS;
}

cvk_result cvk_hash_add_passes(const cvk_hash* hash, cvk_plan* plan, uint32_t count,
                               bool on_device, cvk_error* error)
{
    cvk_hash_push push;
    cvk_result r = cvk_hash_build_push(hash, count, &push, error);
    if (r != CVK_SUCCESS)
        return r;
    uint32_t pass = cvk_plan_pass(plan, "hash");
    /* The build's passes, in the order of their commands (shaders/shared/layout.h). With
       points, one invocation of the clear writes the parameters; without, all zero the starts
       and nothing else runs. */
    struct {
        cvk_pipeline_id pipeline;
        cvk_domain domain;
        uint32_t items;
        const char* note;
    } passes[CVK_HASH_BUILD_PASSES] = {
        {CVK_PIPE_HASH_CLEAR, CVK_DOMAIN_CELLS, count ? 1 : hash->table_size,
         count ? "parameters" : "parameters, starts := 0 (no points)"},
        {CVK_PIPE_HASH_COUNT, CVK_DOMAIN_PARTICLES, count, "keys, counts per slot"},
        {CVK_PIPE_HASH_CHUNK_SUMS, CVK_DOMAIN_CELLS, push.chunks, "sums of chunks of slots"},
        {CVK_PIPE_HASH_SCAN_CHUNKS, CVK_DOMAIN_CELLS, 1, "scan of the chunk sums"},
        {CVK_PIPE_HASH_SCAN, CVK_DOMAIN_CELLS, push.chunks, "starts per slot"},
        {CVK_PIPE_HASH_SCATTER, CVK_DOMAIN_PARTICLES, count, "entries by slot"},
    };
    uint32_t recorded = count ? CVK_HASH_BUILD_PASSES : 1;
    uint32_t groups[CVK_HASH_BUILD_PASSES] = {0};
    for (uint32_t i = 0; i < recorded; i++)
        groups[i] = cvk_plan_groups_of(plan, passes[i].pipeline, passes[i].items);
    if (on_device) {
        cvk_hash_commands_push commands = {groups[0], groups[1], groups[2], groups[3],
                                           groups[4], groups[5], 0, 0};
        cvk_op* op = cvk_plan_dispatch(plan, pass, CVK_PIPE_HASH_COMMANDS, hash->layout,
                                       hash->set, CVK_DOMAIN_CELLS, 0, 1, &commands,
                                       sizeof commands);
        if (op) {
            op->groups = 1;
            op->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT;
            snprintf(op->note, sizeof op->note, "the passes' workgroups, none if not building");
        }
    }
    for (uint32_t i = 0; i < recorded; i++) {
        cvk_op* op;
        if (on_device) {
            op = cvk_plan_dispatch_indirect(plan, pass, passes[i].pipeline, hash->layout,
                                            hash->set, passes[i].domain, hash->params.buffer,
                                            CVK_HASH_COMMANDS_OFFSET + 12u * i, &push,
                                            sizeof push);
            if (op) {
                op->count = passes[i].items;
                /* the clear writes the parameters, whose buffer holds the commands the next
                   passes read */
                if (passes[i].pipeline == CVK_PIPE_HASH_CLEAR)
                    op->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT;
            }
        } else {
            op = cvk_plan_dispatch(plan, pass, passes[i].pipeline, hash->layout, hash->set,
                                   passes[i].domain, 0, passes[i].items, &push, sizeof push);
            if (op)
                op->groups = groups[i];
        }
        if (op)
            snprintf(op->note, sizeof op->note, "%s", passes[i].note);
    }
    return cvk_plan_check(plan, error);
}

/* As hash_cell in shaders/contact/hash_common.glsl: a correctly rounded product, floored, clamped. */
static int32_t cell_coordinate(float p, float inv_cell)
{
    float limit = (float)CVK_HASH_CELL_LIMIT;
    float c = floorf(p * inv_cell);
    c = fmaxf(c, -limit);
    c = fminf(c, limit);
    return (int32_t)c;
}

uint32_t cvk_hash_slot(const cvk_hash* hash, const float p[3])
{
    float inv_cell = 1.0f / hash->cell_size;
    uint32_t x = (uint32_t)cell_coordinate(p[0], inv_cell);
    uint32_t y = (uint32_t)cell_coordinate(p[1], inv_cell);
    uint32_t z = (uint32_t)cell_coordinate(p[2], inv_cell);
    uint32_t h = (x * 73856093u) ^ (y * 19349663u) ^ (z * 83492791u);
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    return h & (hash->table_size - 1u);
}
