#include "sim.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "error.h"
#include "metrics.h"
#include "scene.h"
#include "shaders.h"


#define DEFAULT_WORKGROUP_SIZE 64u
/* Measured on lavapipe (2 cores): beyond a few workgroups per dispatch the thread hand-offs
   cost more than they spread. */
#define CPU_DEVICE_MAX_WORKGROUPS 4u
#define MAX_FRAMES_PER_SUBMIT 256u

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

/* ---- limits, checked before anything large is allocated -------------------------------- */

/* The GPU adjacency packs a particle's springs four to a texel: per quad of slots one
 * rgba32ui texel of neighbours and one of the bits of their k (both in `adjacency`), and one
 * rgba32f texel of k·L (`adjacency_kl`). A sweep then gathers two texels for four springs
 * instead of four; on lavapipe a gather costs the same for one component as for four. */
static uint32_t adjacency_quads(uint32_t max_degree)
{
    return max_degree ? (max_degree + 3u) / 4u : 1u;
}

static uint32_t adjacency_texels_per_particle(uint32_t max_degree)
{
    return 2u * adjacency_quads(max_degree);
}

static uint32_t degree_bound(const cvk_scene_desc* scene)
{
    uint32_t bound = 0;
    for (uint32_t c = 0; c < scene->cloth_count; c++) {
        const cvk_stiffness* k = &scene->cloths[c].stiffness;
        uint32_t d = (k->structural > 0 ? 4u : 0u) + (k->shear > 0 ? 4u : 0u) +
                     (k->bend > 0 ? 4u : 0u);
        if (d > bound)
            bound = d;
    }
    return bound;
}

static cvk_result check_device_limits(const cvk_context* context, const cvk_scene_desc* scene,
                                      uint32_t workgroup_size, cvk_error* error)
{
    const VkPhysicalDeviceLimits* limits = &context->properties.limits;
    if (workgroup_size > limits->maxComputeWorkGroupSize[0] ||
        workgroup_size > limits->maxComputeWorkGroupInvocations)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "workgroup size %u exceeds the device's limit of %u", workgroup_size,
                        limits->maxComputeWorkGroupSize[0]);
    uint64_t total = 0;
    for (uint32_t c = 0; c < scene->cloth_count; c++)
        total += (uint64_t)scene->cloths[c].grid[0] * scene->cloths[c].grid[1];
    const char* where = scene->cloth_count == 1 ? "cloths.0.grid" : "cloths";
    uint64_t max_particles = cvk_context_max_particles(context);
    if (total > max_particles)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "%s: %llu particles are too many for %s, which holds at most %llu "
                        "(maxStorageBufferRange %u bytes, 16 bytes per particle)",
                        where, (unsigned long long)total, context->properties.deviceName,
                        (unsigned long long)max_particles, limits->maxStorageBufferRange);
    uint64_t texels = total * adjacency_texels_per_particle(degree_bound(scene));
    if (total > limits->maxTexelBufferElements || texels > limits->maxTexelBufferElements)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "%s: %llu particles with up to %u springs each need %llu adjacency "
                        "texels; %s allows %u texel buffer elements (maxTexelBufferElements)",
                        where, (unsigned long long)total, degree_bound(scene),
                        (unsigned long long)texels, context->properties.deviceName,
                        limits->maxTexelBufferElements);
    return CVK_SUCCESS;
}

/* ---- buffers ----------------------------------------------------------------------------- */

static cvk_result create_buffers(cvk_sim* s, cvk_error* error)
{
    cvk_context* ctx = s->context;
    const cvk_build* b = &s->build;
    VkDeviceSize n16 = (VkDeviceSize)b->particle_count * 16u;
    VkDeviceSize nf = b->free_count ? b->free_count : 1;
    VkDeviceSize quads = (VkDeviceSize)adjacency_quads(b->max_degree) * nf;
    VkBufferUsageFlags state = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                               VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    VkBufferUsageFlags positions = state | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                   VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
    VkBufferUsageFlags motion = state | VK_BUFFER_USAGE_TRANSFER_SRC_BIT; /* read for velocities */
    VkBufferUsageFlags table = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    struct {
        cvk_buffer* buffer;
        VkDeviceSize size;
        VkBufferUsageFlags usage;
        cvk_memory_kind kind;
        const char* what;
        VkBufferView* view;
        VkFormat format;
    } list[] = {
        {&s->positions, n16, positions, CVK_MEMORY_DEVICE, "positions", &s->view_positions,
         VK_FORMAT_R32G32B32A32_SFLOAT},
        {&s->u[0], n16, motion, CVK_MEMORY_DEVICE, "displacements", &s->view_u[0],
         VK_FORMAT_R32G32B32A32_SFLOAT},
        {&s->u[1], n16, state, CVK_MEMORY_DEVICE, "displacements (second iterate)", &s->view_u[1],
         VK_FORMAT_R32G32B32A32_SFLOAT},
        {&s->y, n16, state, CVK_MEMORY_DEVICE, "predicted displacements", &s->view_y,
         VK_FORMAT_R32G32B32A32_SFLOAT},
        {&s->rhs, nf * 16u, state, CVK_MEMORY_DEVICE, "right-hand side", &s->view_rhs,
         VK_FORMAT_R32G32B32A32_SFLOAT},
        {&s->adjacency, quads * 32u, table, CVK_MEMORY_DEVICE, "adjacency", &s->view_adjacency,
         VK_FORMAT_R32G32B32A32_UINT},
        {&s->adjacency_kl, quads * 16u, table, CVK_MEMORY_DEVICE, "adjacency k*L",
         &s->view_adjacency_kl, VK_FORMAT_R32G32B32A32_SFLOAT},
        {&s->spring_alive, (VkDeviceSize)b->spring_count * 4u, table, CVK_MEMORY_DEVICE, "spring flags",
         &s->view_spring_alive, VK_FORMAT_R32_UINT},
        {&s->staging, 2u * n16, VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
         CVK_MEMORY_HOST, "staging", NULL, VK_FORMAT_UNDEFINED},
    };
    for (size_t i = 0; i < sizeof list / sizeof list[0]; i++) {
        cvk_result r = cvk_buffer_create(ctx, list[i].size, list[i].usage, list[i].kind,
                                         list[i].what, list[i].buffer, error);
        if (r == CVK_SUCCESS && list[i].view)
            r = cvk_buffer_view_create(ctx, list[i].buffer, list[i].format, list[i].view, error);
        if (r != CVK_SUCCESS)
            return r;
    }
    return CVK_SUCCESS;
}

