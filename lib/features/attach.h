/* Attachments: particles of a cloth moved by keyframes (cvk_attachment_desc). The build pins
   them and lists them (cvk_build.attached); this module uploads their start positions and
   motions and adds one pass at the start of every substep that writes each attached
   particle's displacement over the substep into the projective-dynamics iterates (implicit
   Euler: its velocity, and a second pass places it; cvk_attach_add_implicit_pass), from the
   frame state (so one recorded frame submitted again moves them on); finalize then moves them
   with the free particles. Pinned particles are never swept, so the solve treats them as
   infinitely heavy, and the displacement they were given is their velocity (times h): the cloth
   is dragged, not teleported. A scene without attachments records nothing of this module. */
#ifndef CVK_ATTACH_H
#define CVK_ATTACH_H

#include "core/gpu.h"
#include "plan/plan.h"

struct cvk_sim;

/* Which family's iterates a descriptor set of the pass writes: one set each, so that a family
   being created beside another (a solver switch that may still fail) never rebinds the
   running one's (as lib/features/tear.h). */
typedef enum cvk_attach_family {
    CVK_ATTACH_FOR_PD,
    CVK_ATTACH_FOR_IMPLICIT,
    CVK_ATTACH_FAMILIES
} cvk_attach_family;

typedef struct cvk_attach {
    uint32_t attachment_count;
    cvk_motion* motions;         /* deep copies of the scene's motions (keyframes owned here) */
    cvk_buffer keyframes;        /* 2 vec4 per keyframe (cvk_motion_pack) */
    cvk_buffer attachments;      /* cvk_gpu_attachment per attachment */
    cvk_buffer attached;         /* cvk_gpu_attached per attached particle */
    cvk_descriptors descriptors; /* a set per family, bound to its iterates by cvk_attach_bind */
    bool bound[CVK_ATTACH_FAMILIES];
} cvk_attach;

/* Copies the scene's motions and uploads the tables (nothing when the scene has none). */
cvk_result cvk_attach_create(struct cvk_sim* sim, const cvk_scene_desc* scene, cvk_error* error);
void cvk_attach_destroy(struct cvk_sim* sim);

/* Points the family's set at its two displacement iterates (projective dynamics' u[0], u[1];
   implicit Euler's velocities, twice); the family calls it when it creates them. */
void cvk_attach_bind(struct cvk_sim* sim, cvk_attach_family family, const cvk_buffer* u0,
                     const cvk_buffer* u1);

/* The pass ("attach"), before the family's prediction; none without attachments. */
cvk_result cvk_attach_add_passes(struct cvk_sim* sim, cvk_plan* plan, cvk_error* error);

/* Implicit Euler's passes (also "attach"; none without attachments): before the assembly
   (place false) the velocity that takes each attached particle to its keyframed place over the
   substep, v = (pose(t + h) · start − x_n) / h, which the springs to it carry into the
   right-hand side (the particle is pinned for the solver, S = 0); after the integration
   (place true) x = pose(t + h) · start. The velocities must be bound (CVK_ATTACH_FOR_IMPLICIT). */
cvk_result cvk_attach_add_implicit_pass(struct cvk_sim* sim, cvk_plan* plan, bool place,
                                        cvk_error* error);

/* Where attached particle i (cvk_build.attached order) is at time t (s), as the keyframes say:
   pose(t) applied to its position at creation. */
void cvk_attach_position(const struct cvk_sim* sim, uint32_t i, double t, float out[3]);

#endif
