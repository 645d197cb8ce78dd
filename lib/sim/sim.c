/* The simulation object: creation and destruction, the buffers every solver family shares,
   the plan's recording and submission. Families (solver.h) own their solvers; state access
   and solver switches are in sim_state.c, statistics and the printed plan in sim_report.c. */
#include "sim/sim.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "contact/collide.h"
#include "core/checked.h"
#include "core/cookie.h"
#include "core/error.h"
#include "scene/scene.h"
#include "sim/sim_limits.h"
#include "solvers/reference.h"
#include "solvers/solve_pd.h"
#include "solvers/solver.h"

#define DEFAULT_WORKGROUP_SIZE 64u
/* Measured on lavapipe (2 cores): beyond a few workgroups per dispatch the thread hand-offs
   cost more than they spread. */
#define CPU_DEVICE_MAX_WORKGROUPS 4u
/* On a CPU device a workgroup runs as a loop over SIMD vectors of subgroupSize lanes, and the
   passes that stream over particles (the sweeps above all) ran fastest with workgroups of one
   vector: a 100 x 100 rbgs sweep on lavapipe (8 lanes, LP_NUM_THREADS=0) took 64-67 us with
   workgroups of 8 against 70-80 with 64 (README "Performance"). The contact and hash passes
   keep the workgroup size: with 8 the contact pass was slower. */
static uint32_t particle_workgroup_size(const cvk_context* context, const cvk_sim_desc* desc,
                                        uint32_t workgroup_size)
{
    if (desc->workgroup_size != 0 ||
        context->properties.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU)
        return workgroup_size;
    uint32_t lanes = context->subgroup_size;
    return lanes >= 4 && lanes <= workgroup_size ? lanes : workgroup_size;
}
/* On a CPU device, with the library's choice of workgroups per dispatch, each workgroup of the
   passes that stream over particles takes at least this many: llvmpipe runs a dispatch's
   workgroups one after another on a thread, and a workgroup whose invocations stride over the
   whole range leaves the next one to gather its neighbours again from farther caches.
   peer-hanging.json (10,000 particles) on one lavapipe thread (LP_NUM_THREADS=0): 4
   workgroups 21.4-22.1 CPU ms a frame, 1 workgroup 19.1-19.5, the same bits. Ranges past
   65,536 particles, where lavapipe's second thread starts to pay (docs/performance.md,
   Scaling), still get CPU_DEVICE_MAX_WORKGROUPS. */
#define CPU_DEVICE_PARTICLES_PER_WORKGROUP 16384u
/* Whether the library shapes the dispatches for a CPU device: one, and no workgroup count
   asked for. */
static bool cpu_device_shapes(const cvk_context* context, const cvk_sim_desc* desc)
{
    return desc->max_workgroups == 0 &&
           context->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
}
static uint32_t particle_group_items(const cvk_context* context, const cvk_sim_desc* desc)
{
    return cpu_device_shapes(context, desc) ? CPU_DEVICE_PARTICLES_PER_WORKGROUP : 0;
}
/* On a CPU device, with the library's choice of workgroups per dispatch, the passes whose items
   loop over hash slots or colliders (detection, the contact passes: cvk_plan_walk_groups) take
   this many items an invocation instead of one: llvmpipe pays for every workgroup and every
   SIMD batch it starts (the 40 x 40 contact drape's detection passes that only measure or list,
   0.7 ms a detection each with one edge an invocation, 0.2 with one workgroup for all). More
   would risk lavapipe's silent end of a shader's loops after 65,535 iterations, counted over
   all the items of an invocation: an item of detection loops at most 1,264 times in the
   six-cloth pile, 1,103 in the twist and 422 in the drape (measured with a test build over 120
   frames), so eight stay under 10,200, and a crowd of layers six times the pile's in one
   cell would be needed to reach the limit. */
#define CPU_DEVICE_WALK_ITEMS 8u
static uint32_t walk_items(const cvk_context* context, const cvk_sim_desc* desc)
{
    return cpu_device_shapes(context, desc) ? CPU_DEVICE_WALK_ITEMS : 1;
}
/* The fused sweeps (lib/solvers/solve_pd.h) run in one workgroup whose invocations stride over
   each colour: as large as the device allows, up to 1024 (a colour of a 10k-particle cloth in
   three passes), unless the caller chose a workgroup size, which they then take too. */
