/* The implicit Euler family: its device objects (velocities, adjacency, blocks, CG vectors,
   the solve's scalars), its state (positions and velocities), and its passes: assemble, then
   max_iterations CG iterations or Jacobi sweeps that stop themselves on the device, then
   integrate. No host round trip inside a frame. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "features/attach.h"
#include "core/error.h"
#include "shared/layout.h"
#include "solvers/family_objects.h"
#include "solvers/solve_implicit.h"
#include "solvers/velocity_state.h"
#include "contact/collide.h"
#include "contact/hash.h"
#include "features/tear.h"

/* Reduction invocations are at most the free particles rounded up to a workgroup. */
#define MAX_WORKGROUP_SIZE 1024u
#define PARTIALS_CAPACITY(free_count) ((free_count) + MAX_WORKGROUP_SIZE)

typedef struct cvk_implicit {
    /* Velocities (w: mass), adjacency, per-particle and per-slot blocks, the system's vectors,
       partial sums and the scalars (host-visible, read for the statistics). */
    cvk_buffer v, adjacency, diag, offdiag, rhs, dv[2], r, z, p, q, partials, scalars;
    cvk_buffer filter; /* the contact filter's normal per free particle (implicit_contact.comp) */
    VkBufferView view_p, view_offdiag; /* the product's texel reads */
    cvk_descriptors descriptors;
    VkCommandBuffer readback_cmd; /* positions and velocities -> staging */
    uint32_t partial_count;       /* invocations of each reduction pass */
} cvk_implicit;

/* The family's buffers (family_objects.h); returns how many. */
static size_t buffer_table(const cvk_sim* s, cvk_implicit* im,
                           cvk_family_buffer out[CVK_FAMILY_MAX_BUFFERS])
{
    const cvk_build* b = &s->build;
    VkDeviceSize n16 = (VkDeviceSize)b->particle_count * 16u;
    VkDeviceSize nf16 = (VkDeviceSize)(b->free_count ? b->free_count : 1) * 16u;
    VkDeviceSize slots16 = nf16 * (b->max_degree ? b->max_degree : 1);
    VkDeviceSize partials = (VkDeviceSize)PARTIALS_CAPACITY(b->free_count) * 4u;
    VkBufferUsageFlags use = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                             VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    /* p and the off-diagonal blocks are the product's texel reads; the scalars hold the
       solve's indirect dispatches. */
    VkBufferUsageFlags texel = use | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
    VkBufferUsageFlags indirect = use | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
    VkFormat vec4 = VK_FORMAT_R32G32B32A32_SFLOAT;
    cvk_memory_kind device = CVK_MEMORY_DEVICE;
    const cvk_family_buffer list[] = {
        {&im->v, n16, use, device, "velocities", NULL, 0},
        {&im->adjacency, slots16, use, device, "implicit adjacency", NULL, 0},
        {&im->diag, 4 * nf16, use, device, "diagonal blocks", NULL, 0},
        {&im->offdiag, 2 * slots16, texel, device, "off-diagonal blocks", &im->view_offdiag, vec4},
        {&im->rhs, nf16, use, device, "implicit right-hand side", NULL, 0},
        {&im->dv[0], nf16, use, device, "velocity change", NULL, 0},
        {&im->dv[1], nf16, use, device, "velocity change (second iterate)", NULL, 0},
        {&im->r, nf16, use, device, "CG residual", NULL, 0},
        {&im->z, nf16, use, device, "CG preconditioned residual", NULL, 0},
        {&im->p, nf16, texel, device, "CG direction", &im->view_p, vec4},
        {&im->q, nf16, use, device, "CG product", NULL, 0},
        {&im->filter, nf16, use, device, "contact filter", NULL, 0},
        {&im->partials, partials, use, device, "partial sums", NULL, 0},
        {&im->scalars, sizeof(cvk_implicit_scalars), indirect, CVK_MEMORY_HOST, "solver scalars",
         NULL, 0},
    };
    _Static_assert(sizeof list / sizeof list[0] <= CVK_FAMILY_MAX_BUFFERS, "a longer table");
    memcpy(out, list, sizeof list);
    return sizeof list / sizeof list[0];
}