/* Copies one staging region into buffers; waits. Earlier GPU work on them finishes first. */
typedef struct copy_job {
    cvk_buffer* dst;
    VkDeviceSize src_offset, dst_offset, size;
} copy_job;

static cvk_result run_copies(cvk_sim* s, const copy_job* jobs, uint32_t count, bool reset_queries,
                             cvk_error* error)
{
    VkCommandBuffer cmd = s->transfer_cmd;
    cvk_result r = cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                    VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    for (uint32_t i = 0; i < count; i++) {
        VkBufferCopy region = {jobs[i].src_offset, jobs[i].dst_offset, jobs[i].size};
        vkCmdCopyBuffer(cmd, s->staging.buffer, jobs[i].dst->buffer, 1, &region);
    }
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                        VK_ACCESS_TRANSFER_READ_BIT);
    if (reset_queries && s->queries)
        vkCmdResetQueryPool(cmd, s->queries, 0, s->query_count);
    r = cvk_command_buffer_end(cmd, error);
    if (r != CVK_SUCCESS)
        return r;
    return cvk_submit_and_wait(s->context, &s->submitter, &cmd, 1, error);
}

/* Uploads a host array into a device buffer through the staging buffer, in chunks. */
static cvk_result upload(cvk_sim* s, cvk_buffer* dst, const void* data, VkDeviceSize size,
                         cvk_error* error)
{
    for (VkDeviceSize at = 0; at < size;) {
        VkDeviceSize chunk = size - at < s->staging.size ? size - at : s->staging.size;
        memcpy(s->staging.mapped, (const char*)data + at, chunk);
        copy_job job = {dst, 0, at, chunk};
        cvk_result r = run_copies(s, &job, 1, false, error);
        if (r != CVK_SUCCESS)
            return r;
        at += chunk;
    }
    return CVK_SUCCESS;
}

/* The adjacency as the GPU reads it (see adjacency_quads). */
static cvk_result upload_static(cvk_sim* s, cvk_error* error)
{
    const cvk_build* b = &s->build;
    if (b->spring_count > 0) {
        uint32_t* alive = malloc((size_t)b->spring_count * sizeof(uint32_t));
        if (!alive)
            return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the spring flags");
        for (uint32_t i = 0; i < b->spring_count; i++)
            alive[i] = 1;
        cvk_result r = upload(s, &s->spring_alive, alive, (size_t)b->spring_count * sizeof(uint32_t), error);
        free(alive);
        if (r != CVK_SUCCESS)
            return r;
    }
    size_t nf = b->free_count, quads = adjacency_quads(b->max_degree);
    if (nf == 0 || b->max_degree == 0)
        return CVK_SUCCESS;
    /* texel (2q) * nf + p: neighbours of slots 4q..4q+3, texel (2q + 1) * nf + p: bits of their
       k; k·L at texel q * nf + p. Slots past max_degree point at p itself with k = 0. */
    uint32_t* pairs = malloc(quads * nf * 8 * sizeof(uint32_t));
    float* kl = malloc(quads * nf * 4 * sizeof(float));
    cvk_result r = CVK_SUCCESS;
    if (!pairs || !kl)
        r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the adjacency");
    for (size_t q = 0; r == CVK_SUCCESS && q < quads; q++) {
        for (size_t p = 0; p < nf; p++) {
            uint32_t* neighbours = &pairs[4 * ((2 * q) * nf + p)];
            uint32_t* k_bits = &pairs[4 * ((2 * q + 1) * nf + p)];
            float* k_rest = &kl[4 * (q * nf + p)];
            for (size_t j = 0; j < 4; j++) {
                size_t slot = 4 * q + j, e = slot * nf + p;
                bool real = slot < b->max_degree;
                float k = real ? b->adj_k[e] : 0.0f;
                neighbours[j] = real ? b->adj_index[e] : (uint32_t)p;
                memcpy(&k_bits[j], &k, sizeof k);
                k_rest[j] = real ? k * b->adj_rest[e] : 0.0f;
            }
        }
    }
    if (r == CVK_SUCCESS)
        r = upload(s, &s->adjacency, pairs, quads * nf * 8 * sizeof(uint32_t), error);
    if (r == CVK_SUCCESS)
        r = upload(s, &s->adjacency_kl, kl, quads * nf * 4 * sizeof(float), error);
    free(pairs);
    free(kl);
    return r;
}

/* Sets positions `xyz` and last displacements `disp` (internal order, 3 floats each; disp NULL
   means at rest). At rest is zero velocity at this instant, so the first Verlet step moves a
   free particle by ½ h² g, as x(t) = x0 + ½ g t² requires: in displacement form a last
   displacement of −½ h² g. Pinned particles never move: their displacement is 0. */
static cvk_result set_state(cvk_sim* s, const float* xyz, const float* disp, bool reset_queries,
                            cvk_error* error)
{
    const cvk_build* b = &s->build;
    uint32_t n = b->particle_count;
    float* x = s->staging.mapped;
    float* u = x + 4 * (size_t)n;
    for (uint32_t p = 0; p < n; p++) {
        for (int c = 0; c < 3; c++) {
            size_t i = 3 * (size_t)p + c;
            double last = 0.0;
            if (p < b->free_count)
                last = disp ? (double)disp[i] : -0.5 * s->ref.gravity_h2[c];
            x[4 * p + c] = xyz[i];
            u[4 * p + c] = (float)last;
            if (s->host_solver) {
                s->hx[i] = xyz[i];
                s->hprev[i] = xyz[i] - last;
                s->hy[i] = xyz[i];
            }
        }
        x[4 * p + 3] = (float)(b->mass[p] * s->ref.inv_h2); /* m/h², read by predict */
        u[4 * p + 3] = 0.0f;
    }
    VkDeviceSize n16 = (VkDeviceSize)n * 16u;
    copy_job jobs[] = {
        {&s->positions, 0, 0, n16},
        {&s->u[0], n16, 0, n16},
        {&s->u[1], n16, 0, n16},
        {&s->y, n16, 0, n16},
    };
    return run_copies(s, jobs, 4, reset_queries, error);
}

