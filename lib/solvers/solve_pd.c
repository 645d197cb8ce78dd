/* The projective-dynamics family: its device objects (displacement iterates, adjacency,
   descriptor sets), its state in displacement form on the device or, for gs-cpu, on the
   host, and the host reference step. Its passes are in pd_passes.c. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "core/checked.h"
#include "core/error.h"
#include "solvers/family_objects.h"
#include "solvers/solve_pd.h"
#include "solvers/reference.h"
#include "topology/build.h"
#include "solvers/velocity_state.h"
#include "contact/collide.h"
#include "core/clock.h"
#include "features/aero.h"
#include "features/attach.h"
#include "features/grab.h"
#include "features/tear.h"

/* ---- device objects ------------------------------------------------------------------- */

/* The GPU adjacency packs a particle's springs four to a texel: per quad of slots one rgba32ui
   texel of neighbours and one of the bits of their k (both in `adjacency`), and one rgba32f
   texel of rest lengths L (`adjacency_rest`). A sweep then gathers two texels for four springs instead of
   four; on lavapipe a gather costs the same for one component as for four. */
static uint32_t adjacency_quads(uint32_t max_degree)
{
    return max_degree ? (max_degree + 3u) / 4u : 1u;
}

/* The family's buffers (family_objects.h); returns how many. */
static size_t buffer_table(const cvk_sim* s, cvk_pd* pd,
                           cvk_family_buffer out[CVK_FAMILY_MAX_BUFFERS])
{
    const cvk_build* b = &s->build;
    VkDeviceSize n16 = (VkDeviceSize)b->particle_count * 16u;
    VkDeviceSize nf = b->free_count ? b->free_count : 1;
    VkDeviceSize quads = (VkDeviceSize)adjacency_quads(b->max_degree) * nf;
    VkDeviceSize tethers = b->tether_anchor ? nf : 1; /* one texel keeps the view valid */
    VkBufferUsageFlags state = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                               VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    VkBufferUsageFlags motion = state | VK_BUFFER_USAGE_TRANSFER_SRC_BIT; /* read for velocities */
    VkBufferUsageFlags table = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    /* Tearing (tear.h) zeroes the k of broken springs in place. */
    VkBufferUsageFlags adjacency = table | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    VkBufferUsageFlags rest = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                              VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    VkBufferUsageFlags scalars = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                 VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                 VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    VkFormat vec4 = VK_FORMAT_R32G32B32A32_SFLOAT, uvec4 = VK_FORMAT_R32G32B32A32_UINT;
    cvk_memory_kind device = CVK_MEMORY_DEVICE;
    const cvk_family_buffer list[] = {
        {&pd->rest, nf * 16u, rest, device, "rest memory", NULL, 0},
        {&pd->u[0], n16, motion, device, "displacements", &pd->view_u[0], vec4},
        {&pd->u[1], n16, state, device, "displacements (second iterate)", &pd->view_u[1], vec4},
        {&pd->y, n16, state, device, "predicted displacements", &pd->view_y, vec4},
        {&pd->rhs, nf * 16u, state, device, "right-hand side", &pd->view_rhs, vec4},
        {&pd->adjacency, quads * 32u, adjacency, device, "adjacency", &pd->view_adjacency, uvec4},
        {&pd->adjacency_rest, quads * 16u, adjacency, device, "adjacency rest lengths",
         &pd->view_adjacency_rest, vec4},
        {&pd->tether_anchor, tethers * 16u, table, device, "tether pins",
         &pd->view_tether_anchor, uvec4},
        {&pd->tether_length, tethers * 16u, table, device, "tether lengths",
         &pd->view_tether_length, vec4},
        {&pd->sums, 4u * (CVK_PD_PARTIALS + nf), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, device,
         "residuals", NULL, 0},
        {&pd->scalars, sizeof(cvk_pd_scalars), scalars, CVK_MEMORY_HOST, "convergence state",
         NULL, 0},
    };
    _Static_assert(sizeof list / sizeof list[0] <= CVK_FAMILY_MAX_BUFFERS, "a longer table");
    memcpy(out, list, sizeof list);
    return sizeof list / sizeof list[0];
}

