/* Explicit integrators (seed 001 §2.3): a mass-spring cloth with the scene's stretch, shear
   and bend springs, gravity and spring damping (Matyka) or artificial viscosity (Desbrun),
   advanced by forward Euler, TVD-RK2, 4th-order Adams-Bashforth or position Verlet on the
   device (shaders/explicit_*.comp). The host reference here is the same algorithm in double
   precision. Stable only below a step the stiffest mode sets (README "Explicit integrators");
   a run past it is caught by the divergence watch. */
#ifndef CVK_SOLVE_EXPLICIT_H
#define CVK_SOLVE_EXPLICIT_H

#include "plan/state.h"
#include "solvers/solver.h"

/* One substep's settings. */
typedef struct cvk_explicit_params {
    double h;                 /* substep, s */
    double gravity[3];        /* m/s², 0 without integration */
    double keep;              /* 1 − damping */
    double kd;                /* N·s/m */
    cvk_integrator integrator;      /* never NONE */
    cvk_damping_model damping_model; /* never NONE */
} cvk_explicit_params;

cvk_explicit_params cvk_explicit_params_of(const cvk_step_params* step,
                                           const cvk_solver_desc* solver);

/* The host state: x and v (3 per particle, internal order; pinned entries untouched) and the
   Adams-Bashforth history (per free particle: a_n-1..a_n-3 then v_n-1..v_n-3, and how many
   steps it holds). */
typedef struct cvk_explicit_host {
    double *x, *v;
    double* history;   /* 18 per free particle */
    uint32_t* held;    /* per free particle, 0..3 */
} cvk_explicit_host;

/* Allocates the host state at the build's positions, at rest; false when out of memory. */
bool cvk_ref_explicit_init(const cvk_build* build, cvk_explicit_host* state);
void cvk_ref_explicit_free(cvk_explicit_host* state);
/* One substep on the host in double precision, the same rules as the device. Returns false
   when out of memory. */
bool cvk_ref_explicit_substep(const cvk_build* build, const cvk_explicit_params* params,
                              cvk_explicit_host* state);
/* Accelerations of the free particles (3 each) at (x, v): gravity, springs, damping. */
void cvk_ref_explicit_accel(const cvk_build* build, const cvk_explicit_params* params,
                            const double* x, const double* v, const double* x_fixed,
                            const double* v_fixed, double* a);

#endif