/* Verlet's velocity at the end of a substep from its displacement u = x_n − x_{n−1}:
   v = u / h + h g / 2, so a particle at rest (u = −½ h² g) has v = 0. Pinned: 0. */
static void velocities_of(const cvk_sim* s, const float* u, float* v)
{
    double h = s->dt;
    const cvk_build* b = &s->build;
    for (uint32_t p = 0; p < b->particle_count; p++)
        for (int c = 0; c < 3; c++) {
            size_t i = 3 * (size_t)p + c;
            v[i] = p < b->free_count ? (float)(((double)u[i] + 0.5 * s->ref.gravity_h2[c]) / h)
                                     : 0.0f;
        }
}

/* The inverse of velocities_of: u = v h − ½ h² g. */
static void displacements_of(const cvk_sim* s, const float* v, float* u)
{
    double h = s->dt;
    const cvk_build* b = &s->build;
    for (uint32_t p = 0; p < b->particle_count; p++)
        for (int c = 0; c < 3; c++) {
            size_t i = 3 * (size_t)p + c;
            u[i] = p < b->free_count ? (float)((double)v[i] * h - 0.5 * s->ref.gravity_h2[c])
                                     : 0.0f;
        }
}

/* ---- pipelines and descriptors ----------------------------------------------------------- */

#define TEXEL {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 0}
#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
static const cvk_binding pd_bindings[CVK_PD_BINDING_COUNT] = {
    [CVK_PD_BINDING_SRC] = TEXEL,      [CVK_PD_BINDING_DST_READ] = TEXEL,
    [CVK_PD_BINDING_DST] = STORAGE,    [CVK_PD_BINDING_Y_READ] = TEXEL,
    [CVK_PD_BINDING_Y] = STORAGE,      [CVK_PD_BINDING_X_READ] = TEXEL,
    [CVK_PD_BINDING_X] = STORAGE,      [CVK_PD_BINDING_RHS_READ] = TEXEL,
    [CVK_PD_BINDING_RHS] = STORAGE,    [CVK_PD_BINDING_ADJACENCY] = TEXEL,
    [CVK_PD_BINDING_ADJACENCY_KL] = TEXEL,
};
#undef TEXEL
#undef STORAGE

/* Set `set` reads U[src] and writes U[dst]. */
static void write_set(cvk_sim* s, uint32_t set, uint32_t src, uint32_t dst)
{
    const cvk_resource res[CVK_PD_BINDING_COUNT] = {
        [CVK_PD_BINDING_SRC] = {.view = s->view_u[src]},
        [CVK_PD_BINDING_DST_READ] = {.view = s->view_u[dst]},
        [CVK_PD_BINDING_DST] = {.buffer = &s->u[dst]},
        [CVK_PD_BINDING_Y_READ] = {.view = s->view_y},
        [CVK_PD_BINDING_Y] = {.buffer = &s->y},
        [CVK_PD_BINDING_X_READ] = {.view = s->view_positions},
        [CVK_PD_BINDING_X] = {.buffer = &s->positions},
        [CVK_PD_BINDING_RHS_READ] = {.view = s->view_rhs},
        [CVK_PD_BINDING_RHS] = {.buffer = &s->rhs},
        [CVK_PD_BINDING_ADJACENCY] = {.view = s->view_adjacency},
        [CVK_PD_BINDING_ADJACENCY_KL] = {.view = s->view_adjacency_kl},
    };
    cvk_descriptors_write(s->context, &s->descriptors, set, res);
}

static cvk_result create_layouts(cvk_sim* s, cvk_error* error)
{
    cvk_result r = cvk_descriptors_create(s->context, pd_bindings, CVK_PD_BINDING_COUNT,
                                          CVK_SET_COUNT, VK_SHADER_STAGE_COMPUTE_BIT,
                                          sizeof(cvk_pd_push), &s->descriptors, error);
    if (r != CVK_SUCCESS)
        return r;
    s->pipeline_layout = s->descriptors.pipeline_layout;
    write_set(s, CVK_SET_U0_TO_U1, 0, 1);
    write_set(s, CVK_SET_U1_TO_U0, 1, 0);
    write_set(s, CVK_SET_U0_TO_U0, 0, 0);
    return CVK_SUCCESS;
}

/* Creates the pipelines `plan` uses that do not exist yet; *created tells whether any did. */
static cvk_result create_pipelines(cvk_sim* s, const cvk_plan* plan, bool* created,
                                   cvk_error* error)
{
    cvk_spec_inputs inputs = {plan->workgroup_size, s->build.max_degree};
    *created = false;
    for (int id = 0; id < CVK_PIPE_COUNT; id++) {
        if (!plan->uses[id] || s->pipelines.pipeline[id])
            continue;
        cvk_result r = cvk_pipelines_require(s->context, &s->pipelines, (cvk_pipeline_id)id,
                                             s->pipeline_layout, &inputs, error);
        if (r != CVK_SUCCESS)
            return r;
        *created = true;
    }
    return CVK_SUCCESS;
}

/* Lavapipe compiles a pipeline on its first dispatch (tens of ms with LLVM): dispatch each
   one once with no particles, so no timed frame pays for it. */
static cvk_result warm_up(cvk_sim* s, cvk_error* error)
{
    VkCommandBuffer cmd = s->transfer_cmd;
    cvk_result r = cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_pd_push nothing = {0};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, s->pipeline_layout, 0, 1,
                            &s->descriptors.sets[CVK_SET_U0_TO_U1], 0, NULL);
    for (int id = 0; id < CVK_PIPE_COUNT; id++) {
        if (!s->pipelines.pipeline[id])
            continue;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, s->pipelines.pipeline[id]);
        vkCmdPushConstants(cmd, s->pipeline_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof nothing,
                           &nothing);
        vkCmdDispatch(cmd, 1, 1, 1);
        cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    }
    r = cvk_command_buffer_end(cmd, error);
    if (r != CVK_SUCCESS)
        return r;
    return cvk_submit_and_wait(s->context, &s->submitter, &cmd, 1, error);
}

/* Timestamp queries for one frame of `plan`: one at the start and one after each run of
   dispatches of one pass. None for the host solver or when timing is off or unsupported. */