/* The adjacency as the GPU reads it: texel (2q) * nf + p: neighbours of slots 4q..4q+3,
   texel (2q + 1) * nf + p: bits of their k; L at texel q * nf + p. Slots past max_degree
   point at p itself with k = 0, and so do torn springs (alive[s] == 0; alive NULL: none),
   as tear.comp leaves them. */
cvk_result cvk_pd_upload_adjacency(cvk_sim* s, cvk_pd* pd, const uint32_t* alive, cvk_error* error)
{
    const cvk_build* b = &s->build;
    size_t nf = b->free_count, quads = adjacency_quads(b->max_degree);
    /* Without springs (max_degree 0) the one quad of padding is still written: the prediction's
       divergence watch reads slot 0 of every particle (shaders/solvers/predict.comp). */
    if (nf == 0)
        return CVK_SUCCESS;
    uint32_t* pairs = malloc(quads * nf * 8 * sizeof(uint32_t));
    float* rest = malloc(quads * nf * 4 * sizeof(float));
    cvk_result r = CVK_SUCCESS;
    if (!pairs || !rest)
        r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the adjacency");
    for (size_t q = 0; r == CVK_SUCCESS && q < quads; q++) {
        for (size_t p = 0; p < nf; p++) {
            uint32_t* neighbours = &pairs[4 * ((2 * q) * nf + p)];
            uint32_t* k_bits = &pairs[4 * ((2 * q + 1) * nf + p)];
            float* length = &rest[4 * (q * nf + p)];
            for (size_t j = 0; j < 4; j++) {
                size_t slot = 4 * q + j, e = slot * nf + p;
                bool real = slot < b->max_degree;
                bool torn = real && cvk_tear_entry_torn(b, alive, e);
                float k = real && !torn ? b->adj_k[e] : 0.0f;
                neighbours[j] = real ? b->adj_index[e] : (uint32_t)p;
                memcpy(&k_bits[j], &k, sizeof k);
                length[j] = real ? b->adj_rest[e] : 0.0f; /* torn: k = 0 is enough */
            }
        }
    }
    if (r == CVK_SUCCESS)
        r = cvk_device_upload(&s->device, &pd->adjacency, pairs, quads * nf * 8 * sizeof(uint32_t), error);
    if (r == CVK_SUCCESS)
        r = cvk_device_upload(&s->device, &pd->adjacency_rest, rest, quads * nf * 4 * sizeof(float), error);
    free(pairs);
    free(rest);
    return r;
}

/* The tethers as the GPU reads them: one uvec4 of pins and one vec4 of lengths per free
   particle (CVK_TETHER_SLOTS is 4); a missing tether points at the particle itself with a
   length nothing reaches, so the pass needs no test for it (pd_tether.comp). */
static cvk_result upload_tethers(cvk_sim* s, cvk_pd* pd, cvk_error* error)
{
    const cvk_build* b = &s->build;
    if (!b->tether_anchor)
        return CVK_SUCCESS;
    _Static_assert(CVK_TETHER_SLOTS == 4, "pd_tether.comp reads four tethers per particle");
    size_t count = (size_t)b->free_count * CVK_TETHER_SLOTS;
    uint32_t* anchor = malloc(count * sizeof *anchor);
    float* length = malloc(count * sizeof *length);
    cvk_result r = CVK_SUCCESS;
    if (!anchor || !length)
        r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the tethers");
    for (size_t i = 0; r == CVK_SUCCESS && i < count; i++) {
        bool none = b->tether_anchor[i] == CVK_TETHER_NONE;
        anchor[i] = none ? (uint32_t)(i / CVK_TETHER_SLOTS) : b->tether_anchor[i];
        length[i] = none ? FLT_MAX : b->tether_length[i];
    }
    if (r == CVK_SUCCESS)
        r = cvk_device_upload(&s->device, &pd->tether_anchor, anchor, count * sizeof *anchor, error);
    if (r == CVK_SUCCESS)
        r = cvk_device_upload(&s->device, &pd->tether_length, length, count * sizeof *length, error);
    free(anchor);
    free(length);
    return r;
}