#define FUSED_WORKGROUP_MAX 1024u
static uint32_t fused_workgroup_size(const cvk_context* context, const cvk_sim_desc* desc,
                                     uint32_t workgroup_size)
{
    if (desc->workgroup_size != 0)
        return workgroup_size;
    const VkPhysicalDeviceLimits* limits = &context->properties.limits;
    uint32_t size = FUSED_WORKGROUP_MAX;
    if (size > limits->maxComputeWorkGroupSize[0])
        size = limits->maxComputeWorkGroupSize[0];
    if (size > limits->maxComputeWorkGroupInvocations)
        size = limits->maxComputeWorkGroupInvocations;
    return size;
}
/* The fused sweeps take a workgroup a copy of a scene's instances (lib/solvers/solve_pd.h)
   unless cloths collide: contact between cloths detects over the whole scene, in one
   workgroup. Each such workgroup is as large as a copy's largest colour in whole 64s, not the
   1024 one workgroup for the whole scene takes: a 32 x 32 napkin's colour of 256 then fills it,
   and more copies share a multiprocessor. Unless the caller chose a workgroup size. */
#define FUSED_COPY_WORKGROUP_STEP 64u
/* And each keeps its copy's iterate in shared memory (shaders/solvers/pd_fused.comp,
   SHARED_SLOTS) where a copy's free particles fit the device's shared memory at 16 bytes each:
   on a GPU a barrier on shared memory and a read of it cost a fraction of a round trip to
   coherent global memory, which each colour of each sweep makes otherwise. Not on a CPU device
   unless the caller asks (cvk_sim_desc.fused_shared_memory 1): llvmpipe ran 64 fused 32 x 32
   napkins at 1,904 ms a frame with it against 1,731 without (docs/performance.md). */
static void fuse_copies(cvk_sim* s, const cvk_sim_desc* desc)
{
    s->fused_copies = desc->scene->collision.self
                          ? 1
                          : cvk_pd_fused_copies(&s->build, s->instance_count);
    uint32_t copies = s->fused_copies;
    uint64_t slots = s->build.free_count / copies;
    uint64_t room = s->device.context->properties.limits.maxComputeSharedMemorySize / 16u;
    bool cpu = s->device.context->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    bool wanted = desc->fused_shared_memory > 0 || (desc->fused_shared_memory == 0 && !cpu);
    s->fused_shared_slots = wanted && slots <= room ? (uint32_t)slots : 0;
    if (desc->workgroup_size != 0 || copies <= 1)
        return;
    uint32_t largest = 0;
    for (uint32_t c = 0; c < s->build.colour_count; c++) {
        uint32_t n = (s->build.colour_start[c + 1] - s->build.colour_start[c]) / copies;
        largest = n > largest ? n : largest;
    }
    uint32_t size = (largest + FUSED_COPY_WORKGROUP_STEP - 1) / FUSED_COPY_WORKGROUP_STEP *
                    FUSED_COPY_WORKGROUP_STEP;
    if (size < FUSED_COPY_WORKGROUP_STEP)
        size = FUSED_COPY_WORKGROUP_STEP;
    if (size < s->fused_workgroup_size)
        s->fused_workgroup_size = size;
}
#define MAX_FRAMES_PER_SUBMIT 256u

/* ---- shared buffers and uploads ------------------------------------------------------ */

static cvk_result create_buffers(cvk_sim* s, cvk_error* error)
{
    cvk_context* ctx = s->device.context;
    const cvk_build* b = &s->build;
    VkDeviceSize n16 = (VkDeviceSize)b->particle_count * 16u;
    VkBufferUsageFlags positions = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                   VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                                   VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                   VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
    /* Spring flags: written by tearing, read back by cvk_sim_read_mesh to leave torn
       triangles out. */
    VkBufferUsageFlags table = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    cvk_result r = cvk_buffer_create(ctx, n16, positions, CVK_MEMORY_DEVICE, "positions",
                                     &s->positions, error);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_view_create(ctx, &s->positions, VK_FORMAT_R32G32B32A32_SFLOAT,
                                   &s->view_positions, error);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_create(ctx, (VkDeviceSize)b->spring_count * 4u, table, CVK_MEMORY_DEVICE,
                              "spring flags", &s->spring_alive, error);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_view_create(ctx, &s->spring_alive, VK_FORMAT_R32_UINT,
                                   &s->view_spring_alive, error);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_create(ctx, 2u * n16,
                              VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              CVK_MEMORY_HOST, "staging", &s->device.staging, error);
    if (r == CVK_SUCCESS)
        r = cvk_sim_watch_create(s, error);
    return r;
}