#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
#define TEXEL {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 0}
static const cvk_binding implicit_bindings[CVK_IMPLICIT_BINDING_COUNT] = {
    STORAGE, STORAGE, STORAGE, STORAGE, STORAGE, STORAGE, STORAGE, STORAGE, STORAGE,
    STORAGE, STORAGE, STORAGE, STORAGE, STORAGE, TEXEL,   TEXEL,   STORAGE,
};
#undef STORAGE
#undef TEXEL

static cvk_result create_set(cvk_sim* s, cvk_implicit* im, cvk_error* error)
{
    /* Set 1 is the contact set: the contact pass reads the colliders (shaders/contact/collide.glsl). */
    cvk_result r = cvk_descriptors_create_with(s->device.context, implicit_bindings,
                                               CVK_IMPLICIT_BINDING_COUNT, 1,
                                               VK_SHADER_STAGE_COMPUTE_BIT,
                                               sizeof(cvk_implicit_push),
                                               &s->collide->set_layout, 1, &im->descriptors,
                                               error);
    if (r != CVK_SUCCESS)
        return r;
    const cvk_resource res[CVK_IMPLICIT_BINDING_COUNT] = {
        [CVK_IMPLICIT_BINDING_X] = {.buffer = &s->positions},
        [CVK_IMPLICIT_BINDING_V] = {.buffer = &im->v},
        [CVK_IMPLICIT_BINDING_ADJACENCY] = {.buffer = &im->adjacency},
        [CVK_IMPLICIT_BINDING_DIAG] = {.buffer = &im->diag},
        [CVK_IMPLICIT_BINDING_OFFDIAG] = {.buffer = &im->offdiag},
        [CVK_IMPLICIT_BINDING_B] = {.buffer = &im->rhs},
        [CVK_IMPLICIT_BINDING_DV0] = {.buffer = &im->dv[0]},
        [CVK_IMPLICIT_BINDING_DV1] = {.buffer = &im->dv[1]},
        [CVK_IMPLICIT_BINDING_R] = {.buffer = &im->r},
        [CVK_IMPLICIT_BINDING_Z] = {.buffer = &im->z},
        [CVK_IMPLICIT_BINDING_P] = {.buffer = &im->p},
        [CVK_IMPLICIT_BINDING_Q] = {.buffer = &im->q},
        [CVK_IMPLICIT_BINDING_PARTIALS] = {.buffer = &im->partials},
        [CVK_IMPLICIT_BINDING_SCALARS] = {.buffer = &im->scalars},
        [CVK_IMPLICIT_BINDING_P_READ] = {.view = im->view_p},
        [CVK_IMPLICIT_BINDING_OFFDIAG_READ] = {.view = im->view_offdiag},
        [CVK_IMPLICIT_BINDING_FILTER] = {.buffer = &im->filter},
    };
    cvk_descriptors_write(s->device.context, &im->descriptors, 0, res);
    return CVK_SUCCESS;
}

/* ---- state: positions and velocities (w: mass), vec4 in internal order ------------------ */

static cvk_result implicit_write_state(cvk_sim* s, void* self, const float* xyz,
                                       const float* velocity, cvk_error* error)
{
    cvk_implicit* im = self;
    return cvk_vstate_write(s, &im->v, xyz, velocity, error);
}

static cvk_result implicit_read_state(cvk_sim* s, void* self, float* xyz, float* velocity,
                                      cvk_error* error)
{
    cvk_implicit* im = self;
    return cvk_vstate_read(s, im->readback_cmd, xyz, velocity, error);
}

/* Snapshots: positions[n] vec4 then velocities[n] vec4, exactly as held. */
static uint64_t implicit_snapshot_size(const cvk_sim* s, const void* self)
{
    (void)self;
    return 32u * (uint64_t)s->build.particle_count;
}

static cvk_result implicit_save_snapshot(cvk_sim* s, void* self, void* data, cvk_error* error)
{
    cvk_implicit* im = self;
    return cvk_vstate_save(s, im->readback_cmd, data, error);
}

