/* Dragging a particle: the grab buffer and its pass (features/grab.h); the public calls that
   move it are in sim/sim_grab.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "features/grab.h"
#include "shared/layout.h"
#include "plan/state.h"

#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
static const cvk_binding grab_bindings[CVK_GRAB_BINDING_COUNT] = {
    [CVK_GRAB_BINDING_GRAB] = STORAGE,      [CVK_GRAB_BINDING_WATCH] = STORAGE,
    [CVK_GRAB_BINDING_POSITIONS] = STORAGE, [CVK_GRAB_BINDING_Y] = STORAGE,
    [CVK_GRAB_BINDING_U0] = STORAGE,        [CVK_GRAB_BINDING_U1] = STORAGE,
};
#undef STORAGE

static void write_set(cvk_sim* s)
{
    cvk_grab* g = s->grab;
    const cvk_resource res[CVK_GRAB_BINDING_COUNT] = {
        [CVK_GRAB_BINDING_GRAB] = {.buffer = &g->state},
        [CVK_GRAB_BINDING_WATCH] = {.buffer = &s->watch},
        [CVK_GRAB_BINDING_POSITIONS] = {.buffer = &s->positions},
        [CVK_GRAB_BINDING_Y] = {.buffer = g->y},
        [CVK_GRAB_BINDING_U0] = {.buffer = g->u0},
        [CVK_GRAB_BINDING_U1] = {.buffer = g->u1},
    };
    cvk_descriptors_write(s->device.context, &g->descriptors, 0, res);
}

void cvk_grab_bind(cvk_sim* s, const cvk_buffer* u0, const cvk_buffer* u1, const cvk_buffer* y)
{
    cvk_grab* g = s->grab;
    g->u0 = u0;
    g->u1 = u1;
    g->y = y;
    if (g->planned)
        write_set(s);
}

cvk_result cvk_grab_enable(cvk_sim* s, cvk_error* error)
{
    cvk_grab* g = s->grab;
    if (g->planned)
        return CVK_SUCCESS;
    if (!g->u0 || !g->u1 || !g->y)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "cvk_sim_grab: this solver does not move grabbed particles");
    cvk_result r = cvk_buffer_create(s->device.context, CVK_GRAB_BYTES,
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, CVK_MEMORY_HOST, "grab",
                                     &g->state, error);
    if (r == CVK_SUCCESS)
        r = cvk_descriptors_create(s->device.context, grab_bindings, CVK_GRAB_BINDING_COUNT, 1,
                                   VK_SHADER_STAGE_COMPUTE_BIT, sizeof(cvk_grab_push),
                                   &g->descriptors, error);
    if (r != CVK_SUCCESS) {
        cvk_grab_destroy(s);
        return r;
    }
    memset(g->state.mapped, 0, CVK_GRAB_BYTES); /* nothing grabbed */
    g->held = false;
    write_set(s);
    g->planned = true;
    return CVK_SUCCESS;
}

void cvk_grab_destroy(cvk_sim* s)
{
    cvk_grab* g = s->grab;
    cvk_descriptors_destroy(s->device.context, &g->descriptors);
    cvk_buffer_destroy(s->device.context, &g->state);
    g->planned = false;
}

void cvk_grab_add_op(cvk_sim* s, cvk_plan* plan, const char* note)
{
    if (!s->grab->planned)
        return;
    cvk_grab_push push = {s->params.substeps, CVK_GRAB_WEIGHT, 0, 0};
    uint32_t pass = cvk_plan_pass(plan, "grab");
    cvk_op* op = cvk_plan_dispatch(plan, pass, CVK_PIPE_GRAB, s->grab->descriptors.pipeline_layout,
                                   s->grab->descriptors.sets[0], CVK_DOMAIN_PARTICLES, 0, 1, &push,
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