#define TEXEL {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, 0}
#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
static const cvk_binding pd_bindings[CVK_PD_BINDING_COUNT] = {
    [CVK_PD_BINDING_SRC] = TEXEL,      [CVK_PD_BINDING_DST_READ] = TEXEL,
    [CVK_PD_BINDING_DST] = STORAGE,    [CVK_PD_BINDING_Y_READ] = TEXEL,
    [CVK_PD_BINDING_Y] = STORAGE,      [CVK_PD_BINDING_X_READ] = TEXEL,
    [CVK_PD_BINDING_X] = STORAGE,      [CVK_PD_BINDING_RHS_READ] = TEXEL,
    [CVK_PD_BINDING_RHS] = STORAGE,    [CVK_PD_BINDING_ADJACENCY] = TEXEL,
    [CVK_PD_BINDING_ADJACENCY_REST] = TEXEL, [CVK_PD_BINDING_WATCH] = STORAGE,
    [CVK_PD_BINDING_TETHER_ANCHOR] = TEXEL, [CVK_PD_BINDING_TETHER_LENGTH] = TEXEL,
    [CVK_PD_BINDING_EXTERNAL] = TEXEL, [CVK_PD_BINDING_CONVERGE] = STORAGE,
    [CVK_PD_BINDING_REST] = STORAGE,   [CVK_PD_BINDING_SRC_BUFFER] = STORAGE,
};
#undef TEXEL
#undef STORAGE

/* Set `set` reads U[src] and writes U[dst]. */
static void write_set(cvk_sim* s, cvk_pd* pd, cvk_pd_set set, uint32_t src, uint32_t dst)
{
    const cvk_resource res[CVK_PD_BINDING_COUNT] = {
        [CVK_PD_BINDING_SRC] = {.view = pd->view_u[src]},
        [CVK_PD_BINDING_DST_READ] = {.view = pd->view_u[dst]},
        [CVK_PD_BINDING_DST] = {.buffer = &pd->u[dst]},
        [CVK_PD_BINDING_Y_READ] = {.view = pd->view_y},
        [CVK_PD_BINDING_Y] = {.buffer = &pd->y},
        [CVK_PD_BINDING_X_READ] = {.view = s->view_positions},
        [CVK_PD_BINDING_X] = {.buffer = &s->positions},
        [CVK_PD_BINDING_RHS_READ] = {.view = pd->view_rhs},
        [CVK_PD_BINDING_RHS] = {.buffer = &pd->rhs},
        [CVK_PD_BINDING_ADJACENCY] = {.view = pd->view_adjacency},
        [CVK_PD_BINDING_ADJACENCY_REST] = {.view = pd->view_adjacency_rest},
        [CVK_PD_BINDING_WATCH] = {.buffer = &s->watch},
        [CVK_PD_BINDING_TETHER_ANCHOR] = {.view = pd->view_tether_anchor},
        [CVK_PD_BINDING_TETHER_LENGTH] = {.view = pd->view_tether_length},
        [CVK_PD_BINDING_EXTERNAL] = {.view = s->aero->view_external},
        [CVK_PD_BINDING_CONVERGE] = {.buffer = &pd->sums},
        [CVK_PD_BINDING_REST] = {.buffer = &pd->rest},
        [CVK_PD_BINDING_SRC_BUFFER] = {.buffer = &pd->u[src]},
    };
    cvk_descriptors_write(s->device.context, &pd->descriptors, set, res);
}

static const cvk_binding converge_bindings[CVK_PD_CONVERGE_BINDING_COUNT] = {
    [CVK_PD_CONVERGE_BINDING_SUMS] = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0},
    [CVK_PD_CONVERGE_BINDING_SCALARS] = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0},
};

/* The check's own set: the indirect commands are bound nowhere else, so only the decision's
   writes need a barrier to the indirect reads. */
static cvk_result create_converge_set(cvk_sim* s, cvk_pd* pd, cvk_error* error)
{
    cvk_result r = cvk_descriptors_create(s->device.context, converge_bindings,
                                          CVK_PD_CONVERGE_BINDING_COUNT, 1,
                                          VK_SHADER_STAGE_COMPUTE_BIT,
                                          sizeof(cvk_pd_converge_push),
                                          &pd->converge_descriptors, error);
    if (r != CVK_SUCCESS)
        return r;
    const cvk_resource res[CVK_PD_CONVERGE_BINDING_COUNT] = {
        [CVK_PD_CONVERGE_BINDING_SUMS] = {.buffer = &pd->sums},
        [CVK_PD_CONVERGE_BINDING_SCALARS] = {.buffer = &pd->scalars},
    };
    cvk_descriptors_write(s->device.context, &pd->converge_descriptors, 0, res);
    return CVK_SUCCESS;
}

