/* Straightforward double-precision host implementations of the solver steps: the "gs-cpu"
   solver, and the ground truth the tests and the benchmark compare the GPU with. Never on
   the fast path. Arrays hold 3 doubles per particle in internal order; b holds 4 (xyz and
   1/diag). */
#ifndef CVK_REFERENCE_H
#define CVK_REFERENCE_H

#include "build.h"

typedef struct cvk_ref_params {
    double inv_h2;        /* 1 / h² */
    double keep;          /* 1 − damping, 0 without integration */
    double gravity_h2[3]; /* h² g, 0 without integration */
} cvk_ref_params;

cvk_ref_params cvk_ref_params_of(const cvk_scene_desc* scene);

/* y = x + (x − prev)·keep + h² g; prev ← x; x ← y (free particles). */
void cvk_ref_predict(const cvk_build* build, const cvk_ref_params* params, double* x,
                     double* prev, double* y);

/* b_p = m/h² y_p + Σ k L (t_p − t_c)/|t_p − t_c|, and 1/diag (free particles). */
void cvk_ref_rhs(const cvk_build* build, const cvk_ref_params* params, const double* t,
                 const double* y, double* b);

/* One Gauss-Seidel sweep with SOR, colour by colour, in place. */
void cvk_ref_gauss_seidel_sweep(const cvk_build* build, const double* b, double omega, double* x);

/* One Jacobi sweep from src into dst with relaxation omega; when cheb != 1, dst holds the
   iterate before src on entry and receives the Chebyshev combination. */
void cvk_ref_jacobi_sweep(const cvk_build* build, const double* b, double omega, double cheb,
                          const double* src, double* dst);

/* One projective-dynamics substep with the sequential Gauss-Seidel solver; `scratch` holds
   4 doubles per particle (b). */
void cvk_ref_substep_gauss_seidel(const cvk_build* build, const cvk_ref_params* params,
                                  const cvk_solver_desc* solver, double* x, double* prev,
                                  double* y, double* scratch);

#endif