static cvk_result implicit_load_snapshot(cvk_sim* s, void* self, const void* data, uint64_t size,
                                         cvk_error* error)
{
    if (size != implicit_snapshot_size(s, self))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_load_snapshot: the implicit state of this simulation is %llu "
                        "bytes; the snapshot holds %llu",
                        (unsigned long long)implicit_snapshot_size(s, self),
                        (unsigned long long)size);
    cvk_implicit* im = self;
    return cvk_vstate_load(s, &im->v, data, error);
}

void cvk_implicit_stats(const cvk_sim* s, cvk_sim_stats* st)
{
    const cvk_implicit* im = s->family == &cvk_family_implicit ? s->family_state : NULL;
    cvk_implicit_scalars scalars = {0};
    if (im)
        memcpy(&scalars, im->scalars.mapped, sizeof scalars);
    st->solver_iterations = scalars.frame_iterations;
    st->solver_iterations_total = scalars.total_iterations;
    st->solver_breakdowns = scalars.breakdown;
}

cvk_result cvk_implicit_read_held(cvk_sim* s, float* held, cvk_error* error)
{
    if (s->family != &cvk_family_implicit)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_implicit_read_held: the simulation does not solve with implicit");
    cvk_implicit* im = s->family_state;
    const cvk_build* b = &s->build;
    float* filter = malloc(im->filter.size);
    if (!filter)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the filter");
    cvk_result r = cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd, &im->filter,
                                       filter, im->filter.size, error);
    for (uint32_t p = 0; r == CVK_SUCCESS && p < b->particle_count; p++)
        for (int c = 0; c < 4; c++)
            held[4 * (size_t)b->user_of[p] + c] = p < b->free_count ? filter[4 * p + c] : 0.0f;
    free(filter);
    return r;
}

/* Enough reduction invocations to use the device, few enough that one invocation sums them
   quickly: at most 16 workgroups. */
static uint32_t partial_count(const cvk_sim* s, const cvk_plan* plan)
{
    uint32_t wg = plan->workgroup_size;
    uint32_t groups = (s->build.free_count + wg - 1) / wg;
    uint32_t cap = plan->max_groups < 16u ? plan->max_groups : 16u;
    if (groups > cap)
        groups = cap;
    return (groups ? groups : 1u) * wg;
}

/* ---- passes ------------------------------------------------------------------------------ */

typedef struct implicit_builder {
    cvk_plan* plan;
    const cvk_implicit* im;
    cvk_implicit_push push;
    uint32_t solve;
} implicit_builder;

/* How a pass is dispatched. The assembly and integration cover the free particles directly;
   the solve's passes are dispatched indirectly from the commands in the scalars buffer, which
   the assembly fills and the stop test zeroes. Reductions run partial_count invocations, each
   over a fixed stride, so their sums are the same bits every run. */
typedef enum pass_shape {
    SHAPE_DIRECT,
    SHAPE_PARTICLES,
    SHAPE_REDUCE,
    SHAPE_SINGLE, /* one invocation: a stop test; the next passes read the commands it wrote */
} pass_shape;

static cvk_op* add(implicit_builder* ib, uint32_t pass, cvk_pipeline_id pipeline, pass_shape shape,
                   const char* note, uint32_t iteration)
{
    const cvk_implicit* im = ib->im;
    VkPipelineLayout layout = im->descriptors.pipeline_layout;
    VkDescriptorSet set = im->descriptors.sets[0];
    cvk_op* op;
    if (shape == SHAPE_DIRECT) {
        op = cvk_plan_dispatch(ib->plan, pass, pipeline, layout, set, CVK_DOMAIN_PARTICLES, 0,
                               ib->push.count, &ib->push, sizeof ib->push);
    } else {
        VkDeviceSize offset = shape == SHAPE_REDUCE
                                  ? offsetof(cvk_implicit_scalars, reduce_groups)
                                  : shape == SHAPE_PARTICLES
                                        ? offsetof(cvk_implicit_scalars, particle_groups)
                                        : offsetof(cvk_implicit_scalars, single_groups);
        op = cvk_plan_dispatch_indirect(ib->plan, pass, pipeline, layout, set,
                                        CVK_DOMAIN_PARTICLES, im->scalars.buffer, offset,
                                        &ib->push, sizeof ib->push);
        if (op) {
            op->count = shape == SHAPE_REDUCE ? im->partial_count
                                              : shape == SHAPE_PARTICLES ? ib->push.count : 1;
            if (shape == SHAPE_SINGLE)
                op->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT;
        }
    }
    if (op && iteration)
        snprintf(op->note, sizeof op->note, "%s, iteration %u", note, iteration);
    else if (op)
        snprintf(op->note, sizeof op->note, "%s", note);
    return op;
}