static cvk_result create_sets(cvk_sim* s, cvk_pd* pd, cvk_error* error)
{
    /* Set 1 is the contact set: the sweeps resolve contact (shaders/solvers/pd_contact.glsl). */
    cvk_result r = cvk_descriptors_create_with(s->device.context, pd_bindings, CVK_PD_BINDING_COUNT,
                                               CVK_PD_SET_COUNT, VK_SHADER_STAGE_COMPUTE_BIT,
                                               sizeof(cvk_pd_fused_push), &s->collide->set_layout, 1,
                                               &pd->descriptors, error);
    if (r != CVK_SUCCESS)
        return r;
    write_set(s, pd, CVK_PD_SET_U0_TO_U1, 0, 1);
    write_set(s, pd, CVK_PD_SET_U1_TO_U0, 1, 0);
    write_set(s, pd, CVK_PD_SET_U0_TO_U0, 0, 0);
    return create_converge_set(s, pd, error);
}


/* ---- state --------------------------------------------------------------------------- */

/* The gs-cpu state; allocated once, also when a simulation switches to gs-cpu later. */
static cvk_result pd_prepare(cvk_sim* s, void* self, const cvk_solver_desc* solver,
                             cvk_error* error)
{
    cvk_pd* pd = self;
    if (pd->hx || solver->linear != CVK_LINEAR_GS_CPU)
        return CVK_SUCCESS;
    size_t n = s->build.particle_count;
    pd->hx = malloc(3 * n * sizeof(double));
    pd->hprev = malloc(3 * n * sizeof(double));
    pd->hy = malloc(3 * n * sizeof(double));
    pd->hrhs = malloc(4 * n * sizeof(double));
    pd->hrest = calloc(3 * n, sizeof(double));
    if (!pd->hx || !pd->hprev || !pd->hy || !pd->hrhs || !pd->hrest)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "out of host memory for the gs-cpu solver state");
    if (s->tear->count == 0)
        return CVK_SUCCESS;
    /* Intact; a switch from the device brings the device's torn state (pd_switch_solver). */
    const cvk_build* b = &s->build;
    size_t entries = (size_t)b->max_degree * b->free_count;
    pd->h_alive = cvk_malloc_array(b->spring_count, sizeof *pd->h_alive);
    pd->h_adj_k = cvk_malloc_array(entries ? entries : 1, sizeof *pd->h_adj_k);
    if (!pd->h_alive || !pd->h_adj_k)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "out of host memory for the gs-cpu solver's spring flags");
    for (uint32_t i = 0; i < b->spring_count; i++)
        pd->h_alive[i] = 1;
    if (entries)
        memcpy(pd->h_adj_k, b->adj_k, entries * sizeof *pd->h_adj_k);
    return CVK_SUCCESS;
}

cvk_result cvk_pd_set_torn(cvk_sim* s, void* self, const uint32_t* alive, cvk_error* error)
{
    cvk_pd* pd = self;
    const cvk_build* b = &s->build;
    cvk_result r = cvk_device_upload(&s->device, &s->spring_alive, alive,
                                  (size_t)b->spring_count * sizeof *alive, error);
    if (r == CVK_SUCCESS)
        r = cvk_pd_upload_adjacency(s, pd, alive, error);
    if (r != CVK_SUCCESS || !pd->h_alive)
        return r;
    cvk_tear_host_adjacency(b, alive, pd->h_adj_k);
    memcpy(pd->h_alive, alive, (size_t)b->spring_count * sizeof *alive);
    return CVK_SUCCESS;
}

/* The rest memory from `rest` (3 floats per particle, internal order; NULL: 0) on the side
   that holds the state. */
