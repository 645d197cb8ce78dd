/* The simulation object's life and the functions the sim/ files share. The state itself
   (struct cvk_sim) is in plan/state.h, so that the modules below sim/ can build on it. */
#ifndef CVK_SIM_H
#define CVK_SIM_H

#include "contact/collide.h"
#include "features/aero.h"
#include "features/attach.h"
#include "features/grab.h"
#include "features/pick.h"
#include "features/tear.h"
#include "core/clock.h"
#include "plan/state.h"

/* Creates the watch buffer and resets it. */
cvk_result cvk_sim_watch_create(cvk_sim* sim, cvk_error* error);
/* Forgets a divergence and counts substeps from 0 again: the state was rewritten. */
void cvk_sim_watch_reset(cvk_sim* sim);
/* After the queue has finished the simulation's frames: CVK_ERROR_DIVERGED with the frame and
   cloth when the watch tripped, else CVK_SUCCESS. */
cvk_result cvk_sim_watch_check(const cvk_sim* sim, cvk_error* error);
/* The diverged fields of `st`. */
void cvk_sim_watch_stats(const cvk_sim* sim, cvk_sim_stats* st);

/* Reads the state back through the family: positions into sim->scratch, velocities into
   sim->scratch_v (internal order, 3 floats per particle). */
cvk_result cvk_sim_read_internal(cvk_sim* sim, cvk_error* error);

/* The contact figures of `st` (collider_contacts, self_contacts, max_penetration,
   intersecting_pairs) from positions in internal order (3 floats per particle), at the
   simulated time the simulation has reached; all 0 when the scene does not collide. Reads the
   spring flags back (torn triangles are left out), so it waits like cvk_sim_read_mesh. */
cvk_result cvk_sim_contact_stats(cvk_sim* sim, const float* xyz_internal, cvk_sim_stats* st,
                                 cvk_error* error);

/* With collision.self and without collision.allow_intersecting_start, CVK_ERROR_INVALID_ARGUMENT
   when two triangles of one instance (cvk_collide_instance_count) that share no particle
   intersect in the build's initial positions: one
   sentence naming the cloths, the lowest such pair (cvk_first_intersecting_pair; triangles
   numbered within their cloth in build order) and where. */
cvk_result cvk_sim_check_clean_start(const cvk_sim* sim, const cvk_scene_desc* scene,
                                     cvk_error* error);

/* Without collision.allow_intersecting_start, CVK_ERROR_INVALID_ARGUMENT when a free particle
   starts more than the contact thickness inside one of its colliders (posed at time 0; the
   funnel's distance is unsigned, so never inside it): one sentence naming the cloth, the
   collider, the particle, how deep and where. With or without self-contact. */
cvk_result cvk_sim_check_collider_start(const cvk_sim* sim, const cvk_scene_desc* scene,
                                        cvk_error* error);

/* ---- shared by sim.c and sim_state.c ---- */

/* Timestamp queries of one frame; pass[q] (q ≥ 1) is the pass query q closes. */
typedef struct cvk_sim_queries {
    VkQueryPool pool;
    uint32_t count;
    uint32_t* pass;
} cvk_sim_queries;

/* A plan for `solver` by `family` (state `self`) on this simulation's scene. */
cvk_result cvk_sim_make_plan(cvk_sim* sim, const struct cvk_family_api* family, void* self,
                             const cvk_solver_desc* solver, uint32_t workgroup_size,
                             uint32_t max_groups, cvk_plan* out, cvk_error* error);
/* Creates the pipelines `plan` uses and dispatches the new ones once (warm-up). */
cvk_result cvk_sim_ready_pipelines(cvk_sim* sim, const cvk_plan* plan, cvk_error* error);
cvk_result cvk_sim_create_queries(cvk_sim* sim, const cvk_plan* plan, cvk_sim_queries* out,
                                  cvk_error* error);
void cvk_sim_destroy_queries(cvk_sim* sim, cvk_sim_queries* queries);
/* Makes `queries` the simulation's (taking them over) and marks them for a reset. */
void cvk_sim_use_queries(cvk_sim* sim, cvk_sim_queries* queries);
/* Makes the plan again for the current solver (a module joined it: the grab pass), with its
   pipelines, queries and frame_cmd; waits for the queue first. On failure the old plan stays. */
cvk_result cvk_sim_replan(cvk_sim* sim, cvk_error* error);
/* The internal index of a particle named as the public API names it; `call` starts the
   message when it does not exist. */
cvk_result cvk_sim_particle_internal(const cvk_sim* sim, cvk_particle particle, const char* call,
                                     uint32_t* out, cvk_error* error);
/* Records frame_cmd from the current plan. */
cvk_result cvk_sim_record_frame_cmd(cvk_sim* sim, cvk_error* error);

#endif
