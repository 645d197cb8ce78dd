/* Dragging a particle: the grab buffer, its pass, and cvk_sim_grab / cvk_sim_release
   (lib/grab.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "error.h"
#include "grab.h"
#include "shared/layout.h"
#include "sim.h"

#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
static const cvk_binding grab_bindings[CVK_GRAB_BINDING_COUNT] = {
    [CVK_GRAB_BINDING_GRAB] = STORAGE,      [CVK_GRAB_BINDING_WATCH] = STORAGE,
    [CVK_GRAB_BINDING_POSITIONS] = STORAGE, [CVK_GRAB_BINDING_Y] = STORAGE,
    [CVK_GRAB_BINDING_U0] = STORAGE,        [CVK_GRAB_BINDING_U1] = STORAGE,
};
#undef STORAGE

static void write_set(cvk_sim* s)
{
    cvk_grab* g = &s->grab;
    const cvk_resource res[CVK_GRAB_BINDING_COUNT] = {
        [CVK_GRAB_BINDING_GRAB] = {.buffer = &g->state},
        [CVK_GRAB_BINDING_WATCH] = {.buffer = &s->watch},
        [CVK_GRAB_BINDING_POSITIONS] = {.buffer = &s->positions},
        [CVK_GRAB_BINDING_Y] = {.buffer = g->y},
        [CVK_GRAB_BINDING_U0] = {.buffer = g->u0},
        [CVK_GRAB_BINDING_U1] = {.buffer = g->u1},
    };
    cvk_descriptors_write(s->context, &g->descriptors, 0, res);
}

void cvk_grab_bind(cvk_sim* s, const cvk_buffer* u0, const cvk_buffer* u1, const cvk_buffer* y)
{
    cvk_grab* g = &s->grab;
    g->u0 = u0;
    g->u1 = u1;
    g->y = y;
    if (g->planned)
        write_set(s);
}

cvk_result cvk_grab_enable(cvk_sim* s, cvk_error* error)
{
    cvk_grab* g = &s->grab;
    if (g->planned)
        return CVK_SUCCESS;
    if (!g->u0 || !g->u1 || !g->y)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "cvk_sim_grab: this solver does not move grabbed particles");
    cvk_result r = cvk_buffer_create(s->context, sizeof(cvk_gpu_grab),
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, CVK_MEMORY_HOST, "grab",
                                     &g->state, error);
    if (r == CVK_SUCCESS)
        r = cvk_descriptors_create(s->context, grab_bindings, CVK_GRAB_BINDING_COUNT, 1,
                                   VK_SHADER_STAGE_COMPUTE_BIT, sizeof(cvk_grab_push),
                                   &g->descriptors, error);
    if (r != CVK_SUCCESS) {
        cvk_grab_destroy(s);
        return r;
    }
    memset(g->state.mapped, 0, sizeof(cvk_gpu_grab)); /* nothing grabbed */
    write_set(s);
    g->planned = true;
    return CVK_SUCCESS;
}

void cvk_grab_destroy(cvk_sim* s)
{
    cvk_grab* g = &s->grab;
    cvk_descriptors_destroy(s->context, &g->descriptors);
    cvk_buffer_destroy(s->context, &g->state);
    g->planned = false;
}

void cvk_grab_add_op(cvk_sim* s, cvk_plan* plan, const char* note)
{
    if (!s->grab.planned)
        return;
    cvk_grab_push push = {plan->substeps, CVK_GRAB_WEIGHT, 0, 0};
    uint32_t pass = cvk_plan_pass(plan, "grab");
    cvk_op* op = cvk_plan_dispatch(plan, pass, CVK_PIPE_GRAB, s->grab.descriptors.pipeline_layout,
                                   s->grab.descriptors.sets[0], CVK_DOMAIN_PARTICLES, 0, 1, &push,
                                   sizeof push);
    if (op) {
        op->groups = 1;
        snprintf(op->note, sizeof op->note, "%s", note);
    }
}

const char* cvk_grab_unsupported(const cvk_solver_desc* solver)
{
    if (solver->method != CVK_METHOD_PD)
        return solver->method == CVK_METHOD_IMPLICIT ? "the implicit method"
                                                     : "the explicit method";
    if (solver->linear == CVK_LINEAR_GS_CPU)
        return "gs-cpu (the host reference)";
    return NULL;
}

/* ---- the public calls ---------------------------------------------------------------- */

cvk_result cvk_sim_particle_internal(const cvk_sim* s, cvk_particle particle, const char* call,
                                     uint32_t* out, cvk_error* error)
{
    const cvk_build* b = &s->build;
    if (particle.cloth >= b->cloth_count)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: cloth %u does not exist (the scene has %u cloth%s)", call,
                        particle.cloth, b->cloth_count, b->cloth_count == 1 ? "" : "s");
    const cvk_cloth_range* c = &b->cloths[particle.cloth];
    if (particle.index >= c->particle_count)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: particle %u of cloth %u (\"%s\") does not exist (it has %u)", call,
                        particle.index, particle.cloth, c->name, c->particle_count);
    *out = b->internal_of[c->first_user + particle.index];
    return CVK_SUCCESS;
}

cvk_result cvk_sim_grab(cvk_sim* s, cvk_particle particle, const float target[3],
                        cvk_error* error)
{
    if (!s || !target)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_grab needs a simulation and a target");
    const char* unsupported = cvk_grab_unsupported(&s->solver);
    if (unsupported)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "cvk_sim_grab: %s cannot hold a grabbed particle; use the pd method with "
                        "rbgs, jacobi or chebyshev", unsupported);
    if (!isfinite(target[0]) || !isfinite(target[1]) || !isfinite(target[2]))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_grab: the target must be finite, got [%g, %g, %g]",
                        (double)target[0], (double)target[1], (double)target[2]);
    uint32_t p;
    cvk_result r = cvk_sim_particle_internal(s, particle, "cvk_sim_grab", &p, error);
    if (r != CVK_SUCCESS)
        return r;
    if (p >= s->build.free_count)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_grab: particle %u of cloth %u (\"%s\") is pinned; only free "
                        "particles can be grabbed", particle.index, particle.cloth,
                        s->build.cloths[particle.cloth].name);
    if (!s->grab.planned) {
        r = cvk_grab_enable(s, error);
        if (r == CVK_SUCCESS)
            r = cvk_sim_replan(s, error);
        if (r != CVK_SUCCESS) {
            if (cvk_plan_find_pass(&s->plan, "grab") == UINT32_MAX)
                cvk_grab_destroy(s); /* the old plan was kept: nothing uses the pass's set */
            return r;
        }
    }
    cvk_gpu_grab grab = {{target[0], target[1], target[2], 0.0f}, p, 1u, 0, 0};
    memcpy(s->grab.state.mapped, &grab, sizeof grab);
    return CVK_SUCCESS;
}

void cvk_sim_release(cvk_sim* s)
{
    if (!s || !s->grab.planned)
        return;
    cvk_gpu_grab none = {{0.0f, 0.0f, 0.0f, 0.0f}, 0, 0u, 0, 0};
    memcpy(s->grab.state.mapped, &none, sizeof none);
}