static void plan_cg(implicit_builder* ib, uint32_t iterations)
{
    add(ib, ib->solve, CVK_PIPE_IMPLICIT_CG_START, SHAPE_REDUCE, "start", 0);
    add(ib, ib->solve, CVK_PIPE_IMPLICIT_CG_RHO0, SHAPE_SINGLE, "rho0", 0);
    for (uint32_t i = 1; i <= iterations; i++) {
        add(ib, ib->solve, CVK_PIPE_IMPLICIT_CG_PRODUCT, SHAPE_REDUCE, "until converged", i);
        add(ib, ib->solve, CVK_PIPE_IMPLICIT_CG_ALPHA, SHAPE_SINGLE, "until converged", i);
        add(ib, ib->solve, CVK_PIPE_IMPLICIT_CG_UPDATE, SHAPE_REDUCE, "until converged", i);
        add(ib, ib->solve, CVK_PIPE_IMPLICIT_CG_BETA, SHAPE_SINGLE, "until converged", i);
        if (i < iterations)
            add(ib, ib->solve, CVK_PIPE_IMPLICIT_CG_DIRECTION, SHAPE_PARTICLES, "until converged",
                i);
    }
}

static void plan_jacobi(implicit_builder* ib, uint32_t sweeps)
{
    for (uint32_t i = 1; i <= sweeps; i++) {
        add(ib, ib->solve, i % 2 ? CVK_PIPE_IMPLICIT_JACOBI_EVEN : CVK_PIPE_IMPLICIT_JACOBI_ODD,
            SHAPE_REDUCE, "until converged", i);
        add(ib, ib->solve, CVK_PIPE_IMPLICIT_JACOBI_CHECK, SHAPE_SINGLE, "until converged", i);
    }
}

/* Self-contact after the integration (shaders/solvers/implicit_self.comp): the listed
   particles pushed off the cloth features, through the work list's command that detection
   writes (no workgroups when no particle is in a pair), then x += the kept displacement. */
static void add_self_contact(implicit_builder* ib, cvk_sim* s, uint32_t pass)
{
    const cvk_implicit* im = ib->im;
    cvk_op* op = cvk_plan_dispatch_indirect(ib->plan, pass, CVK_PIPE_IMPLICIT_SELF_LISTED,
                                            im->descriptors.pipeline_layout, im->descriptors.sets[0],
                                            CVK_DOMAIN_PARTICLES, s->collide->lists.buffer,
                                            4u * CVK_LIST_LISTED_GROUPS, &ib->push, sizeof ib->push);
    if (op) {
        op->count = ib->push.count;
        op->set1 = s->collide->set;
        snprintf(op->note, sizeof op->note, "listed particles off the cloth features: r -> z");
    }
    op = add(ib, pass, CVK_PIPE_IMPLICIT_SELF_APPLY, SHAPE_DIRECT, "x += z, v = z / h where pushed",
             0);
    if (op)
        op->set1 = s->collide->set;
}

/* With self-contact, after the attachments' place pass: each attached particle kept within its
   bound (pd's contact pass keeps them so): over [free_count, particle_count). */
