/* The simulation object; private so solver families, mesh generation, export and rendering
   can reach its buffers. It owns what every family shares (positions, spring flags, staging,
   the plan and its recording, timing); the solver family owns the rest (solver.h). */
#ifndef CVK_SIM_H
#define CVK_SIM_H

#include "aero.h"
#include "attach.h"
#include "build.h"
#include "collide.h"
#include "gpu.h"
#include "grab.h"
#include "pick.h"
#include "plan.h"
#include "reference.h"
#include "tear.h"

struct cvk_family_api;

struct cvk_sim {
    cvk_context* context;
    cvk_build build;
    cvk_plan plan;
    char name[64];
    float dt;
    cvk_solver_desc solver;
    cvk_scene_desc params;  /* the scene's step, gravity and damping (no cloths): plan input */
    int timing_request;     /* cvk_sim_desc.timing */
    uint32_t particle_workgroup_size; /* of the passes that stream over particles (the sweeps,
                                         prediction, finalize, tethers): cvk_plan */
    uint32_t search_lanes;  /* cvk_sim_desc.search_lanes, resolved: a divisor of the workgroup
                               size, fixed for the simulation's life (the patch buffers'
                               size depends on it, lib/collide.h) */
    cvk_ref_params ref;

    cvk_collide collide;    /* colliders, self-contact, the frame state (collide.h) */
    cvk_attach attach;      /* keyframed attached particles (attach.h) */
    cvk_aero aero;          /* wind and air drag (aero.h) */
    cvk_grab grab;          /* the dragged particle (grab.h) */
    cvk_pick pick;          /* picking's buffers, made on the first pick (pick.h) */
    cvk_tear tear;          /* springs that break (tear.h) */

    const struct cvk_family_api* family; /* the family that solves `solver` */
    void* family_state;

    /* Positions (internal order, vec4; the family may use w: PD keeps m/h² there). */
    cvk_buffer positions;
    cvk_buffer spring_alive; /* uint per spring of build.springs: 1, 0 once torn (tear.h); the
                                mesh reads it */
    cvk_buffer staging; /* host-visible, 2 vec4 per particle: uploads and readback */
    cvk_buffer watch;   /* host-visible cvk_gpu_watch: the divergence watch */
    uint64_t watch_frames; /* s->frames when the watch was last reset */
    VkBufferView view_positions, view_spring_alive;
    cvk_pipelines pipelines; /* the table's pipelines, created on first use */

    bool timing;
    VkQueryPool queries;
    uint32_t query_count;    /* per frame: one at the start, one per pass run */
    uint32_t* query_pass;    /* query q > 0 closes this pass */
    bool queries_unreset;    /* a new pool: the next upload resets it */

    cvk_submitter submitter;
    VkCommandBuffer frame_cmd;    /* one frame, recorded once, submitted again and again */
    VkCommandBuffer transfer_cmd; /* re-recorded for each upload */
    VkCommandBuffer* batch;       /* frame_cmd repeated, for one submission of many frames */
    uint32_t batch_capacity;

    uint64_t frames;
    double host_pass_ms[CVK_MAX_PASSES]; /* host plans: host time of the last frame, by pass */
    bool host_timed;

    float* scratch;   /* positions, 3 floats per particle, internal order */
    float* scratch_v; /* velocities, same layout */
};

/* The divergence watch (shaders/finalize.comp): a particle whose step is longer than
   CVK_DIVERGED_SPEED · h in one substep has run away. 10000 m/s is the bound on a cloth's
   initial velocity (lib/scene.h) and thirty times the speed of sound: a sane cloth does not
   reach it, while a blown-up solve passes it within a few substeps. It trips falsely only for
   motion that fast, such as a free fall in vacuum for over 1000 s at 9.81 m/s². */
#define CVK_DIVERGED_SPEED 1e4 /* m/s */
/* ... and a spring longer than ten times its rest length has too (predict.comp checks each
   particle's first spring): cloth tears or stops long before that; a solve whose step is
   far too long for its springs (dt = 1000 s) gets there without moving fast. */
#define CVK_DIVERGED_STRETCH 10

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

/* One region of the staging buffer into a device buffer. */
typedef struct cvk_staging_copy {
    cvk_buffer* dst;
    VkDeviceSize src_offset, dst_offset, size;
} cvk_staging_copy;

/* Copies staging regions into buffers and waits; earlier GPU work on them finishes first, and
   compute and transfer work after sees them. */
cvk_result cvk_sim_copy_from_staging(cvk_sim* sim, const cvk_staging_copy* jobs, uint32_t count,
                                     cvk_error* error);

/* A device buffer for a module's tables (storage, uniform, texel and transfer use; at least 16
   bytes), filled with `size` bytes of `data` unless data is NULL. */
cvk_result cvk_sim_make_buffer(cvk_sim* sim, cvk_buffer* buffer, VkDeviceSize size, const char* what,
                               const void* data, cvk_error* error);

/* Fills every byte of a device buffer (a size of whole words) with `byte` (clear: with
   zeros) on the device, and waits. */
cvk_result cvk_sim_fill_buffer(cvk_sim* sim, cvk_buffer* buffer, unsigned char byte,
                               cvk_error* error);
cvk_result cvk_sim_clear_buffer(cvk_sim* sim, cvk_buffer* buffer, cvk_error* error);

/* Uploads a host array into a device buffer through the staging buffer, in chunks. */
cvk_result cvk_sim_upload(cvk_sim* sim, cvk_buffer* dst, const void* data, VkDeviceSize size,
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

/* Milliseconds of a monotonic clock. */
double cvk_now_ms(void);

#endif