static cvk_result set_rest(cvk_sim* s, cvk_pd* pd, const float* rest, cvk_error* error)
{
    const cvk_build* b = &s->build;
    if (pd->host) {
        for (size_t i = 0; i < 3 * (size_t)b->particle_count; i++)
            pd->hrest[i] = rest && i < 3 * (size_t)b->free_count ? (double)rest[i] : 0.0;
        return CVK_SUCCESS;
    }
    if (!rest)
        return cvk_device_clear_buffer(&s->device, &pd->rest, error);
    float* r4 = s->device.staging.mapped; /* the rest memory is at most one vec4 per particle */
    memset(r4, 0, pd->rest.size);
    for (size_t p = 0; p < b->free_count; p++)
        for (int c = 0; c < 3; c++)
            r4[4 * p + c] = rest[3 * p + c];
    cvk_staging_copy job = {&pd->rest, 0, 0, pd->rest.size};
    return cvk_device_copy_from_staging(&s->device, &job, 1, error);
}

/* Sets positions `xyz` and last displacements `disp` (internal order, 3 floats each; disp NULL
   means at rest) and the rest memory (3 floats each; NULL: 0, as wherever positions come from
   the host). At rest is zero velocity at this instant, so the first Verlet step moves a
   free particle by ½ h² g, as x(t) = x0 + ½ g t² requires: in displacement form a last
   displacement of −½ h² g. Pinned particles never move: their displacement is 0. */
static cvk_result set_state(cvk_sim* s, cvk_pd* pd, const float* xyz, const float* disp,
                            const float* rest, cvk_error* error)
{
    const cvk_ref_params ref = cvk_ref_params_of(&s->params);
    cvk_result r = set_rest(s, pd, rest, error); /* first: it goes through the staging buffer */
    if (r != CVK_SUCCESS)
        return r;
    const cvk_build* b = &s->build;
    uint32_t n = b->particle_count;
    float* x = s->device.staging.mapped;
    float* u = x + 4 * (size_t)n;
    for (uint32_t p = 0; p < n; p++) {
        for (int c = 0; c < 3; c++) {
            size_t i = 3 * (size_t)p + c;
            double last = 0.0;
            if (p < b->free_count)
                last = disp ? (double)disp[i] : -0.5 * ref.gravity_h2[c];
            x[4 * p + c] = xyz[i];
            u[4 * p + c] = (float)last;
            if (pd->host) {
                pd->hx[i] = xyz[i];
                pd->hprev[i] = xyz[i] - last;
                pd->hy[i] = xyz[i];
            }
        }
        x[4 * p + 3] = (float)(b->mass[p] * ref.inv_h2); /* m/h², read by predict */
        u[4 * p + 3] = 0.0f;
    }
    return cvk_pd_upload_staged_state(s, pd, error);
}

cvk_result cvk_pd_upload_staged_state(cvk_sim* s, cvk_pd* pd, cvk_error* error)
{
    VkDeviceSize n16 = (VkDeviceSize)s->build.particle_count * 16u;
    cvk_staging_copy jobs[] = {
        {&s->positions, 0, 0, n16},
        {&pd->u[0], n16, 0, n16},
        {&pd->u[1], n16, 0, n16},
        {&pd->y, n16, 0, n16},
    };
    return cvk_device_copy_from_staging(&s->device, jobs, 4, error);
}

/* The rest memory into `rest` (3 floats per particle, internal order; pinned: 0), from
   whichever side holds the state. */
static cvk_result read_rest(cvk_sim* s, cvk_pd* pd, float* rest, cvk_error* error)
{
    const cvk_build* b = &s->build;
    size_t n = b->particle_count;
    if (pd->host) {
        for (size_t i = 0; i < 3 * n; i++)
            rest[i] = (float)pd->hrest[i];
        return CVK_SUCCESS;
    }
    float* r4 = malloc(pd->rest.size);
    if (!r4)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the rest memory");
    cvk_result r = cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd, &pd->rest, r4,
                                       pd->rest.size, error);
    for (size_t p = 0; r == CVK_SUCCESS && p < n; p++)
        for (int c = 0; c < 3; c++)
            rest[3 * p + c] = p < b->free_count ? r4[4 * p + c] : 0.0f;
    free(r4);
    return r;
}

