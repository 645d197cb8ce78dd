/* Reading and writing the state (user order at the API, internal order inside), and
   switching solvers at run time; both go through the solver family. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene.h"
#include "sim/sim.h"
#include "solvers/solver.h"

cvk_result cvk_sim_read_internal(cvk_sim* s, cvk_error* error)
{
    return s->family->read_state(s, s->family_state, s->scratch, s->scratch_v, error);
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
    r = s->family->write_state(s, s->family_state, s->scratch, velocity ? s->scratch_v : NULL,
                               error);
    if (r == CVK_SUCCESS) /* cloth-contact candidates of the old positions no longer hold */
        r = cvk_collide_positions_written(s, s->scratch, velocity ? s->scratch_v : NULL, error);
    if (r == CVK_SUCCESS)
        cvk_sim_watch_reset(s); /* a new state: a past divergence no longer holds */
    return r;
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

/* ---- changing the solver ------------------------------------------------------------ */

/* Everything that can fail on a valid description comes before the switch: a failure leaves
   the old solver running; only added pipelines (harmless) stay behind. */
/* A plan for `solver` with its pipelines ready and its queries made; nothing is left behind
   on failure but pipelines (harmless). */
static cvk_result make_plan_ready(cvk_sim* s, const cvk_family_api* family, void* self,
                                  const cvk_solver_desc* solver, cvk_plan* plan,
                                  cvk_sim_queries* queries, cvk_error* error)
{
    cvk_result r = cvk_sim_make_plan(s, family, self, solver, s->plan.workgroup_size,
                                     s->plan.max_groups, plan, error);
    if (r != CVK_SUCCESS)
        return r;
    r = cvk_sim_ready_pipelines(s, plan, error);
    if (r == CVK_SUCCESS)
        r = cvk_sim_create_queries(s, plan, queries, error);
    if (r != CVK_SUCCESS)
        cvk_plan_destroy(plan);
    return r;
}

static cvk_result prepare_switch(cvk_sim* s, const cvk_family_api* family, void* self,
                                 const cvk_solver_desc* solver, cvk_plan* plan,
                                 cvk_sim_queries* queries, cvk_error* error)
{
    cvk_result r = family->prepare(s, self, solver, error);
    return r == CVK_SUCCESS ? make_plan_ready(s, family, self, solver, plan, queries, error) : r;
}

/* The switch itself: the new family (if any) takes the place of the old one and receives the
   state as positions and velocities; within a family, the family moves its own state. */
static cvk_result commit_switch(cvk_sim* s, const cvk_family_api* family, void* self,
                                const cvk_solver_desc* solver, cvk_plan* plan,
                                cvk_sim_queries* queries, cvk_error* error)
{
    bool new_family = family != s->family;
    cvk_solver_desc from = s->solver;
    if (new_family) {
        s->family->destroy(s, s->family_state);
        s->family = family;
        s->family_state = self;
    }
    cvk_plan_destroy(&s->plan);
    s->plan = *plan;
    s->solver = *solver;
    s->host_timed = false;
    cvk_sim_use_queries(s, queries);
    cvk_result r = cvk_sim_record_frame_cmd(s, error);
    if (r == CVK_SUCCESS)
        r = new_family ? family->write_state(s, self, s->scratch, s->scratch_v, error)
                       : family->switch_solver(s, self, &from, solver, error);
    if (r == CVK_SUCCESS && s->device.unreset_queries)
        r = cvk_device_copy_from_staging(&s->device, NULL, 0, error); /* resets the new queries */
    return r;
}

