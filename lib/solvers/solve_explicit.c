/* The explicit family: its device objects (velocities, the RK2 stage, accelerations, the
   Adams-Bashforth history, the adjacency), its state (positions, velocities, history) and its
   passes: per substep, a force pass and an update (Euler, Adams-Bashforth, Verlet) or two of
   each (TVD-RK2). The updates carry the divergence watch. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "shared/layout.h"
#include "solvers/family_objects.h"
#include "solvers/solve_explicit.h"
#include "solvers/velocity_state.h"
#include "features/tear.h"

typedef struct cvk_explicit {
    cvk_buffer v, xs, vs, adjacency, acc, history;
    cvk_descriptors descriptors; /* set 0 reads the state, set 1 the RK2 stage */
    VkCommandBuffer readback_cmd; /* positions and velocities -> staging */
} cvk_explicit;

/* The family's buffers (family_objects.h); returns how many. */
static size_t buffer_table(const cvk_sim* s, cvk_explicit* ex,
                           cvk_family_buffer out[CVK_FAMILY_MAX_BUFFERS])
{
    const cvk_build* b = &s->build;
    VkDeviceSize n16 = (VkDeviceSize)b->particle_count * 16u;
    VkDeviceSize nf16 = (VkDeviceSize)(b->free_count ? b->free_count : 1) * 16u;
    VkDeviceSize slots16 = nf16 * (b->max_degree ? b->max_degree : 1);
    VkBufferUsageFlags use = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                             VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    const cvk_family_buffer list[] = {
        {&ex->v, n16, use, CVK_MEMORY_DEVICE, "velocities", NULL, 0},
        {&ex->xs, nf16, use, CVK_MEMORY_DEVICE, "RK2 stage positions", NULL, 0},
        {&ex->vs, nf16, use, CVK_MEMORY_DEVICE, "RK2 stage velocities", NULL, 0},
        {&ex->adjacency, slots16, use, CVK_MEMORY_DEVICE, "explicit adjacency", NULL, 0},
        {&ex->acc, nf16, use, CVK_MEMORY_DEVICE, "accelerations", NULL, 0},
        {&ex->history, CVK_EXPLICIT_HISTORY * nf16, use, CVK_MEMORY_DEVICE,
         "Adams-Bashforth history", NULL, 0},
    };
    _Static_assert(sizeof list / sizeof list[0] <= CVK_FAMILY_MAX_BUFFERS, "a longer table");
    memcpy(out, list, sizeof list);
    return sizeof list / sizeof list[0];
}

static cvk_result create_sets(cvk_sim* s, cvk_explicit* ex, cvk_error* error)
{
    cvk_binding bindings[CVK_EXPLICIT_BINDING_COUNT];
    for (uint32_t i = 0; i < CVK_EXPLICIT_BINDING_COUNT; i++)
        bindings[i] = (cvk_binding){VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0};
    cvk_result r = cvk_descriptors_create(s->device.context, bindings, CVK_EXPLICIT_BINDING_COUNT, 2,
                                          VK_SHADER_STAGE_COMPUTE_BIT,
                                          sizeof(cvk_explicit_push), &ex->descriptors, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_resource res[CVK_EXPLICIT_BINDING_COUNT] = {
        [CVK_EXPLICIT_BINDING_X] = {.buffer = &s->positions},
        [CVK_EXPLICIT_BINDING_V] = {.buffer = &ex->v},
        [CVK_EXPLICIT_BINDING_XS] = {.buffer = &ex->xs},
        [CVK_EXPLICIT_BINDING_VS] = {.buffer = &ex->vs},
        [CVK_EXPLICIT_BINDING_ADJACENCY] = {.buffer = &ex->adjacency},
        [CVK_EXPLICIT_BINDING_A] = {.buffer = &ex->acc},
        [CVK_EXPLICIT_BINDING_HISTORY] = {.buffer = &ex->history},
        [CVK_EXPLICIT_BINDING_WATCH] = {.buffer = &s->watch},
        [CVK_EXPLICIT_BINDING_X_IN] = {.buffer = &s->positions},
        [CVK_EXPLICIT_BINDING_V_IN] = {.buffer = &ex->v},
    };
    cvk_descriptors_write(s->device.context, &ex->descriptors, 0, res);
    res[CVK_EXPLICIT_BINDING_X_IN].buffer = &ex->xs;
    res[CVK_EXPLICIT_BINDING_V_IN].buffer = &ex->vs;
    cvk_descriptors_write(s->device.context, &ex->descriptors, 1, res);
    return CVK_SUCCESS;
}

/* ---- state: positions, velocities (w: mass) and the history --------------------------- */

/* A new state starts the Adams-Bashforth rule again from Euler steps. */
static cvk_result explicit_write_state(cvk_sim* s, void* self, const float* xyz,
                                       const float* velocity, cvk_error* error)
{
    cvk_explicit* ex = self;
    cvk_result r = cvk_device_clear_buffer(&s->device, &ex->history, error);
    return r == CVK_SUCCESS ? cvk_vstate_write(s, &ex->v, xyz, velocity, error) : r;
}

static cvk_result explicit_read_state(cvk_sim* s, void* self, float* xyz, float* velocity,
                                      cvk_error* error)
{
    cvk_explicit* ex = self;
    return cvk_vstate_read(s, ex->readback_cmd, xyz, velocity, error);
}

/* Snapshots: positions[n] vec4, velocities[n] vec4, then the history, exactly as held. */
static uint64_t explicit_snapshot_size(const cvk_sim* s, const void* self)
{
    const cvk_explicit* ex = self;
    return 32u * (uint64_t)s->build.particle_count + ex->history.size;
}

static cvk_result explicit_save_snapshot(cvk_sim* s, void* self, void* data, cvk_error* error)
{
    cvk_explicit* ex = self;
    uint64_t state = 32u * (uint64_t)s->build.particle_count;
    cvk_result r = cvk_vstate_save(s, ex->readback_cmd, data, error);
    if (r != CVK_SUCCESS)
        return r;
    return cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd, &ex->history,
                               (unsigned char*)data + state, ex->history.size, error);
}