static cvk_result upload_spring_flags(cvk_sim* s, cvk_error* error)
{
    const cvk_build* b = &s->build;
    if (b->spring_count == 0)
        return CVK_SUCCESS;
    uint32_t* alive = cvk_malloc_array(b->spring_count, sizeof(uint32_t));
    if (!alive)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the spring flags");
    for (uint32_t i = 0; i < b->spring_count; i++)
        alive[i] = 1;
    cvk_result r = cvk_device_upload(&s->device, &s->spring_alive, alive,
                                  (size_t)b->spring_count * sizeof(uint32_t), error);
    free(alive);
    return r;
}

/* ---- the plan, its pipelines, its timing, its recording ------------------------------- */

/* A plan for `solver` by `family` (whose state is `self`) on this simulation's scene. */
cvk_result cvk_sim_make_plan(cvk_sim* s, const cvk_family_api* family, void* self,
                             const cvk_solver_desc* solver, uint32_t workgroup_size,
                             uint32_t max_groups, cvk_plan* out, cvk_error* error)
{
    cvk_plan_init(out, s->params.substeps, workgroup_size, max_groups);
    out->particle_workgroup_size = s->particle_workgroup_size;
    out->fused_workgroup_size = s->fused_workgroup_size;
    out->particle_group_items = s->particle_group_items;
    out->walk_items = s->walk_items;
    out->fused = family->fuse_refusal && family->fuse_refusal(s, solver) == NULL;
    cvk_result r = cvk_collide_add_passes(s, out, error);
    if (r == CVK_SUCCESS)
        r = family->add_passes(s, self, solver, out, error);
    if (r == CVK_SUCCESS)
        r = cvk_plan_check(out, error);
    if (r != CVK_SUCCESS)
        cvk_plan_destroy(out);
    return r;
}

/* Creates the pipelines `plan` uses and dispatches the new ones once. */
cvk_result cvk_sim_ready_pipelines(cvk_sim* s, const cvk_plan* plan, cvk_error* error)
{
    cvk_spec_inputs inputs = {.workgroup_size = plan->workgroup_size,
                              .particle_workgroup_size = plan->particle_workgroup_size,
                              .fused_workgroup_size = plan->fused_workgroup_size,
                              .fused_shared_slots = s->fused_shared_slots,
                              .fused_one_copy = s->fused_copies <= 1,
                              .max_degree = s->build.max_degree,
                              .collider_types = s->collide->types,
                              .self_contact = s->collide->self,
                              .wind = s->aero->enabled,
                              .tethers = s->build.tether_anchor != NULL,
                              .tether_slots = s->build.tether_slots,
                              .rest = cvk_ref_params_of(&s->params).rest_rate > 0.0};
    bool created = false;
    cvk_result r = cvk_plan_require_pipelines(plan, s->device.context, &s->pipelines, &inputs, &created,
                                              error);
    if (r != CVK_SUCCESS || !created)
        return r;
    VkCommandBuffer cmd = s->device.transfer_cmd;
    r = cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_plan_record_warm_up(plan, &s->pipelines, cmd);
    r = cvk_command_buffer_end(cmd, error);
    if (r != CVK_SUCCESS)
        return r;
    return cvk_submit_and_wait(s->device.context, &s->device.submitter, &cmd, 1, error);
}

void cvk_sim_destroy_queries(cvk_sim* s, cvk_sim_queries* q)
{
    if (q->pool)
        vkDestroyQueryPool(s->device.context->device, q->pool, NULL);
    free(q->pass);
    *q = (cvk_sim_queries){0};
}

/* Timestamp queries for one frame of `plan`; none for host plans or when timing is off or
   unsupported. */
