/* Implicit Euler (Baraff & Witkin 1998; seed 000 §4): backward Euler with one linearised
   Newton step per substep, the system assembled on the device into 3×3 blocks per particle
   and per adjacency slot, solved by filtered block-Jacobi-preconditioned CG or by block
   Jacobi, both stopping on the device (shaders/implicit_*.comp). The host reference here is
   the same algorithm in double precision. */
#ifndef CVK_SOLVE_IMPLICIT_H
#define CVK_SOLVE_IMPLICIT_H

#include "plan/state.h"
#include "solvers/solver.h"

/* One substep's settings. */
typedef struct cvk_implicit_params {
    double h;             /* substep, s */
    double gravity[3];    /* m/s², 0 without integration */
    double keep;          /* 1 − damping */
    double kd;            /* spring damping, N·s/m */
    double tolerance;     /* relative residual (preconditioner's norm) where the solve stops */
    uint32_t max_iterations;
    cvk_linear_solver linear; /* CVK_LINEAR_CG or CVK_LINEAR_JACOBI */
    bool clamp;           /* clamp the compressive part of each spring block (keeps A SPD) */
    /* The host reference's colliders: static planes, each a point and a unit outward normal
       (m), kept `thickness` (m) away as shaders/solvers/implicit_contact.comp keeps every collider. */
    const double (*planes)[6];
    uint32_t plane_count;
    double thickness;
    double friction, static_friction; /* Coulomb coefficients against every plane */
} cvk_implicit_params;

cvk_implicit_params cvk_implicit_params_of(const cvk_step_params* step,
                                           const cvk_solver_desc* solver);

/* What one reference substep did. */
typedef struct cvk_implicit_report {
    uint32_t iterations;  /* CG iterations or Jacobi sweeps */
    bool breakdown;       /* a negative or non-finite rᵀP⁻¹r, pᵀAp (CG) or diagonal-block norm
                             (Jacobi): A is not positive definite; the solve stopped there */
    double residual;      /* the last relative residual √(rᵀP⁻¹r / r₀ᵀP⁻¹r₀) */
} cvk_implicit_report;

/* One backward-Euler substep on the host in double precision: x and v (3 per particle,
   internal order; pinned entries untouched) advance by h. The same contact filter, assembly,
   iteration, stopping rule and release as the device. Returns false when out of memory. */
bool cvk_ref_implicit_substep(const cvk_build* build, const cvk_implicit_params* params,
                              double* x, double* v, cvk_implicit_report* report);

/* The contact filter of the last substep, for tests: 4 floats per particle in the user's
   order, the unit normal of the collider it was held on and 1 + the collider's index (its
   negative: released at the end of the substep), 0 for a free or pinned one. The simulation
   must solve with this family. */
cvk_result cvk_implicit_read_held(cvk_sim* sim, float* held, cvk_error* error);

/* The solver_* fields of `st` (0 unless the simulation solves with this family); the
   simulation's work must be complete. */
void cvk_implicit_stats(const cvk_sim* sim, cvk_sim_stats* st);

#endif