typedef struct query_set {
    VkQueryPool pool;
    uint32_t count;
    cvk_pass_id* pass; /* query q > 0 closes this pass */
} query_set;

static void destroy_queries(cvk_sim* s, query_set* q)
{
    if (q->pool)
        vkDestroyQueryPool(s->context->device, q->pool, NULL);
    free(q->pass);
    *q = (query_set){0};
}

static cvk_result create_queries(cvk_sim* s, const cvk_plan* plan, bool host, query_set* out,
                                 cvk_error* error)
{
    *out = (query_set){0};
    if (s->timing_request < 0 || s->context->timestamp_valid_bits == 0 || host)
        return CVK_SUCCESS;
    uint32_t runs = 0;
    for (uint32_t i = 0; i < plan->op_count; i++)
        if (i + 1 == plan->op_count || plan->ops[i + 1].pass != plan->ops[i].pass)
            runs++;
    out->count = 1 + runs * plan->substeps;
    out->pass = calloc(out->count, sizeof *out->pass);
    if (!out->pass)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for queries");
    uint32_t q = 1;
    for (uint32_t sub = 0; sub < plan->substeps; sub++)
        for (uint32_t i = 0; i < plan->op_count; i++)
            if (i + 1 == plan->op_count || plan->ops[i + 1].pass != plan->ops[i].pass)
                out->pass[q++] = plan->ops[i].pass;
    VkQueryPoolCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
        .queryType = VK_QUERY_TYPE_TIMESTAMP,
        .queryCount = out->count,
    };
    VkResult vr = vkCreateQueryPool(s->context->device, &info, NULL, &out->pool);
    if (vr != VK_SUCCESS) {
        out->pool = VK_NULL_HANDLE;
        destroy_queries(s, out);
        return cvk_fail_vk(error, "vkCreateQueryPool", vr);
    }
    return CVK_SUCCESS;
}

static void use_queries(cvk_sim* s, query_set* q)
{
    if (s->queries)
        vkDestroyQueryPool(s->context->device, s->queries, NULL);
    free(s->query_pass);
    s->queries = q->pool;
    s->query_count = q->count;
    s->query_pass = q->pass;
    s->timing = q->pool != VK_NULL_HANDLE;
    *q = (query_set){0};
}

/* ---- recording ----------------------------------------------------------------------------- */

/* One frame: an opening barrier (earlier compute and transfer writes), the plan's dispatches
   with barriers between them, and none after the last (the next frame opens with its own). */
static void record_frame(cvk_sim* s, VkCommandBuffer cmd)
{
    const cvk_plan* plan = &s->plan;
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                    VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    uint32_t query = 0;
    if (s->timing) {
        vkCmdResetQueryPool(cmd, s->queries, 0, s->query_count);
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, s->queries, query++);
    }
    VkPipeline bound = VK_NULL_HANDLE;
    int bound_set = -1;
    for (uint32_t sub = 0; sub < plan->substeps; sub++) {
        for (uint32_t i = 0; i < plan->op_count; i++) {
            const cvk_op* op = &plan->ops[i];
            if (s->pipelines.pipeline[op->pipeline] != bound) {
                bound = s->pipelines.pipeline[op->pipeline];
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, bound);
            }
            if ((int)op->set != bound_set) {
                bound_set = (int)op->set;
                vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, s->pipeline_layout,
                                        0, 1, &s->descriptors.sets[op->set], 0, NULL);
            }
            vkCmdPushConstants(cmd, s->pipeline_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                               sizeof op->push, &op->push);
            vkCmdDispatch(cmd, op->groups, 1, 1);
            bool pass_ends = i + 1 == plan->op_count || plan->ops[i + 1].pass != op->pass;
            if (s->timing && pass_ends)
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, s->queries,
                                    query++);
            bool last = sub + 1 == plan->substeps && i + 1 == plan->op_count;
            if (!last)
                cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
        }
    }
}

/* frame_cmd holds one frame of the plan; the host solver records nothing. */
static cvk_result record_frame_cmd(cvk_sim* s, cvk_error* error)
{
    if (s->host_solver) {
        VkResult vr = vkResetCommandBuffer(s->frame_cmd, 0);
        return vr == VK_SUCCESS ? CVK_SUCCESS : cvk_fail_vk(error, "vkResetCommandBuffer", vr);
    }
    cvk_result r = cvk_command_buffer_begin(s->frame_cmd, VK_COMMAND_BUFFER_USAGE_SIMULTANEOUS_USE_BIT, error);
    if (r != CVK_SUCCESS)
        return r;
    record_frame(s, s->frame_cmd);
    return cvk_command_buffer_end(s->frame_cmd, error);
}