cvk_result cvk_sim_create_queries(cvk_sim* s, const cvk_plan* plan, cvk_sim_queries* out,
                                  cvk_error* error)
{
    *out = (cvk_sim_queries){0};
    if (s->timing_request < 0 || s->device.context->timestamp_valid_bits == 0 || plan->host)
        return CVK_SUCCESS;
    out->count = cvk_plan_query_count(plan, NULL);
    if (out->count == UINT32_MAX)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "substeps: %u substeps of %u operations need more timestamp queries "
                        "than a frame may hold", plan->substeps, plan->op_count);
    out->pass = calloc(out->count, sizeof *out->pass);
    if (!out->pass)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for queries");
    cvk_plan_query_count(plan, out->pass);
    VkQueryPoolCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
        .queryType = VK_QUERY_TYPE_TIMESTAMP,
        .queryCount = out->count,
    };
    VkResult vr = vkCreateQueryPool(s->device.context->device, &info, NULL, &out->pool);
    if (vr != VK_SUCCESS) {
        out->pool = VK_NULL_HANDLE;
        cvk_sim_destroy_queries(s, out);
        return cvk_fail_vk(error, "vkCreateQueryPool", vr);
    }
    return CVK_SUCCESS;
}

void cvk_sim_use_queries(cvk_sim* s, cvk_sim_queries* q)
{
    if (s->queries)
        vkDestroyQueryPool(s->device.context->device, s->queries, NULL);
    free(s->query_pass);
    s->queries = q->pool;
    s->query_count = q->count;
    s->query_pass = q->pass;
    s->timing = q->pool != VK_NULL_HANDLE;
    s->device.unreset_queries = s->timing ? s->queries : VK_NULL_HANDLE;
    s->device.unreset_query_count = s->query_count;
    *q = (cvk_sim_queries){0};
}

static void record_frame(const cvk_sim* s, VkCommandBuffer cmd)
{
    cvk_plan_queries queries = {s->timing ? s->queries : VK_NULL_HANDLE, s->query_count};
    cvk_plan_record_frame(&s->plan, &s->pipelines, &queries, cmd);
}

/* With self-contact, cvk_sim_step's frames end by copying the contact frame state's cut flag
   (a detection's loops ended early: shaders/contact/bounds.glsl) into the watch, which the host
   reads after its fence (cvk_sim_watch_check): no submission more. */
static void record_cut_copy(const cvk_sim* s, VkCommandBuffer cmd)
{
    if (!s->collide->self)
        return;
    VkMemoryBarrier to_copy = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT, /* the frame state; the watch too */
        .dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                         1, &to_copy, 0, NULL, 0, NULL);
    VkBufferCopy region = {.srcOffset = offsetof(cvk_gpu_frame, cut),
                           .dstOffset = offsetof(cvk_gpu_watch, contact_cut),
                           .size = sizeof(uint32_t)};
    vkCmdCopyBuffer(cmd, s->collide->frame.buffer, s->watch.buffer, 1, &region);
    VkMemoryBarrier to_host = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_HOST_READ_BIT,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                         &to_host, 0, NULL, 0, NULL);
}

/* frame_cmd holds one frame of the plan; a host plan records nothing. */
cvk_result cvk_sim_record_frame_cmd(cvk_sim* s, cvk_error* error)
{
    if (s->plan.host) {
        VkResult vr = vkResetCommandBuffer(s->frame_cmd, 0);
        return vr == VK_SUCCESS ? CVK_SUCCESS : cvk_fail_vk(error, "vkResetCommandBuffer", vr);
    }
    cvk_result r = cvk_command_buffer_begin(s->frame_cmd, VK_COMMAND_BUFFER_USAGE_SIMULTANEOUS_USE_BIT, error);
    if (r != CVK_SUCCESS)
        return r;
    record_frame(s, s->frame_cmd);
    record_cut_copy(s, s->frame_cmd);
    return cvk_command_buffer_end(s->frame_cmd, error);
}

/* ---- creation ------------------------------------------------------------------------ */