static cvk_result explicit_load_snapshot(cvk_sim* s, void* self, const void* data, uint64_t size,
                                         cvk_error* error)
{
    cvk_explicit* ex = self;
    if (size != explicit_snapshot_size(s, self))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_load_snapshot: the explicit state of this simulation is %llu "
                        "bytes; the snapshot holds %llu",
                        (unsigned long long)explicit_snapshot_size(s, self),
                        (unsigned long long)size);
    uint64_t state = 32u * (uint64_t)s->build.particle_count;
    /* The history first: its upload goes through the staging buffer too. */
    cvk_result r = cvk_device_upload(&s->device, &ex->history, (const unsigned char*)data + state,
                                  ex->history.size, error);
    return r == CVK_SUCCESS ? cvk_vstate_load(s, &ex->v, data, error) : r;
}

/* ---- passes ------------------------------------------------------------------------------ */

static void add(cvk_plan* plan, uint32_t pass, const cvk_explicit* ex, cvk_pipeline_id pipeline,
                uint32_t set, cvk_explicit_push push, uint32_t mode, const char* note)
{
    push.mode = mode;
    cvk_op* op = cvk_plan_dispatch(plan, pass, pipeline, ex->descriptors.pipeline_layout,
                                   ex->descriptors.sets[set], CVK_DOMAIN_PARTICLES, 0,
                                   push.count, &push, sizeof push);
    if (op)
        snprintf(op->note, sizeof op->note, "%s", note);
}

static cvk_result explicit_add_passes(cvk_sim* s, void* self, const cvk_solver_desc* solver,
                                      cvk_plan* plan, cvk_error* error)
{
    const cvk_explicit* ex = self;
    cvk_explicit_params ep = cvk_explicit_params_of(&s->params, solver);
    cvk_explicit_push push = {
        .count = s->build.free_count,
        .stride = s->build.free_count,
        .viscosity = ep.damping_model == CVK_DAMPING_VISCOSITY,
        .h = (float)ep.h,
        .kd = (float)ep.kd,
        .keep = (float)ep.keep,
        .max_u2 = (float)(CVK_DIVERGED_SPEED * ep.h * CVK_DIVERGED_SPEED * ep.h),
    };
    for (int c = 0; c < 3; c++)
        push.gravity[c] = (float)ep.gravity[c];
    uint32_t force = cvk_plan_pass(plan, "force");
    uint32_t update = cvk_plan_pass(plan, "update");
    add(plan, force, ex, CVK_PIPE_EXPLICIT_FORCE, 0, push, 1, "from x, v; counts the substep");
    switch (ep.integrator) {
    case CVK_INTEGRATOR_RK2:
        add(plan, update, ex, CVK_PIPE_EXPLICIT_UPDATE, 0, push, CVK_EXPLICIT_RK2_STAGE,
            "rk2 stage: xs, vs (an Euler step)");
        add(plan, force, ex, CVK_PIPE_EXPLICIT_FORCE, 1, push, 0, "from xs, vs");
        add(plan, update, ex, CVK_PIPE_EXPLICIT_UPDATE, 0, push, CVK_EXPLICIT_RK2_COMBINE,
            "rk2: average of x and an Euler step from xs");
        break;
    case CVK_INTEGRATOR_AB4:
        add(plan, update, ex, CVK_PIPE_EXPLICIT_UPDATE, 0, push, CVK_EXPLICIT_AB4,
            "adams-bashforth 4 (euler for 3 steps), history");
        break;
    case CVK_INTEGRATOR_VERLET:
        add(plan, update, ex, CVK_PIPE_EXPLICIT_UPDATE, 0, push, CVK_EXPLICIT_VERLET,
            "verlet: v += h a, x += h v");
        break;
    default:
        add(plan, update, ex, CVK_PIPE_EXPLICIT_UPDATE, 0, push, CVK_EXPLICIT_EULER,
            "euler: x += h v, v += h a");
        break;
    }
    cvk_result r = cvk_tear_add_passes(s, CVK_TEAR_FOR_EXPLICIT, plan, error); /* after the update */
    if (r != CVK_SUCCESS)
        return r;
    snprintf(plan->solver_note, sizeof plan->solver_note, ", %s, %s damping, kd %g N s/m",
             cvk_integrator_name(ep.integrator), cvk_damping_model_name(ep.damping_model),
             solver->kd);
    return cvk_plan_check(plan, error);
}