/* readback_cmd copies positions and last displacements into the staging buffer. */
static cvk_result record_readback_cmd(cvk_sim* s, cvk_error* error)
{
    cvk_result r = cvk_command_buffer_begin(s->readback_cmd, 0, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_cmd_barrier(s->readback_cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                    VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    VkDeviceSize n16 = (VkDeviceSize)s->build.particle_count * 16u;
    VkBufferCopy positions = {0, 0, n16}, displacements = {0, n16, n16};
    vkCmdCopyBuffer(s->readback_cmd, s->positions.buffer, s->staging.buffer, 1, &positions);
    vkCmdCopyBuffer(s->readback_cmd, s->u[0].buffer, s->staging.buffer, 1, &displacements);
    cvk_cmd_barrier(s->readback_cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    return cvk_command_buffer_end(s->readback_cmd, error);
}

/* A plan for `solver` on this simulation's scene. Chebyshev's spectral radius is estimated
   once per omega: it depends only on the scene, h and omega, and costs a power iteration. */
static cvk_result make_plan(cvk_sim* s, const cvk_solver_desc* solver, uint32_t workgroup_size,
                            uint32_t max_groups, cvk_plan* out, cvk_error* error)
{
    cvk_scene_desc scene = s->params;
    scene.solver = *solver;
    double rho = -1.0;
    if (solver->linear == CVK_LINEAR_CHEBYSHEV && solver->chebyshev_rho <= 0.0f) {
        if (s->rho_estimate < 0.0 || s->rho_omega != solver->omega) {
            s->rho_estimate = cvk_estimate_jacobi_rho(&s->build, s->ref.inv_h2, solver->omega);
            s->rho_omega = solver->omega;
        }
        rho = s->rho_estimate;
    }
    return cvk_plan_create_with_rho(&scene, &s->build, workgroup_size, max_groups, rho, out,
                                    error);
}

/* ---- creation ------------------------------------------------------------------------------ */

static cvk_result create_gpu_objects(cvk_sim* s, cvk_error* error)
{
    cvk_result r = create_buffers(s, error);
    if (r == CVK_SUCCESS)
        r = cvk_submitter_create(s->context, &s->submitter, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_allocate(s->context, &s->submitter, &s->frame_cmd, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_allocate(s->context, &s->submitter, &s->readback_cmd, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_allocate(s->context, &s->submitter, &s->transfer_cmd, error);
    if (r == CVK_SUCCESS)
        r = create_layouts(s, error);
    bool created = false;
    if (r == CVK_SUCCESS)
        r = create_pipelines(s, &s->plan, &created, error);
    if (r == CVK_SUCCESS && created)
        r = warm_up(s, error);
    query_set queries;
    if (r == CVK_SUCCESS)
        r = create_queries(s, &s->plan, s->host_solver, &queries, error);
    if (r == CVK_SUCCESS)
        use_queries(s, &queries);
    if (r == CVK_SUCCESS)
        r = upload_static(s, error);
    if (r == CVK_SUCCESS)
        r = set_state(s, s->build.position, NULL, true, error);
    if (r == CVK_SUCCESS)
        r = record_frame_cmd(s, error);
    if (r == CVK_SUCCESS)
        r = record_readback_cmd(s, error);
    return r;
}

static cvk_result alloc_host_solver(cvk_sim* s, cvk_error* error);

static cvk_result alloc_host(cvk_sim* s, cvk_error* error)
{
    size_t n = s->build.particle_count;
    s->scratch = malloc(3 * n * sizeof(float));
    s->scratch_u = malloc(3 * n * sizeof(float));
    s->scratch_v = malloc(3 * n * sizeof(float));
    if (!s->scratch || !s->scratch_u || !s->scratch_v)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for positions");
    return s->host_solver ? alloc_host_solver(s, error) : CVK_SUCCESS;
}

/* The gs-cpu state; allocated once, also when a simulation switches to gs-cpu later. */
static cvk_result alloc_host_solver(cvk_sim* s, cvk_error* error)
{
    if (s->hx)
        return CVK_SUCCESS;
    size_t n = s->build.particle_count;
    s->hx = malloc(3 * n * sizeof(double));
    s->hprev = malloc(3 * n * sizeof(double));
    s->hy = malloc(3 * n * sizeof(double));
    s->hrhs = malloc(4 * n * sizeof(double));
    if (!s->hx || !s->hprev || !s->hy || !s->hrhs)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "out of host memory for the gs-cpu solver state");
    return CVK_SUCCESS;
}

cvk_result cvk_sim_create(cvk_context* context, const cvk_sim_desc* desc, cvk_sim** out_sim,
                          cvk_error* error)
{
    if (!context || !desc || !desc->scene || !out_sim)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_create needs a context, a description with a scene, and an "
                        "output pointer");
    *out_sim = NULL;
    const cvk_scene_desc* scene = desc->scene;
    cvk_result r = cvk_scene_desc_validate(scene, error);
    if (r != CVK_SUCCESS)
        return r;
    uint32_t workgroup_size = desc->workgroup_size ? desc->workgroup_size : DEFAULT_WORKGROUP_SIZE;
    uint32_t max_groups = desc->max_workgroups;
    if (max_groups == 0)
        max_groups = context->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU
                         ? CPU_DEVICE_MAX_WORKGROUPS
                         : UINT32_MAX;
    if (max_groups > context->properties.limits.maxComputeWorkGroupCount[0])
        max_groups = context->properties.limits.maxComputeWorkGroupCount[0];
    r = check_device_limits(context, scene, workgroup_size, error);
    if (r != CVK_SUCCESS)
        return r;

    cvk_sim* s = calloc(1, sizeof *s);
    if (!s)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the simulation");
    s->context = context;
    snprintf(s->name, sizeof s->name, "%s", scene->name ? scene->name : "scene");
    s->dt = scene->dt;
    s->solver = scene->solver;
    s->params = *scene;
    s->params.name = NULL;
    s->params.cloths = NULL;
    s->params.cloth_count = 0;
    s->timing_request = desc->timing;
    s->rho_estimate = -1.0;
    s->ref = cvk_ref_params_of(scene);
    s->host_solver = scene->solver.linear == CVK_LINEAR_GS_CPU;

    r = cvk_build_create(scene, &s->build, error);
    if (r == CVK_SUCCESS)
        r = make_plan(s, &scene->solver, workgroup_size, max_groups, &s->plan, error);
    if (r == CVK_SUCCESS)
        r = alloc_host(s, error);
    if (r == CVK_SUCCESS)
        r = create_gpu_objects(s, error);
    if (r != CVK_SUCCESS) {
        cvk_sim_destroy(s);
        return r;
    }
    *out_sim = s;
    return CVK_SUCCESS;
}

void cvk_sim_destroy(cvk_sim* s)
{
    if (!s)
        return;
    VkDevice dev = s->context->device;
    if (s->submitter.pool)
        vkQueueWaitIdle(s->context->queue);
    cvk_pipelines_destroy(s->context, &s->pipelines);
    if (s->queries)
        vkDestroyQueryPool(dev, s->queries, NULL);
    cvk_descriptors_destroy(s->context, &s->descriptors);
    cvk_submitter_destroy(s->context, &s->submitter);
    VkBufferView views[] = {s->view_positions, s->view_u[0], s->view_u[1], s->view_y,
                            s->view_rhs, s->view_adjacency, s->view_adjacency_kl,
                            s->view_spring_alive};
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++)
        if (views[i])
            vkDestroyBufferView(dev, views[i], NULL);
    cvk_buffer* buffers[] = {&s->positions, &s->u[0], &s->u[1], &s->y, &s->rhs, &s->adjacency,
                             &s->adjacency_kl, &s->spring_alive, &s->staging};
    for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; i++)
        cvk_buffer_destroy(s->context, buffers[i]);
    cvk_plan_destroy(&s->plan);
    cvk_build_destroy(&s->build);
    free(s->query_pass);
    free(s->batch);
    free(s->hx);
    free(s->hprev);
    free(s->hy);
    free(s->hrhs);
    free(s->scratch);
    free(s->scratch_u);
    free(s->scratch_v);
    free(s);
}

/* ---- running ------------------------------------------------------------------------------- */

cvk_result cvk_sim_record(cvk_sim* s, VkCommandBuffer cmd, uint32_t frames, cvk_error* error)
{
    if (!s || !cmd)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_record needs a simulation and a command buffer");
    if (s->host_solver)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "the gs-cpu solver runs on the host and cannot be recorded into a command "
                        "buffer; use cvk_sim_step");
    for (uint32_t f = 0; f < frames; f++)
        record_frame(s, cmd);
    return CVK_SUCCESS;
}

static cvk_result upload_host_positions(cvk_sim* s, cvk_error* error)
{
    float* x = s->staging.mapped;
    for (size_t p = 0; p < s->build.particle_count; p++) {
        for (int c = 0; c < 3; c++)
            x[4 * p + c] = (float)s->hx[3 * p + c];
        x[4 * p + 3] = 0.0f;
    }
    copy_job job = {&s->positions, 0, 0, (VkDeviceSize)s->build.particle_count * 16u};
    return run_copies(s, &job, 1, false, error);
}

static cvk_result step_host(cvk_sim* s, uint32_t frames, cvk_error* error)
{
    for (uint32_t f = 0; f < frames; f++) {
        double predict_ms = 0.0, solve_ms = 0.0;
        for (uint32_t sub = 0; sub < s->plan.substeps; sub++) {
            double t0 = now_ms();
            cvk_ref_predict(&s->build, &s->ref, s->hx, s->hprev, s->hy);
            double t1 = now_ms();
            cvk_ref_solve_gauss_seidel(&s->build, &s->ref, &s->solver, s->hy, s->hx, s->hrhs);
            predict_ms += t1 - t0;
            solve_ms += now_ms() - t1;
        }
        s->host_pass_ms[CVK_PASS_PREDICT] = predict_ms;
        s->host_pass_ms[CVK_PASS_SOLVE] = solve_ms;
        s->host_timed = true;
    }
    s->frames += frames;
    return upload_host_positions(s, error);
}

cvk_result cvk_sim_step(cvk_sim* s, uint32_t frames, cvk_error* error)
{
    if (!s)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_sim_step needs a simulation");
    if (frames == 0)
        return CVK_SUCCESS;
    if (s->host_solver)
        return step_host(s, frames, error);

    uint32_t per_submit = frames < MAX_FRAMES_PER_SUBMIT ? frames : MAX_FRAMES_PER_SUBMIT;
    if (s->batch_capacity < per_submit) {
        VkCommandBuffer* batch = realloc(s->batch, per_submit * sizeof *batch);
        if (!batch)
            return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for a submission");
        s->batch = batch;
        s->batch_capacity = per_submit;
    }
    for (uint32_t i = 0; i < per_submit; i++)
        s->batch[i] = s->frame_cmd;
    /* Only the last submission carries the fence: the queue runs them in order. */
    for (uint32_t done = 0; done < frames;) {
        uint32_t count = frames - done < per_submit ? frames - done : per_submit;
        if (done + count == frames) {
            cvk_result r = cvk_submit_and_wait(s->context, &s->submitter, s->batch, count, error);
            if (r != CVK_SUCCESS)
                return r;
        } else {
            VkSubmitInfo submit = {
                .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                .commandBufferCount = count,
                .pCommandBuffers = s->batch,
            };
            VkResult vr = vkQueueSubmit(s->context->queue, 1, &submit, VK_NULL_HANDLE);
            if (vr != VK_SUCCESS)
                return cvk_fail_vk(error, "vkQueueSubmit", vr);
        }
        done += count;
    }
    s->frames += frames;
    return CVK_SUCCESS;
}

uint64_t cvk_sim_particle_count(const cvk_sim* s)
{
    return s ? s->build.particle_count : 0;
}

cvk_result cvk_sim_read_internal(cvk_sim* s, cvk_error* error)
{
    size_t n = s->build.particle_count;
    if (s->host_solver) {
        for (size_t i = 0; i < 3 * n; i++) {
            s->scratch[i] = (float)s->hx[i];
            s->scratch_u[i] = (float)(s->hx[i] - s->hprev[i]);
        }
        return CVK_SUCCESS;
    }
    cvk_result r = cvk_submit_and_wait(s->context, &s->submitter, &s->readback_cmd, 1, error);
    if (r != CVK_SUCCESS)
        return r;
    const float* x = s->staging.mapped;
    const float* u = x + 4 * n;
    for (size_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++) {
            s->scratch[3 * p + c] = x[4 * p + c];
            s->scratch_u[3 * p + c] = u[4 * p + c];
        }
    return CVK_SUCCESS;
}

static cvk_result check_count(const cvk_sim* s, uint64_t count, const char* call, cvk_error* error)
{
    if (count != s->build.particle_count)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: the array holds %llu particles; the simulation has %u", call,
                        (unsigned long long)count, s->build.particle_count);
    return CVK_SUCCESS;
}