/* A cloth's "velocity": every free particle starts with its cloth's, through the family. */
static cvk_result set_initial_velocity(cvk_sim* s, const cvk_scene_desc* scene, cvk_error* error)
{
    bool moving = false;
    for (uint32_t c = 0; c < scene->cloth_count; c++)
        for (int k = 0; k < 3; k++)
            moving = moving || scene->cloths[c].velocity[k] != 0.0f;
    if (!moving)
        return CVK_SUCCESS;
    const cvk_build* b = &s->build;
    for (uint32_t p = 0; p < b->particle_count; p++) {
        uint32_t cloth = cvk_build_cloth_of(b, p);
        for (int k = 0; k < 3; k++) {
            s->scratch[3 * (size_t)p + k] = b->position[3 * (size_t)p + k];
            s->scratch_v[3 * (size_t)p + k] =
                p < b->free_count ? scene->cloths[cloth].velocity[k] : 0.0f;
        }
    }
    cvk_result r = s->family->write_state(s, s->family_state, s->scratch, s->scratch_v, error);
    return r == CVK_SUCCESS ? cvk_collide_positions_written(s, s->scratch, s->scratch_v, error) : r;
}

/* The contact radius: given with a default thickness, checked against the thickness the
   contact resolved. */
static cvk_result resolve_radius(cvk_sim* s, const cvk_scene_desc* scene, cvk_error* error)
{
    cvk_scene_issue issue;
    if (!cvk_collision_radius_check(&scene->collision, s->collide->thickness, &issue))
        return cvk_fail_issue(error, &issue);
    return CVK_SUCCESS;
}

