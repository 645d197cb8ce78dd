/* The simulation's state, which every module's passes are built on: the device-buffer layer,
   the build, the plan, the step parameters, the buffers every family shares (positions,
   spring flags, the divergence watch), timing, and each module's state behind a pointer. The
   simulation object (sim/) creates and destroys it; the modules below sim/ (contact,
   features, solver families) read and extend it, and the solver family owns the rest
   (plan/family.h). */
#ifndef CVK_STATE_H
#define CVK_STATE_H

#include "core/device.h"
#include "core/pipelines.h"
#include "plan/plan.h"
#include "scene/scene.h"
#include "topology/build.h"

struct cvk_family_api;
/* Each module's state, complete in its own header (contact/collide.h and the features/ headers); the
   simulation holds them behind pointers so that this header needs none of them. */
struct cvk_collide;
struct cvk_attach;
struct cvk_aero;
struct cvk_grab;
struct cvk_pick;
struct cvk_tear;

struct cvk_sim {
    cvk_device device;      /* context, submitter, staging: every module's buffers go through it */
    cvk_build build;
    cvk_plan plan;
    char name[64];
    cvk_step_params params; /* dt, substeps, gravity, damping: derived once from the scene, the
                               one copy every module reads */
    cvk_solver_desc solver; /* the current solver: cvk_sim_set_solver changes it */
    int timing_request;     /* cvk_sim_desc.timing */
    uint32_t particle_workgroup_size; /* of the passes that stream over particles (the sweeps,
                                         prediction, finalize, tethers): cvk_plan */
    uint32_t fused_workgroup_size;    /* of the fused sweeps' workgroups: cvk_plan */
    uint32_t fused_copies;            /* the copies fused sweeps take a workgroup each: the
                                         instances without self-contact where the build lays
                                         them out so (cvk_pd_fused_copies), else 1 */
    uint32_t fused_shared_slots;      /* a copy's free particles where the fused sweeps keep
                                         their iterate in shared memory, else 0 */
    uint32_t particle_group_items;    /* the fewest particles a workgroup of those passes
                                         takes (0: no floor): cvk_plan */
    uint32_t walk_items;              /* items per invocation of the walking passes: cvk_plan */
    const char* notes[CVK_COLLISION_NOTES_MAX + 1]; /* cvk_sim_note: static sentences, one
                                                       per scene key set that has no effect,
                                                       and split_note */
    uint32_t note_count;
    char split_note[256]; /* why the substeps were split (cvk_collide_create), or empty */
    uint32_t instance_count;      /* the scene's instances, for cvk_sim_describe_plan: how many, */
    bool instances_listed;        /* whether their offsets were listed, */
    float instance_offset1[3];    /* and copy 1's offset, m */

    struct cvk_collide* collide; /* colliders, self-contact, the frame state (collide.h) */
    struct cvk_attach* attach; /* keyframed attached particles (attach.h) */
    struct cvk_aero* aero;   /* wind and air drag (aero.h) */
    struct cvk_grab* grab;   /* the dragged particle (grab.h) */
    struct cvk_pick* pick;   /* picking's buffers, made on the first pick (pick.h) */
    struct cvk_tear* tear;   /* springs that break (tear.h) */

    const struct cvk_family_api* family; /* the family that solves `solver` */
    void* family_state;

    /* Positions (internal order, vec4; the family may use w: PD keeps m/h² there). */
    cvk_buffer positions;
    cvk_buffer spring_alive; /* uint per spring of build.springs: 1, 0 once torn (tear.h); the
                                mesh reads it */
    cvk_buffer watch;   /* host-visible cvk_gpu_watch: the divergence watch */
    uint64_t watch_frames; /* s->frames when the watch was last reset */
    VkBufferView view_positions, view_spring_alive;
    cvk_pipelines pipelines; /* the table's pipelines, created on first use */

    bool timing;
    VkQueryPool queries;
    uint32_t query_count;    /* per frame: one at the start, one per pass run */
    uint32_t* query_pass;    /* query q > 0 closes this pass */

    VkCommandBuffer frame_cmd;    /* one frame, recorded once, submitted again and again */
    VkCommandBuffer* batch;       /* frame_cmd repeated, for one submission of many frames */
    uint32_t batch_capacity;

    uint64_t frames;
    double host_pass_ms[CVK_MAX_PASSES]; /* host plans: host time of the last frame, by pass */
    bool host_timed;

    float* scratch;   /* positions, 3 floats per particle, internal order */
    float* scratch_v; /* velocities, same layout */
};

/* The divergence watch (shaders/solvers/finalize.comp): a particle whose step is longer than
   CVK_DIVERGED_SPEED · h in one substep has run away. 10000 m/s is the bound on a cloth's
   initial velocity (lib/scene/scene.h) and thirty times the speed of sound: a sane cloth does not
   reach it, while a blown-up solve passes it within a few substeps. It trips falsely only for
   motion that fast, such as a free fall in vacuum for over 1000 s at 9.81 m/s². */
#define CVK_DIVERGED_SPEED 1e4 /* m/s */
/* ... and a spring longer than ten times its rest length has too (predict.comp checks each
   particle's first spring): cloth tears or stops long before that; a solve whose step is
   far too long for its springs (dt = 1000 s) gets there without moving fast. */
#define CVK_DIVERGED_STRETCH 10

#endif