static cvk_result check_finite(const float* v, uint64_t count, const char* call, const char* what,
                               cvk_error* error)
{
    for (uint64_t i = 0; v && i < 3 * count; i++)
        if (!isfinite(v[i]))
            return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                            "%s: %s coordinate %llu of particle %llu is not a finite number", call,
                            what, (unsigned long long)(i % 3), (unsigned long long)(i / 3));
    return CVK_SUCCESS;
}

cvk_result cvk_sim_read_state(cvk_sim* s, float* xyz, float* velocity, uint64_t count,
                              cvk_error* error)
{
    if (!s || (!xyz && !velocity))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_read_state needs a simulation and a position or velocity array");
    cvk_result r = check_count(s, count, "cvk_sim_read_state", error);
    if (r == CVK_SUCCESS)
        r = cvk_sim_read_internal(s, error);
    if (r != CVK_SUCCESS)
        return r;
    if (velocity)
        velocities_of(s, s->scratch_u, s->scratch_v);
    for (uint32_t p = 0; p < s->build.particle_count; p++) {
        size_t user = 3 * (size_t)s->build.user_of[p];
        if (xyz)
            memcpy(&xyz[user], &s->scratch[3 * (size_t)p], 3 * sizeof(float));
        if (velocity)
            memcpy(&velocity[user], &s->scratch_v[3 * (size_t)p], 3 * sizeof(float));
    }
    return CVK_SUCCESS;
}