/* ---- the family ---------------------------------------------------------------------------- */

static bool explicit_accepts(const cvk_solver_desc* solver)
{
    return solver->method == CVK_METHOD_EXPLICIT;
}

static void explicit_destroy(cvk_sim* s, void* self)
{
    cvk_explicit* ex = self;
    if (!ex)
        return;
    cvk_family_buffer list[CVK_FAMILY_MAX_BUFFERS];
    size_t count = buffer_table(s, ex, list);
    cvk_descriptors* sets[] = {&ex->descriptors};
    cvk_family_destroy(s, sets, 1, list, count, ex->readback_cmd);
    free(ex);
}

static cvk_result explicit_set_torn(cvk_sim* s, void* self, const uint32_t* alive,
                                    cvk_error* error)
{
    cvk_explicit* ex = self;
    return cvk_vstate_set_torn(s, &ex->adjacency, alive, error);
}

static cvk_result explicit_create(cvk_sim* s, const cvk_solver_desc* solver, void** self,
                                  cvk_error* error)
{
    (void)solver;
    *self = NULL;
    cvk_explicit* ex = calloc(1, sizeof *ex);
    if (!ex)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the solver");
    cvk_family_buffer list[CVK_FAMILY_MAX_BUFFERS];
    size_t count = buffer_table(s, ex, list);
    cvk_result r = cvk_family_create(s, list, count, &ex->readback_cmd, error);
    if (r == CVK_SUCCESS)
        r = create_sets(s, ex, error);
    if (r == CVK_SUCCESS) /* Adams-Bashforth starts from Euler steps */
        r = cvk_device_clear_buffer(&s->device, &ex->history, error);
    if (r == CVK_SUCCESS)
        cvk_tear_bind(s, CVK_TEAR_FOR_EXPLICIT, &ex->adjacency);
    if (r == CVK_SUCCESS)
        r = cvk_vstate_start(s, &ex->v, &ex->adjacency, ex->readback_cmd, error);
    if (r != CVK_SUCCESS) {
        explicit_destroy(s, ex);
        return r;
    }
    *self = ex;
    return CVK_SUCCESS;
}

static cvk_result explicit_prepare(cvk_sim* s, void* self, const cvk_solver_desc* solver,
                                   cvk_error* error)
{
    (void)s, (void)self, (void)solver, (void)error;
    return CVK_SUCCESS;
}

/* Every integrator shares the state; a switch starts Adams-Bashforth again from Euler. */
static cvk_result explicit_switch_solver(cvk_sim* s, void* self, const cvk_solver_desc* from,
                                         const cvk_solver_desc* to, cvk_error* error)
{
    (void)from, (void)to;
    cvk_explicit* ex = self;
    return cvk_device_clear_buffer(&s->device, &ex->history, error);
}

static cvk_result explicit_step_host(cvk_sim* s, void* self, uint32_t frames, cvk_error* error)
{
    (void)s, (void)self, (void)frames;
    return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "the explicit family has no host solver");
}

const cvk_family_api cvk_family_explicit = {
    .name = "explicit",
    .accepts = explicit_accepts,
    .create = explicit_create,
    .destroy = explicit_destroy,
    .add_passes = explicit_add_passes,
    .prepare = explicit_prepare,
    .switch_solver = explicit_switch_solver,
    .read_state = explicit_read_state,
    .write_state = explicit_write_state,
    .step_host = explicit_step_host,
    .snapshot_size = explicit_snapshot_size,
    .save_snapshot = explicit_save_snapshot,
    .load_snapshot = explicit_load_snapshot,
    .set_torn = explicit_set_torn,
};