static cvk_result create_objects(cvk_sim* s, const cvk_scene_desc* scene, uint32_t workgroup_size,
                                 uint32_t max_groups, bool grab, cvk_error* error)
{
    size_t n = s->build.particle_count;
    s->scratch = cvk_malloc_array(3 * n, sizeof(float)); /* n < 2^30: 3n fits */
    s->scratch_v = cvk_malloc_array(3 * n, sizeof(float));
    if (!s->scratch || !s->scratch_v)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for positions");
    cvk_result r = create_buffers(s, error);
    if (r == CVK_SUCCESS)
        r = cvk_submitter_create(s->device.context, &s->device.submitter, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_allocate(s->device.context, &s->device.submitter, &s->frame_cmd, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_allocate(s->device.context, &s->device.submitter, &s->device.transfer_cmd, error);
    if (r == CVK_SUCCESS)
        r = upload_spring_flags(s, error);
    if (r == CVK_SUCCESS)
        r = cvk_collide_create(s, scene, error);
    if (r == CVK_SUCCESS)
        r = resolve_radius(s, scene, error);
    if (r == CVK_SUCCESS)
        r = cvk_sim_check_collider_start(s, scene, error);
    if (r == CVK_SUCCESS)
        r = cvk_attach_create(s, scene, error);
    if (r == CVK_SUCCESS)
        r = cvk_aero_create(s, scene, error);
    if (r == CVK_SUCCESS)
        r = cvk_tear_create(s, scene, error);
    if (r == CVK_SUCCESS)
        r = s->family->create(s, &s->solver, &s->family_state, error);
    if (r == CVK_SUCCESS)
        r = set_initial_velocity(s, scene, error);
    if (r == CVK_SUCCESS && grab) {
        const char* unsupported = cvk_grab_unsupported(&s->solver);
        r = unsupported ? cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                                   "cvk_sim_desc.grab: %s cannot hold a grabbed particle; use the "
                                   "pd method with rbgs, jacobi or chebyshev", unsupported)
                        : cvk_grab_enable(s, error);
    }
    if (r == CVK_SUCCESS)
        r = cvk_sim_make_plan(s, s->family, s->family_state, &s->solver, workgroup_size,
                              max_groups, &s->plan, error);
    if (r == CVK_SUCCESS)
        r = cvk_sim_ready_pipelines(s, &s->plan, error);
    cvk_sim_queries queries;
    if (r == CVK_SUCCESS)
        r = cvk_sim_create_queries(s, &s->plan, &queries, error);
    if (r == CVK_SUCCESS)
        cvk_sim_use_queries(s, &queries);
    if (r == CVK_SUCCESS)
        r = cvk_device_copy_from_staging(&s->device, NULL, 0, error); /* resets the queries */
    if (r == CVK_SUCCESS)
        r = cvk_sim_record_frame_cmd(s, error);
    return r;
}

static uint32_t max_workgroups(const cvk_context* context, const cvk_sim_desc* desc)
{
    uint32_t max_groups = desc->max_workgroups;
    if (max_groups == 0)
        max_groups = context->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU
                         ? CPU_DEVICE_MAX_WORKGROUPS
                         : UINT32_MAX;
    if (max_groups > context->properties.limits.maxComputeWorkGroupCount[0])
        max_groups = context->properties.limits.maxComputeWorkGroupCount[0];
    return max_groups;
}


/* The simulation and its modules' states in one allocation; the simulation comes first, so
   freeing it frees them all. */
typedef struct sim_block {
    cvk_sim sim;
    cvk_collide collide;
    cvk_attach attach;
    cvk_aero aero;
    cvk_grab grab;
    cvk_pick pick;
    cvk_tear tear;
} sim_block;

static void init_fields(cvk_sim* s, cvk_context* context, const cvk_sim_desc* desc)
{
    const cvk_scene_desc* scene = desc->scene;
    s->device.context = context;
    snprintf(s->name, sizeof s->name, "%s", scene->name ? scene->name : "scene");
    s->params = cvk_step_params_of(scene);
    s->solver = scene->solver;
    s->timing_request = desc->timing;
    s->family = cvk_family_for(&scene->solver);
    s->note_count = cvk_collision_notes(&scene->collision, s->notes);
    s->instance_count = scene->instances.count;
    s->instances_listed = scene->instances.offsets != NULL;
    for (int a = 0; a < 3 && scene->instances.count > 1; a++)
        s->instance_offset1[a] = scene->instances.offsets ? scene->instances.offsets[1][a]
                                                          : scene->instances.spacing[a];
}

cvk_sim_desc cvk_default_sim_desc(void)
{
    return (cvk_sim_desc){
        .scene = NULL,
        .workgroup_size = 0,     /* the library's choice */
        .max_workgroups = 0,     /* the library's choice */
        .timing = 0,             /* on where supported */
        .grab = false,           /* the first cvk_sim_grab adds the grab pass */
        .fused_shared_memory = 0, /* the library's choice */
        .search_lanes = 0,       /* the library's choice */
        .cookie_ = CVK_COOKIE_SIM,
    };
}

cvk_result cvk_sim_create(cvk_context* context, const cvk_sim_desc* desc, cvk_sim** out_sim,
                          cvk_error* error)
{
    static const char needs[] = "cvk_sim_create needs a context, a description with a scene, "
                                "and an output pointer";
    if (out_sim)
        *out_sim = NULL;
    if (!context || !desc || !out_sim)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s", needs);
    if (desc->cookie_ != CVK_COOKIE_SIM)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_sim_create: the description did "
                        "not come from cvk_default_sim_desc()");
    if (!desc->scene)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s", needs);
    const cvk_scene_desc* scene = desc->scene;
    cvk_result r = cvk_scene_desc_validate(scene, error);
    if (r != CVK_SUCCESS)
        return r;
    uint32_t workgroup_size = desc->workgroup_size ? desc->workgroup_size : DEFAULT_WORKGROUP_SIZE;
    r = cvk_check_scene_limits(context, scene, workgroup_size, error);
    if (r != CVK_SUCCESS)
        return r;
    if (!cvk_family_for(&scene->solver))
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "solver.method: no solver family for %s",
                        cvk_method_name(scene->solver.method));
    if (scene->solver.linear == CVK_LINEAR_GS_CPU &&
        (scene->collider_count > 0 || scene->collision.self))
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "solver.linear: gs-cpu (the host reference) does not handle contact; "
                        "use rbgs, jacobi or chebyshev in a scene with colliders or self-contact");

    sim_block* block = calloc(1, sizeof *block);
    if (!block)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the simulation");
    cvk_sim* s = &block->sim;
    s->collide = &block->collide;
    s->attach = &block->attach;
    s->aero = &block->aero;
    s->grab = &block->grab;
    s->pick = &block->pick;
    s->tear = &block->tear;
    init_fields(s, context, desc);
    s->particle_workgroup_size = particle_workgroup_size(context, desc, workgroup_size);
    s->fused_workgroup_size = fused_workgroup_size(context, desc, workgroup_size);
    s->particle_group_items = particle_group_items(context, desc);
    s->walk_items = walk_items(context, desc);
    cvk_build_limits limits = {context, scene};
    r = cvk_build_create_checked(scene, cvk_check_build_limits, &limits, &s->build, error);
    if (r == CVK_SUCCESS) {
        fuse_copies(s, desc);
        r = cvk_check_derived(scene, &s->build, scene->dt, error);
    }
    if (r == CVK_SUCCESS)
        r = cvk_sim_check_clean_start(s, scene, error);
    if (r == CVK_SUCCESS)
        r = create_objects(s, scene, workgroup_size, max_workgroups(context, desc), desc->grab,
                           error);
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
    VkDevice dev = s->device.context->device;
    if (s->device.submitter.pool)
        cvk_queue_idle(s->device.context);
    if (s->family && s->family_state)
        s->family->destroy(s, s->family_state);
    cvk_pick_destroy(s);
    cvk_grab_destroy(s);
    cvk_tear_destroy(s);
    cvk_aero_destroy(s);
    cvk_attach_destroy(s);
    cvk_collide_destroy(s);
    cvk_pipelines_destroy(s->device.context, &s->pipelines);
    if (s->queries)
        vkDestroyQueryPool(dev, s->queries, NULL);
    cvk_submitter_destroy(s->device.context, &s->device.submitter);
    VkBufferView views[] = {s->view_positions, s->view_spring_alive};
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++)
        if (views[i])
            vkDestroyBufferView(dev, views[i], NULL);
    cvk_buffer* buffers[] = {&s->positions, &s->spring_alive, &s->device.staging, &s->watch};
    for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; i++)
        cvk_buffer_destroy(s->device.context, buffers[i]);
    cvk_plan_destroy(&s->plan);
    cvk_build_destroy(&s->build);
    free(s->query_pass);
    free(s->batch);
    free(s->scratch);
    free(s->scratch_v);
    free(s);
}