/* Positions and last displacements, from whichever side holds the state. */
static cvk_result read_displacement_state(cvk_sim* s, cvk_pd* pd, float* xyz, float* disp,
                                          cvk_error* error)
{
    size_t n = s->build.particle_count;
    if (pd->host) {
        for (size_t i = 0; i < 3 * n; i++) {
            xyz[i] = (float)pd->hx[i];
            disp[i] = (float)(pd->hx[i] - pd->hprev[i]);
        }
        return CVK_SUCCESS;
    }
    return cvk_vstate_read(s, pd->readback_cmd, xyz, disp, error); /* positions, then u[0] */
}

/* Verlet's velocity at the end of a substep from its displacement u = x_n − x_{n−1}:
   v = u / h + h g / 2, so a particle at rest (u = −½ h² g) has v = 0. Pinned: u / h, which is
   0 but for attached particles (their motion over the substep: lib/features/attach.h). */
static void velocities_of(const cvk_sim* s, const float* u, float* v)
{
    const cvk_ref_params ref = cvk_ref_params_of(&s->params);
    double h = s->params.dt;
    const cvk_build* b = &s->build;
    for (uint32_t p = 0; p < b->particle_count; p++)
        for (int c = 0; c < 3; c++) {
            size_t i = 3 * (size_t)p + c;
            v[i] = p < b->free_count ? (float)(((double)u[i] + 0.5 * ref.gravity_h2[c]) / h)
                                     : (float)((double)u[i] / h);
        }
}

/* The inverse of velocities_of: u = v h − ½ h² g. */
static void displacements_of(const cvk_sim* s, const float* v, float* u)
{
    const cvk_ref_params ref = cvk_ref_params_of(&s->params);
    double h = s->params.dt;
    const cvk_build* b = &s->build;
    for (uint32_t p = 0; p < b->particle_count; p++)
        for (int c = 0; c < 3; c++) {
            size_t i = 3 * (size_t)p + c;
            u[i] = p < b->free_count ? (float)((double)v[i] * h - 0.5 * ref.gravity_h2[c])
                                     : 0.0f;
        }
}

static cvk_result pd_read_state(cvk_sim* s, void* self, float* xyz, float* velocity,
                                cvk_error* error)
{
    cvk_pd* pd = self;
    size_t n = s->build.particle_count;
    float* x = xyz ? xyz : malloc(3 * n * sizeof(float));
    if (!x)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for positions");
    cvk_result r = read_displacement_state(s, pd, x, pd->scratch_u, error);
    if (r == CVK_SUCCESS && velocity)
        velocities_of(s, pd->scratch_u, velocity);
    if (x != xyz)
        free(x);
    return r;
}

static cvk_result pd_write_state(cvk_sim* s, void* self, const float* xyz, const float* velocity,
                                 cvk_error* error)
{
    cvk_pd* pd = self;
    if (velocity)
        displacements_of(s, velocity, pd->scratch_u);
    return set_state(s, pd, xyz, velocity ? pd->scratch_u : NULL, NULL, error);
}

/* The state moves between host and device only when the solver does. */
static cvk_result pd_switch_solver(cvk_sim* s, void* self, const cvk_solver_desc* from,
                                   const cvk_solver_desc* to, cvk_error* error)
{
    const cvk_ref_params ref = cvk_ref_params_of(&s->params);
    cvk_pd* pd = self;
    bool host = to->linear == CVK_LINEAR_GS_CPU;
    /* A checked solve has no rest memory (solve_pd.h): it starts again from 0 after one. */
    if (!host && to->tolerance > 0.0f && ref.rest_rate > 0.0) {
        cvk_result r = cvk_device_clear_buffer(&s->device, &pd->rest, error);
        if (r != CVK_SUCCESS)
            return r;
    }
    if (host == (from->linear == CVK_LINEAR_GS_CPU))
        return CVK_SUCCESS;
    cvk_result r = read_rest(s, pd, s->scratch_v, error);
    if (r == CVK_SUCCESS)
        r = read_displacement_state(s, pd, s->scratch, pd->scratch_u, error);
    pd->host = host;
    if (r == CVK_SUCCESS)
        r = set_state(s, pd, s->scratch, pd->scratch_u, s->scratch_v, error);
    if (r != CVK_SUCCESS || s->tear->count == 0)
        return r;
    /* The torn state follows: the device's flags are current (gs-cpu uploads its own after
       every step), and both sides' adjacency is rebuilt from them. */
    uint32_t* alive = NULL;
    r = cvk_tear_copy_flags(s, &alive, error);
    if (r == CVK_SUCCESS)
        r = cvk_pd_set_torn(s, pd, alive, error);
    free(alive);
    return r;
}

