/* Solver families behind one interface (Box2D's solver stages, sokol's function tables): a
   family owns the device objects and host state of one way of solving a substep, adds its
   passes to the plan, converts its state to and from positions and velocities, and may step
   on the host. The simulation (sim/sim.c) knows families only through this table, so a new
   one (implicit Euler, explicit integrators) is a new file in solvers/ and one line in the
   table of solvers/solver.c. */
#ifndef CVK_FAMILY_H
#define CVK_FAMILY_H

#include "plan/state.h"

typedef struct cvk_family_api {
    const char* name;
    /* Whether this family solves `solver` (by its method and linear solver). */
    bool (*accepts)(const cvk_solver_desc* solver);
    /* Creates what the family needs on `sim` (buffers, descriptor sets, host arrays for
       `solver`) and returns its state in *self; the state is at rest at the build's
       positions. On failure it leaves nothing to destroy. */
    cvk_result (*create)(cvk_sim* sim, const cvk_solver_desc* solver, void** self,
                         cvk_error* error);
    void (*destroy)(cvk_sim* sim, void* self);
    /* Adds one substep's passes for `solver` to `plan` (registering its pass names even when
       it adds no op, so timings keep their names), or marks the plan as a host plan. */
    cvk_result (*add_passes)(cvk_sim* sim, void* self, const cvk_solver_desc* solver,
                             cvk_plan* plan, cvk_error* error);
    /* Why a plan does not fuse `solver`'s passes (solver.fuse), or NULL where it does; asked
       before any pass is added, so that the detection's hash builds fuse with the solve
       (cvk_plan.fused). NULL member: the family never fuses. */
    const char* (*fuse_refusal)(const cvk_sim* sim, const cvk_solver_desc* solver);
    /* Readies `solver` before a switch to it (host arrays); may fail, changing nothing. */
    cvk_result (*prepare)(cvk_sim* sim, void* self, const cvk_solver_desc* solver,
                          cvk_error* error);
    /* Moves the family's state from where `from` keeps it to where `to` does (host or
       device) when a switch needs it; `to` is already the simulation's solver. */
    cvk_result (*switch_solver)(cvk_sim* sim, void* self, const cvk_solver_desc* from,
                                const cvk_solver_desc* to, cvk_error* error);
    /* The state as positions and velocities (internal order, 3 floats per particle, either
       may be NULL), and back (velocity NULL: at rest). */
    cvk_result (*read_state)(cvk_sim* sim, void* self, float* xyz, float* velocity,
                             cvk_error* error);
    cvk_result (*write_state)(cvk_sim* sim, void* self, const float* xyz, const float* velocity,
                              cvk_error* error);
    /* Steps `frames` frames on the host (plan->host), then uploads the positions. */
    cvk_result (*step_host)(cvk_sim* sim, void* self, uint32_t frames, cvk_error* error);
    /* The family's raw state for exact snapshots (snapshot.c adds the header): its size in
       bytes under the current solver, a copy of it into `data` (that many bytes), and back.
       The bytes are the state as the family holds it, so stepping on from a loaded copy gives
       the same bits; load refuses bytes it cannot take (another layout, another size) with a
       sentence naming cvk_sim_load_snapshot, changing nothing. */
    uint64_t (*snapshot_size)(const cvk_sim* sim, const void* self);
    cvk_result (*save_snapshot)(cvk_sim* sim, void* self, void* data, cvk_error* error);
    cvk_result (*load_snapshot)(cvk_sim* sim, void* self, const void* data, uint64_t size,
                                cvk_error* error);
    /* Takes the torn state `alive` (uint per spring of the build, 0 = torn; lib/features/tear.h): the
       simulation's spring flags and the family's adjacency without the dead springs. */
    cvk_result (*set_torn)(cvk_sim* sim, void* self, const uint32_t* alive, cvk_error* error);
} cvk_family_api;

#endif