/* ---- running ------------------------------------------------------------------------- */

cvk_result cvk_sim_record(cvk_sim* s, VkCommandBuffer cmd, uint32_t frames, cvk_error* error)
{
    if (!s || !cmd)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_record needs a simulation and a command buffer");
    if (s->plan.host)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "the %s solver runs on the host and cannot be recorded into a command "
                        "buffer; use cvk_sim_step", cvk_linear_solver_name(s->solver.linear));
    for (uint32_t f = 0; f < frames; f++)
        record_frame(s, cmd);
    return CVK_SUCCESS;
}

/* Submits `frames` copies of frame_cmd in batches; only the last carries the fence: the
   queue runs them in order. */
static cvk_result submit_frames(cvk_sim* s, uint32_t frames, cvk_error* error)
{
    uint32_t per_submit = frames < MAX_FRAMES_PER_SUBMIT ? frames : MAX_FRAMES_PER_SUBMIT;
    if (s->batch_capacity < per_submit) {
        VkCommandBuffer* batch = cvk_realloc_array(s->batch, per_submit, sizeof *batch);
        if (!batch)
            return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for a submission");
        s->batch = batch;
        s->batch_capacity = per_submit;
    }
    for (uint32_t i = 0; i < per_submit; i++)
        s->batch[i] = s->frame_cmd;
    for (uint32_t done = 0; done < frames;) {
        uint32_t count = frames - done < per_submit ? frames - done : per_submit;
        if (done + count == frames)
            return cvk_submit_and_wait(s->device.context, &s->device.submitter, s->batch, count, error);
        VkSubmitInfo submit = {
            .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
            .commandBufferCount = count,
            .pCommandBuffers = s->batch,
        };
        cvk_result r = cvk_queue_submit(s->device.context, &submit, VK_NULL_HANDLE, error);
        if (r != CVK_SUCCESS)
            return r;
        done += count;
    }
    return CVK_SUCCESS;
}

cvk_result cvk_sim_step(cvk_sim* s, uint32_t frames, cvk_error* error)
{
    if (!s)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_sim_step needs a simulation");
    if (frames == 0)
        return CVK_SUCCESS;
    cvk_result r = s->plan.host ? s->family->step_host(s, s->family_state, frames, error)
                                : submit_frames(s, frames, error);
    if (r == CVK_SUCCESS)
        s->frames += frames;
    if (r == CVK_SUCCESS && !s->plan.host)
        r = cvk_sim_watch_check(s, error);
    return r;
}

uint64_t cvk_sim_particle_count(const cvk_sim* s)
{
    return s ? s->build.particle_count : 0;
}