cvk_result cvk_sim_replan(cvk_sim* s, cvk_error* error)
{
    cvk_queue_idle(s->device.context); /* the old queries may be in use */
    cvk_plan plan;
    cvk_sim_queries queries = {0};
    cvk_result r = make_plan_ready(s, s->family, s->family_state, &s->solver, &plan, &queries,
                                   error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_plan_destroy(&s->plan);
    s->plan = plan;
    cvk_sim_use_queries(s, &queries);
    r = cvk_sim_record_frame_cmd(s, error);
    if (r == CVK_SUCCESS && s->device.unreset_queries)
        r = cvk_device_copy_from_staging(&s->device, NULL, 0, error); /* resets the new queries */
    return r;
}

cvk_result cvk_sim_set_solver(cvk_sim* s, const cvk_solver_desc* solver, cvk_error* error)
{
    if (!s || !solver)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_set_solver needs a simulation and a solver description");
    cvk_scene_issue issue;
    if (!cvk_solver_desc_check(solver, &issue))
        return cvk_fail_issue(error, &issue);
    const char* no_grab = cvk_grab_unsupported(solver);
    if (no_grab && s->grab->held)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "cvk_sim_set_solver: a particle is grabbed and %s cannot hold it; "
                        "release it first (cvk_sim_release)", no_grab);
    if (!cvk_attachments_solver_check(solver, s->attach->attachment_count, &issue) ||
        !cvk_wind_solver_check(solver, s->aero->enabled, &issue))
        return cvk_fail_issue(error, &issue);
    const cvk_family_api* family = cvk_family_for(solver);
    if (!family)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "solver.method: no solver family for %s",
                        cvk_method_name(solver->method));
    if (solver->linear == CVK_LINEAR_GS_CPU && s->collide->colliding)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "solver.linear: gs-cpu (the host reference) does not handle contact; "
                        "use rbgs, jacobi or chebyshev in a scene with colliders or self-contact");
    if (solver->method != CVK_METHOD_PD && s->build.tether_anchor)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "solver.method: the %s method has no tethers; use pd in a scene with "
                        "tethers", cvk_method_name(solver->method));
    if (solver->method == CVK_METHOD_EXPLICIT && s->collide->colliding)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "solver.method: explicit does not handle contact; use pd in a scene "
                        "with colliders or self-contact");
    /* The substeps were split for the method the simulation was made with
       (cvk_collide_split_substeps): implicit's self-contact needs them shorter than pd's. */
    double move = s->collide->self ? cvk_collide_fastest_move(s, s->collide) : 0.0;
    if (solver->method == CVK_METHOD_IMPLICIT && move > cvk_collide_move_limit(true))
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "solver.method: implicit with self-contact needs substeps in which no "
                        "collider moves more than %.3g of the thickness (one moves %.3g here); "
                        "make the simulation with implicit, which splits them",
                        cvk_collide_move_limit(true), move);
    bool new_family = family != s->family;
    /* The state, for the new family: read before it is created, since creating one puts its
       state at rest at the build's positions (shared buffers included). */
    cvk_result r = new_family ? cvk_sim_read_internal(s, error) : CVK_SUCCESS;
    if (r != CVK_SUCCESS)
        return r;
    void* self = s->family_state;
    if (new_family)
        r = family->create(s, solver, &self, error);
    if (r == CVK_SUCCESS && new_family && s->tear->count > 0) {
        /* A new family's adjacency starts whole: it takes the torn state (the flags are
           unchanged by its creation). */
        uint32_t* alive = NULL;
        r = cvk_tear_copy_flags(s, &alive, error);
        if (r == CVK_SUCCESS)
            r = family->set_torn(s, self, alive, error);
        free(alive);
    }
    cvk_plan plan;
    cvk_sim_queries queries = {0};
    if (r == CVK_SUCCESS)
        r = prepare_switch(s, family, self, solver, &plan, &queries, error);
    if (r != CVK_SUCCESS) {
        if (new_family) {
            family->destroy(s, self); /* NULL when create failed */
            /* the old family gets its state back; the first failure is the one reported */
            cvk_error ignored;
            s->family->write_state(s, s->family_state, s->scratch, s->scratch_v, &ignored);
        }
        return r;
    }
    return commit_switch(s, family, self, solver, &plan, &queries, error);
}

cvk_solver_desc cvk_sim_get_solver(const cvk_sim* s)
{
    return s ? s->solver : (cvk_solver_desc){0};
}