static void add_attached_within_bounds(implicit_builder* ib, cvk_sim* s, uint32_t pass)
{
    cvk_implicit_push push = ib->push;
    push.count = s->build.particle_count;
    cvk_op* op = cvk_plan_dispatch(ib->plan, pass, CVK_PIPE_IMPLICIT_SELF_ATTACHED,
                                   ib->im->descriptors.pipeline_layout, ib->im->descriptors.sets[0],
                                   CVK_DOMAIN_PARTICLES, s->build.free_count,
                                   s->build.particle_count - s->build.free_count, &push,
                                   sizeof push);
    if (op) {
        op->set1 = s->collide->set;
        snprintf(op->note, sizeof op->note, "attached x within its bound");
    }
}

static cvk_result implicit_add_passes(cvk_sim* s, void* self, const cvk_solver_desc* solver,
                                      cvk_plan* plan, cvk_error* error)
{
    cvk_implicit* im = self;
    if (plan->workgroup_size > MAX_WORKGROUP_SIZE)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "the implicit solver takes workgroups of at most %u invocations, not %u",
                        MAX_WORKGROUP_SIZE, plan->workgroup_size);
    im->partial_count = partial_count(s, plan);
    cvk_implicit_params ip = cvk_implicit_params_of(&s->params, solver);
    implicit_builder ib = {.plan = plan, .im = im};
    ib.push = (cvk_implicit_push){
        .count = s->build.free_count,
        .stride = s->build.free_count,
        .partials = im->partial_count,
        .clamp = 1,
        .h = (float)ip.h,
        .tol2 = (float)(ip.tolerance * ip.tolerance),
        .kd = (float)ip.kd,
        .keep = (float)ip.keep,
    };
    for (int c = 0; c < 3; c++)
        ib.push.gravity[c] = (float)ip.gravity[c];
    if (s->collide->collider_count > 0) {
        uint32_t contact = cvk_plan_pass(plan, "contact");
        cvk_op* op = add(&ib, contact, CVK_PIPE_IMPLICIT_CONTACT, SHAPE_DIRECT,
                         "held on colliders: x, v along n, S = I - n n^T", 0);
        if (op) {
            op->set1 = s->collide->set;
            /* each particle loops over the colliders: a few per invocation keep lavapipe's
               per-shader loop budget out of reach (cvk_plan_walk_groups) */
            op->groups = cvk_plan_walk_groups(plan, op->count);
        }
    }
    /* Attached particles: their velocity over the substep, read by the assembly. */
    cvk_result r = cvk_attach_add_implicit_pass(s, plan, false, error);
    if (r != CVK_SUCCESS)
        return r;
    uint32_t assemble = cvk_plan_pass(plan, "assemble");
    ib.solve = cvk_plan_pass(plan, "solve");
    uint32_t integrate = cvk_plan_pass(plan, "integrate");
    /* The frame's iteration count starts at its first substep. */
    cvk_op* reset = cvk_plan_fill(plan, assemble, im->scalars.buffer,
                                  offsetof(cvk_implicit_scalars, frame_iterations), 4, 0);
    if (reset)
        reset->every = s->params.substeps;
    cvk_op* op = add(&ib, assemble, CVK_PIPE_IMPLICIT_ASSEMBLE, SHAPE_DIRECT,
                     "blocks, b, dv = 0, the solve's dispatch commands", 0);
    if (op)
        op->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT;
    if (solver->linear == CVK_LINEAR_JACOBI)
        plan_jacobi(&ib, ip.max_iterations);
    else
        plan_cg(&ib, ip.max_iterations);
    op = add(&ib, integrate, CVK_PIPE_IMPLICIT_INTEGRATE, SHAPE_DIRECT, "from the solving iterate",
             0);
    if (op)
        op->set1 = s->collide->set; /* friction: the colliders' coefficients and poses */
    if (s->collide->self)
        add_self_contact(&ib, s, integrate);
    r = cvk_attach_add_implicit_pass(s, plan, true, error); /* attached x at their targets */
    if (r == CVK_SUCCESS && s->collide->self && s->build.attached_count > 0)
        add_attached_within_bounds(&ib, s, integrate);
    if (r == CVK_SUCCESS)
        r = cvk_tear_add_passes(s, CVK_TEAR_FOR_IMPLICIT, plan, error); /* after x += h v */
    if (r != CVK_SUCCESS)
        return r;
    snprintf(plan->solver_note, sizeof plan->solver_note,
             ", tolerance %g, at most %u iterations (stopped on the device), kd %g N s/m",
             ip.tolerance, ip.max_iterations, solver->kd);
    return cvk_plan_check(plan, error);
}