/* ---- the host reference step ---------------------------------------------------------- */

cvk_result cvk_pd_upload_host_positions(cvk_sim* s, cvk_pd* pd, cvk_error* error)
{
    float* x = s->device.staging.mapped;
    for (size_t p = 0; p < s->build.particle_count; p++) {
        for (int c = 0; c < 3; c++)
            x[4 * p + c] = (float)pd->hx[3 * p + c];
        x[4 * p + 3] = 0.0f;
    }
    cvk_staging_copy job = {&s->positions, 0, 0, (VkDeviceSize)s->build.particle_count * 16u};
    return cvk_device_copy_from_staging(&s->device, &job, 1, error);
}

static cvk_result pd_step_host(cvk_sim* s, void* self, uint32_t frames, cvk_error* error)
{
    const cvk_ref_params ref = cvk_ref_params_of(&s->params);
    cvk_pd* pd = self;
    uint32_t predict = cvk_plan_find_pass(&s->plan, "predict");
    uint32_t solve = cvk_plan_find_pass(&s->plan, "solve");
    uint32_t tear = cvk_plan_find_pass(&s->plan, "tear");
    /* With tearing the solve reads the host's adjacency, torn springs at k = 0. */
    cvk_build view = s->build;
    if (pd->h_adj_k)
        view.adj_k = pd->h_adj_k;
    cvk_solver_desc solver = cvk_solver_desc_resolve(&s->solver); /* max_iterations: outer */
    for (uint32_t f = 0; f < frames; f++) {
        double predict_ms = 0.0, solve_ms = 0.0, tear_ms = 0.0;
        for (uint32_t sub = 0; sub < s->params.substeps; sub++) {
            double t0 = cvk_now_ms();
            cvk_ref_predict(&view, &ref, pd->hx, pd->hprev, pd->hy);
            cvk_ref_rest_start(&view, &ref, pd->hrest, pd->hx);
            double t1 = cvk_now_ms();
            cvk_ref_solve_gauss_seidel(&view, &ref, &solver, pd->hy, pd->hx, pd->hrhs);
            cvk_ref_rest_update(&view, &ref, pd->hx, pd->hy, pd->hrest);
            double t2 = cvk_now_ms();
            if (pd->h_alive)
                cvk_tear_host(s, pd->hx, pd->h_alive, pd->h_adj_k);
            predict_ms += t1 - t0;
            solve_ms += t2 - t1;
            tear_ms += cvk_now_ms() - t2;
        }
        if (predict < CVK_MAX_PASSES)
            s->host_pass_ms[predict] = predict_ms;
        if (solve < CVK_MAX_PASSES)
            s->host_pass_ms[solve] = solve_ms;
        if (tear < CVK_MAX_PASSES)
            s->host_pass_ms[tear] = tear_ms;
        s->host_timed = true;
    }
    cvk_result r = cvk_pd_upload_host_positions(s, pd, error);
    if (r == CVK_SUCCESS && pd->h_alive) /* for the mesh, the statistics and snapshots */
        r = cvk_device_upload(&s->device, &s->spring_alive, pd->h_alive,
                           (size_t)s->build.spring_count * sizeof *pd->h_alive, error);
    return r;
}

void cvk_pd_stats(const cvk_sim* s, cvk_sim_stats* st)
{
    const cvk_pd* pd = s->family == &cvk_family_pd ? s->family_state : NULL;
    if (!pd)
        return;
    /* The current plan checks when it has the pass (a failed switch leaves the plan as is). */
    if (cvk_plan_find_pass(&s->plan, "convergence") != UINT32_MAX) {
        cvk_pd_scalars scalars;
        memcpy(&scalars, pd->scalars.mapped, sizeof scalars);
        st->solver_iterations = scalars.frame_iterations;
        st->solver_iterations_total = scalars.total_iterations;
        st->solver_residual = scalars.residual;
        return;
    }
    cvk_solver_desc solver = cvk_solver_desc_resolve(&s->solver);
    uint64_t per_frame = (uint64_t)solver.outer_iterations * solver.inner_iterations *
                         s->params.substeps;
    st->solver_iterations = s->frames ? (uint32_t)per_frame : 0;
    st->solver_iterations_total = per_frame * s->frames;
}