cvk_result cvk_sim_read_positions(cvk_sim* s, float* xyz, uint64_t count, cvk_error* error)
{
    if (!s || !xyz)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_read_positions needs a simulation and an array");
    return cvk_sim_read_state(s, xyz, NULL, count, error);
}

/* cvk_sim_write_state and cvk_sim_write_positions; `call` names the function in messages. */
static cvk_result write_state(cvk_sim* s, const float* xyz, const float* velocity, uint64_t count,
                              const char* call, cvk_error* error)
{
    if (!s || !xyz)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s needs a simulation and a position array", call);
    cvk_result r = check_count(s, count, call, error);
    if (r == CVK_SUCCESS)
        r = check_finite(xyz, count, call, "position", error);
    if (r == CVK_SUCCESS)
        r = check_finite(velocity, count, call, "velocity", error);
    if (r != CVK_SUCCESS)
        return r;
    for (uint32_t p = 0; p < s->build.particle_count; p++) {
        size_t user = 3 * (size_t)s->build.user_of[p];
        memcpy(&s->scratch[3 * (size_t)p], &xyz[user], 3 * sizeof(float));
        if (velocity)
            memcpy(&s->scratch_v[3 * (size_t)p], &velocity[user], 3 * sizeof(float));
    }
    if (velocity)
        displacements_of(s, s->scratch_v, s->scratch_u);
    return set_state(s, s->scratch, velocity ? s->scratch_u : NULL, false, error);
}

cvk_result cvk_sim_write_state(cvk_sim* s, const float* xyz, const float* velocity,
                               uint64_t count, cvk_error* error)
{
    return write_state(s, xyz, velocity, count, "cvk_sim_write_state", error);
}

cvk_result cvk_sim_write_positions(cvk_sim* s, const float* xyz, uint64_t count, cvk_error* error)
{
    return write_state(s, xyz, NULL, count, "cvk_sim_write_positions", error);
}

/* ---- changing the solver ------------------------------------------------------------------ */

cvk_result cvk_sim_set_solver(cvk_sim* s, const cvk_solver_desc* solver, cvk_error* error)
{
    if (!s || !solver)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_set_solver needs a simulation and a solver description");
    cvk_scene_issue issue;
    if (!cvk_solver_desc_check(solver, &issue))
        return cvk_fail_issue(error, &issue);
    bool host = solver->linear == CVK_LINEAR_GS_CPU;

    /* Everything that can fail on a valid description comes before the switch, so a failure
       leaves the old solver running; only added pipelines (harmless) stay behind. */
    cvk_plan plan;
    cvk_result r = make_plan(s, solver, s->plan.workgroup_size, s->plan.max_groups, &plan, error);
    if (r != CVK_SUCCESS)
        return r;
    query_set queries = {0};
    bool created = false;
    if (host)
        r = alloc_host_solver(s, error);
    else
        r = create_pipelines(s, &plan, &created, error);
    /* The state moves between host and device only when the solver does, or when warming up
       new pipelines runs them over the device buffers; otherwise it stays where it is. */
    bool move_state = host != s->host_solver || created;
    if (r == CVK_SUCCESS && move_state)
        r = cvk_sim_read_internal(s, error); /* the state, from whichever solver holds it */
    if (r == CVK_SUCCESS && created)
        r = warm_up(s, error);
    if (r == CVK_SUCCESS)
        r = create_queries(s, &plan, host, &queries, error);
    if (r != CVK_SUCCESS) {
        cvk_plan_destroy(&plan);
        return r;
    }

    cvk_plan_destroy(&s->plan);
    s->plan = plan;
    s->solver = *solver;
    s->host_solver = host;
    s->host_timed = false;
    use_queries(s, &queries);
    r = record_frame_cmd(s, error);
    if (r == CVK_SUCCESS && move_state)
        r = set_state(s, s->scratch, s->scratch_u, true, error);
    else if (r == CVK_SUCCESS && !host)
        r = run_copies(s, NULL, 0, true, error); /* resets the new queries */
    return r;
}

cvk_solver_desc cvk_sim_get_solver(const cvk_sim* s)
{
    return s ? s->solver : (cvk_solver_desc){0};
}

/* ---- statistics ---------------------------------------------------------------------------- */

