/* Dragging a particle (cvk_sim_grab, cvk_sim_release): the host writes which free particle
   follows which target into a small host-visible buffer between frames, and one pass of the
   recorded frame reads it every substep (shaders/features/grab.comp): the particle moves in a straight
   line from where the frame found it to the target, evenly over the frame's substeps, and is
   infinitely heavy for the projective-dynamics solve meanwhile (its m/h^2 becomes
   CVK_GRAB_WEIGHT), so the cloth is dragged, not teleported, and a released particle keeps the
   velocity of its last substep. The pass is in the plan from the first grab on (or from
   creation with cvk_sim_desc.grab); while nothing is grabbed it returns at once. */
#ifndef CVK_GRAB_H
#define CVK_GRAB_H

#include "core/gpu.h"
#include "plan/plan.h"

struct cvk_sim;

/* The m/h^2 the solve sees for the grabbed particle: 2^100. A spring's k (at most ~1e12 N/m
   times the springs of a particle) is lost in rounding next to it, so a sweep gives back the
   displacement it was given to within 1e-27 m; 2^100 times a displacement up to 1e4 m stays
   far from float's 3.4e38. */
#define CVK_GRAB_WEIGHT 1.2676506002282294e30f

/* Bytes of the grab buffer: the cvk_gpu_grab, then CVK_GRAB_MAX members (shared/layout.h). */
#define CVK_GRAB_BYTES (sizeof(cvk_gpu_grab) + CVK_GRAB_MAX * 4 * sizeof(float))

typedef struct cvk_grab {
    bool planned;                 /* the plan has the grab pass */
    cvk_buffer state;             /* host-visible cvk_gpu_grab and its members (CVK_GRAB_BYTES),
                                     written by cvk_sim_grab and cvk_sim_grab_within */
    bool held;                    /* what the buffer holds, for a repeated call: */
    uint32_t particle;            /* the grabbed particle (internal index) */
    float radius;                 /* its cvk_sim_grab_within radius (0: cvk_sim_grab) */
    uint32_t count;               /* members held, the grabbed particle included */
    cvk_descriptors descriptors;  /* one set */
    const cvk_buffer* u0;         /* the solver's iterates, from cvk_grab_bind */
    const cvk_buffer* u1;
    const cvk_buffer* y;
} cvk_grab;

/* Creates the grab buffer and descriptor set, bound to the iterates cvk_grab_bind gave, and
   marks the pass as planned: the caller makes the plan again. */
cvk_result cvk_grab_enable(struct cvk_sim* sim, cvk_error* error);
void cvk_grab_destroy(struct cvk_sim* sim);

/* Projective dynamics' displacement iterates and prediction; the family calls it when it
   creates them. */
void cvk_grab_bind(struct cvk_sim* sim, const cvk_buffer* u0, const cvk_buffer* u1,
                   const cvk_buffer* y);

/* One op of the "grab" pass (after the prediction, and again before finalize); none unless
   planned. */
void cvk_grab_add_op(struct cvk_sim* sim, cvk_plan* plan, const char* note);

/* Why the current solver cannot hold a grabbed particle (for messages), or NULL when it can. */
const char* cvk_grab_unsupported(const cvk_solver_desc* solver);

#endif