/* ---- the family ---------------------------------------------------------------------------- */

static bool implicit_accepts(const cvk_solver_desc* solver)
{
    return solver->method == CVK_METHOD_IMPLICIT;
}

static void implicit_destroy(cvk_sim* s, void* self)
{
    cvk_implicit* im = self;
    if (!im)
        return;
    cvk_family_buffer list[CVK_FAMILY_MAX_BUFFERS];
    size_t count = buffer_table(s, im, list);
    cvk_descriptors* sets[] = {&im->descriptors};
    cvk_family_destroy(s, sets, 1, list, count, im->readback_cmd);
    free(im);
}

static cvk_result implicit_set_torn(cvk_sim* s, void* self, const uint32_t* alive,
                                    cvk_error* error)
{
    cvk_implicit* im = self;
    return cvk_vstate_set_torn(s, &im->adjacency, alive, error);
}

static cvk_result implicit_create(cvk_sim* s, const cvk_solver_desc* solver, void** self,
                                  cvk_error* error)
{
    (void)solver;
    *self = NULL;
    cvk_implicit* im = calloc(1, sizeof *im);
    if (!im)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the solver");
    cvk_family_buffer list[CVK_FAMILY_MAX_BUFFERS];
    size_t count = buffer_table(s, im, list);
    cvk_result r = cvk_family_create(s, list, count, &im->readback_cmd, error);
    if (r == CVK_SUCCESS)
        memset(im->scalars.mapped, 0, sizeof(cvk_implicit_scalars));
    if (r == CVK_SUCCESS)
        r = create_set(s, im, error);
    if (r == CVK_SUCCESS)
        r = cvk_device_clear_buffer(&s->device, &im->filter, error); /* nothing held before contact */
    if (r == CVK_SUCCESS) {
        cvk_tear_bind(s, CVK_TEAR_FOR_IMPLICIT, &im->adjacency);
        cvk_attach_bind(s, CVK_ATTACH_FOR_IMPLICIT, &im->v, &im->v); /* velocity, place */
    }
    if (r == CVK_SUCCESS)
        r = cvk_vstate_start(s, &im->v, &im->adjacency, im->readback_cmd, error);
    if (r != CVK_SUCCESS) {
        implicit_destroy(s, im);
        return r;
    }
    *self = im;
    return CVK_SUCCESS;
}

static cvk_result implicit_prepare(cvk_sim* s, void* self, const cvk_solver_desc* solver,
                                   cvk_error* error)
{
    (void)s, (void)self, (void)solver, (void)error;
    return CVK_SUCCESS;
}

/* cg and jacobi share the state. */
static cvk_result implicit_switch_solver(cvk_sim* s, void* self, const cvk_solver_desc* from,
                                         const cvk_solver_desc* to, cvk_error* error)
{
    (void)s, (void)self, (void)from, (void)to, (void)error;
    return CVK_SUCCESS;
}

static cvk_result implicit_step_host(cvk_sim* s, void* self, uint32_t frames, cvk_error* error)
{
    (void)s, (void)self, (void)frames;
    return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "the implicit family has no host solver");
}

const cvk_family_api cvk_family_implicit = {
    .name = "implicit",
    .accepts = implicit_accepts,
    .create = implicit_create,
    .destroy = implicit_destroy,
    .add_passes = implicit_add_passes,
    .prepare = implicit_prepare,
    .switch_solver = implicit_switch_solver,
    .read_state = implicit_read_state,
    .write_state = implicit_write_state,
    .step_host = implicit_step_host,
    .snapshot_size = implicit_snapshot_size,
    .save_snapshot = implicit_save_snapshot,
    .load_snapshot = implicit_load_snapshot,
    .set_torn = implicit_set_torn,
};