/* ---- the family ------------------------------------------------------------------------ */

static bool pd_accepts(const cvk_solver_desc* solver)
{
    return solver->method == CVK_METHOD_PD;
}

static void pd_destroy(cvk_sim* s, void* self)
{
    cvk_pd* pd = self;
    if (!pd)
        return;
    cvk_family_buffer list[CVK_FAMILY_MAX_BUFFERS];
    size_t count = buffer_table(s, pd, list);
    cvk_descriptors* sets[] = {&pd->descriptors, &pd->converge_descriptors};
    cvk_family_destroy(s, sets, 2, list, count, pd->readback_cmd);
    free(pd->hx);
    free(pd->hprev);
    free(pd->hy);
    free(pd->hrhs);
    free(pd->hrest);
    free(pd->h_alive);
    free(pd->h_adj_k);
    free(pd->scratch_u);
    free(pd);
}

static cvk_result pd_create(cvk_sim* s, const cvk_solver_desc* solver, void** self,
                            cvk_error* error)
{
    *self = NULL;
    cvk_pd* pd = calloc(1, sizeof *pd);
    if (!pd)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the solver");
    pd->rho_estimate = -1.0;
    pd->host = solver->linear == CVK_LINEAR_GS_CPU;
    pd->scratch_u = malloc(3 * (size_t)s->build.particle_count * sizeof(float));
    cvk_result r = pd->scratch_u ? CVK_SUCCESS
                                 : cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                                            "out of host memory for positions");
    if (r == CVK_SUCCESS)
        r = pd_prepare(s, pd, solver, error);
    cvk_family_buffer list[CVK_FAMILY_MAX_BUFFERS];
    size_t count = buffer_table(s, pd, list);
    if (r == CVK_SUCCESS)
        r = cvk_family_create(s, list, count, &pd->readback_cmd, error);
    if (r == CVK_SUCCESS)
        memset(pd->scalars.mapped, 0, sizeof(cvk_pd_scalars));
    if (r == CVK_SUCCESS)
        r = create_sets(s, pd, error);
    if (r == CVK_SUCCESS) { /* the passes other modules add to this family's substep */
        cvk_attach_bind(s, CVK_ATTACH_FOR_PD, &pd->u[0], &pd->u[1]);
        cvk_grab_bind(s, &pd->u[0], &pd->u[1], &pd->y);
        cvk_aero_bind(s, pd->view_u[0]);
        cvk_tear_bind(s, CVK_TEAR_FOR_PD, &pd->adjacency);
    }
    if (r == CVK_SUCCESS)
        r = cvk_pd_upload_adjacency(s, pd, NULL, error);
    if (r == CVK_SUCCESS)
        r = upload_tethers(s, pd, error);
    if (r == CVK_SUCCESS)
        r = set_state(s, pd, s->build.position, NULL, NULL, error);
    if (r == CVK_SUCCESS)
        r = cvk_vstate_record_readback(s, pd->readback_cmd, &pd->u[0], error);
    if (r != CVK_SUCCESS) {
        pd_destroy(s, pd);
        return r;
    }
    *self = pd;
    return CVK_SUCCESS;
}

const cvk_family_api cvk_family_pd = {
    .name = "pd",
    .accepts = pd_accepts,
    .create = pd_create,
    .destroy = pd_destroy,
    .add_passes = cvk_pd_add_passes,
    .fuse_refusal = cvk_pd_plan_fuse_refusal,
    .prepare = pd_prepare,
    .switch_solver = pd_switch_solver,
    .read_state = pd_read_state,
    .write_state = pd_write_state,
    .step_host = pd_step_host,
    .snapshot_size = cvk_pd_snapshot_size,
    .save_snapshot = cvk_pd_save_snapshot,
    .load_snapshot = cvk_pd_load_snapshot,
    .set_torn = cvk_pd_set_torn,
};