static void read_gpu_times(const cvk_sim* s, cvk_sim_stats* st)
{
    st->gpu_ms_per_frame = -1.0;
    for (uint32_t p = 0; p < st->pass_count; p++)
        st->passes[p].gpu_ms = -1.0;
    if (s->host_solver) {
        if (!s->host_timed)
            return;
        st->gpu_ms_per_frame = 0.0;
        for (uint32_t p = 0; p < st->pass_count; p++) {
            st->passes[p].gpu_ms = s->host_pass_ms[p];
            st->gpu_ms_per_frame += s->host_pass_ms[p];
        }
        return;
    }
    if (!s->timing)
        return;
    uint64_t* data = calloc(2 * (size_t)s->query_count, sizeof(uint64_t));
    if (!data)
        return;
    VkResult vr = vkGetQueryPoolResults(s->context->device, s->queries, 0, s->query_count,
                                        2 * s->query_count * sizeof(uint64_t), data,
                                        2 * sizeof(uint64_t),
                                        VK_QUERY_RESULT_64_BIT |
                                            VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
    bool available = vr == VK_SUCCESS;
    for (uint32_t q = 0; q < s->query_count && available; q++)
        available = data[2 * q + 1] != 0;
    if (available) {
        uint32_t bits = s->context->timestamp_valid_bits;
        uint64_t mask = bits >= 64 ? UINT64_MAX : ((uint64_t)1 << bits) - 1;
        double period_ms = s->context->properties.limits.timestampPeriod * 1e-6;
        double per_pass[CVK_PASS_COUNT] = {0};
        for (uint32_t q = 1; q < s->query_count; q++)
            per_pass[s->query_pass[q]] += (double)((data[2 * q] - data[2 * (q - 1)]) & mask) * period_ms;
        st->gpu_ms_per_frame =
            (double)((data[2 * (s->query_count - 1)] - data[0]) & mask) * period_ms;
        for (uint32_t p = 0; p < st->pass_count; p++)
            st->passes[p].gpu_ms = per_pass[p];
    }
    free(data);
}

void cvk_sim_get_timing(const cvk_sim* s, cvk_sim_stats* st)
{
    memset(st, 0, sizeof *st);
    const cvk_build* b = &s->build;
    st->particles = b->particle_count;
    st->pinned = b->particle_count - b->free_count;
    for (int t = 0; t < 3; t++)
        st->springs[t] = b->springs_by_type[t];
    st->colours = b->colour_count;
    st->frames = s->frames;
    st->pass_count = CVK_PASS_COUNT;
    for (uint32_t p = 0; p < CVK_PASS_COUNT; p++) {
        st->passes[p].name = cvk_pass_name((cvk_pass_id)p);
        st->passes[p].dispatches = s->plan.pass_dispatches[p] * s->plan.substeps;
    }
    st->dispatches_per_substep = s->plan.op_count;
    st->dispatches_per_frame = s->plan.op_count * s->plan.substeps;
    read_gpu_times(s, st);
}

cvk_result cvk_sim_get_stats(cvk_sim* s, cvk_sim_stats* st, cvk_error* error)
{
    if (!s || !st)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_get_stats needs a simulation and an output struct");
    cvk_sim_get_timing(s, st);
    const cvk_build* b = &s->build;
    cvk_result r = cvk_sim_read_internal(s, error);
    if (r != CVK_SUCCESS)
        return r;
    velocities_of(s, s->scratch_u, s->scratch_v);
    cvk_metrics m;
    cvk_metrics_compute(b, s->scratch, s->scratch_v, s->params.integrate ? s->params.gravity : NULL,
                        &m);
    st->residual = m.residual[CVK_SPRING_STRUCTURAL];
    for (int t = 0; t < 3; t++)
        st->residual_per_type[t] = m.residual[t];
    st->residual_normalized = m.residual_normalized;
    st->max_stretch = m.max_stretch;
    st->nan_count = m.nan_count;
    st->kinetic_energy = m.kinetic;
    st->gravitational_energy = m.gravitational;
    st->elastic_energy = m.elastic;
    st->energy = m.kinetic + m.gravitational + m.elastic;
    return CVK_SUCCESS;
}

/* ---- the printed plan ---------------------------------------------------------------------- */

typedef struct text {
    char* at;
    size_t left;
    size_t needed;
} text;

static void put(text* t, const char* format, ...) __attribute__((format(printf, 2, 3)));
static void put(text* t, const char* format, ...)
{
    va_list args;
    va_start(args, format);
    int n = vsnprintf(t->at, t->left, format, args);
    va_end(args);
    if (n < 0)
        return;
    t->needed += (size_t)n;
    size_t used = (size_t)n < t->left ? (size_t)n : (t->left ? t->left - 1 : 0);
    t->at += used;
    t->left -= used;
}

size_t cvk_sim_describe_plan(const cvk_sim* s, char* out, size_t capacity)
{
    char dummy[1];
    text t = {capacity ? out : dummy, capacity ? capacity : 1, 0};
    const cvk_build* b = &s->build;
    const cvk_plan* plan = &s->plan;
    put(&t, "scene %s: %u particles (%u pinned), springs: %llu structural, %llu shear, %llu bend\n",
        s->name, b->particle_count, b->particle_count - b->free_count,
        (unsigned long long)b->springs_by_type[0], (unsigned long long)b->springs_by_type[1],
        (unsigned long long)b->springs_by_type[2]);
    put(&t, "colours: %u (%s), sizes", b->colour_count,
        b->colour_count == 2 ? "red-black" : "multi-colour");
    for (uint32_t c = 0; c < b->colour_count; c++)
        put(&t, " %u", b->colour_start[c + 1] - b->colour_start[c]);
    put(&t, "\nsolver: %s / %s, %u outer x %u inner, omega %g", cvk_method_name(s->solver.method),
        cvk_linear_solver_name(s->solver.linear), s->solver.outer_iterations,
        s->solver.inner_iterations, s->solver.omega);
    if (s->solver.linear == CVK_LINEAR_CHEBYSHEV)
        put(&t, ", rho %.6f (estimated %.6f, capped for stability), delay %u", plan->chebyshev_rho,
            plan->chebyshev_rho_estimated, s->solver.chebyshev_delay);
    put(&t, "\n");
    if (s->host_solver) {
        put(&t, "per frame: %u substeps on the host (sequential double-precision Gauss-Seidel, "
                "colour order), then one upload of the positions\n",
            plan->substeps);
        return t.needed;
    }
    put(&t, "per frame: %u substeps x %u dispatches = %u dispatches, workgroup size %u, at most "
            "%u workgroups per dispatch%s\n",
        plan->substeps, plan->op_count, plan->substeps * plan->op_count, plan->workgroup_size,
        plan->max_groups,
        s->timing ? ", timestamps per pass" : "");
    put(&t, "per substep:\n");
    for (uint32_t i = 0; i < plan->op_count; i++) {
        const cvk_op* op = &plan->ops[i];
        put(&t, "  %-7s %-26s", cvk_pass_name(op->pass), cvk_pipeline_label(op->pipeline));
        if (op->pass == CVK_PASS_SOLVE) {
            put(&t, " outer %u inner %u", op->outer + 1, op->inner + 1);
            if (op->pipeline == CVK_PIPE_GS_FIRST || op->pipeline == CVK_PIPE_GS)
                put(&t, " colour %u", op->colour);
            if (op->push.cheb != 1.0f)
                put(&t, " cheb %.4f", op->push.cheb);
            if (op->push.omega != s->solver.omega)
                put(&t, " omega %g", op->push.omega);
        }
        put(&t, "  particles %u..%u, %u groups, u%u -> u%u\n", op->push.first,
            op->push.first + op->push.count - 1, op->groups,
            op->set == CVK_SET_U1_TO_U0 ? 1 : 0, op->set == CVK_SET_U0_TO_U1 ? 1 : 0);
    }
    return t.needed;
}
