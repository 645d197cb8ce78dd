/* Straightforward double-precision host implementations of the solver steps: the "gs-cpu"
   solver, and the ground truth the tests and the benchmark compare the GPU with. Never on
   the fast path. Arrays hold 3 doubles per particle in internal order; b holds 4 (xyz and
   1/diag). */
#ifndef CVK_REFERENCE_H
#define CVK_REFERENCE_H

#include "topology/build.h"

/* The rest memory's rate per unit of damping (its reasons in solve_pd.h). */
#define CVK_REST_RATE_PER_DAMPING 0.25

typedef struct cvk_ref_params {
    double inv_h2;        /* 1 / h² */
    double keep;          /* 1 − damping, 0 without integration */
    double gravity_h2[3]; /* h² g, 0 without integration */
    double rest_rate;     /* the rest memory's rate (solve_pd.h), 0 without damping or with
                             contact */
} cvk_ref_params;

cvk_ref_params cvk_ref_params_of(const cvk_step_params* step);

/* y = x + (x − prev)·keep + h² g; prev ← x; x ← y (free particles). */
void cvk_ref_predict(const cvk_build* build, const cvk_ref_params* params, double* x,
                     double* prev, double* y);

/* The rest memory (solve_pd.h) on the host: x += rest after the prediction (the first
   iterate y + r), and r += rate ((x − y) − r) after the solve (free particles; nothing when
   params->rest_rate is 0). */
void cvk_ref_rest_start(const cvk_build* build, const cvk_ref_params* params, const double* rest,
                        double* x);
void cvk_ref_rest_update(const cvk_build* build, const cvk_ref_params* params, const double* x,
                         const double* y, double* rest);

/* b_p = m/h² y_p + Σ k L (t_p − t_c)/|t_p − t_c|, and 1/diag (free particles). */
void cvk_ref_rhs(const cvk_build* build, const cvk_ref_params* params, const double* t,
                 const double* y, double* b);

/* Relaxation of Gauss-Seidel sweep i (0-based) of an outer iteration of `inner` sweeps, of
   `outer` in a substep, for rbgs (lib/solvers/pd_passes.c, fused or not) and gs-cpu alike:
   omega, except the last of two or more sweeps when a substep has two or more outer
   iterations, which is not over-relaxed (at most 1). With one outer iteration no local step
   reads the iterate again, and an unrelaxed last sweep did little there (demo.json: 0.308 ->
   0.280 mm) while it cost peer-hanging.json's 20 x 1 x 5 its 99th-percentile stretch target
   (0.92 -> 1.03 %).
   SOR leaves the modes its sweeps barely couple (for a grid with shear springs as stiff as its
   structural ones, the checkerboard: its neighbours' pulls cancel) with the error (1 − omega)
   per sweep, alternating in sign; in the iterate the next local step and the velocity read,
   that is a particle-scale zig-zag the springs do not resist (out of the plane, skip-one bend
   springs and the diagonals see no checkerboard), and demo.json's sheet grew an orange peel of
   it. An unrelaxed last sweep removes that part (docs/how-it-works.md, "The last sweep"). */
float cvk_gs_sweep_omega(uint32_t sweep, uint32_t inner, uint32_t outer, float omega);

/* One Gauss-Seidel sweep with SOR, colour by colour, in place; returns the largest change of
   a coordinate. */
double cvk_ref_gauss_seidel_sweep(const cvk_build* build, const double* b, double omega, double* x);

/* One Jacobi sweep from src into dst with relaxation omega; when cheb != 1, dst holds the
   iterate before src on entry and receives the Chebyshev combination. */
void cvk_ref_jacobi_sweep(const cvk_build* build, const double* b, double omega, double cheb,
                          const double* src, double* dst);

/* Tethers (tether.h) on positions x: each free particle farther from one of its pins than
   that tether allows is moved onto the sphere around the pin, pin by pin, nearest first,
   CVK_TETHER_ROUNDS times. */
void cvk_ref_tethers(const cvk_build* build, double* x);

/* The solve of one substep with the sequential Gauss-Seidel solver (the "gs-cpu" solver):
   outer iterations of local step + inner sweeps, then tethers, from x towards the prediction
   y; `scratch` holds 4 doubles per particle (b). */
void cvk_ref_solve_gauss_seidel(const cvk_build* build, const cvk_ref_params* params,
                                const cvk_solver_desc* solver, const double* y, double* x,
                                double* scratch);

/* One projective-dynamics substep with it: predict, then cvk_ref_solve_gauss_seidel; with a
   rest memory `rest` (3 doubles per particle; NULL: none) started from y + rest, which it
   updates. */
void cvk_ref_substep_gauss_seidel(const cvk_build* build, const cvk_ref_params* params,
                                  const cvk_solver_desc* solver, double* x, double* prev,
                                  double* y, double* rest, double* scratch);

/* The converged solution x* of one substep: from the iterate in x (usually the prediction y),
   repeats local step + one Gauss-Seidel sweep with SOR `omega` until no coordinate changes by
   more than `tolerance` m in an iteration (the residual has then stopped falling), or until
   `max_iterations`. Returns the iterations done; *last_change (may be NULL) receives the
   largest change of the last one. `scratch` holds 4 doubles per particle. */
uint64_t cvk_ref_solve_converged(const cvk_build* build, const cvk_ref_params* params,
                                 const double* y, double omega, double tolerance,
                                 uint64_t max_iterations, double* x, double* scratch,
                                 double* last_change);

/* What cvk_ref_solve_newton did. */
typedef struct cvk_ref_newton_report {
    uint32_t steps;          /* Newton steps taken */
    uint64_t cg_iterations;  /* conjugate-gradient iterations over all steps */
    double last_step;        /* largest coordinate change of the last step, m */
    double gradient;         /* |∇E| at the end, N */
    double gs_change;        /* largest change of `check_sweeps` Gauss-Seidel iterations (local
                                step + sweep) started from the result, m: how far x* is from
                                gs-cpu's fixed point */
} cvk_ref_newton_report;

/* The converged solution of one substep by Newton's method on the substep's energy
   E(x) = Σ m/(2h²) |x − y|² + Σ k/2 (|xa − xb| − L)², whose stationary points are exactly the
   fixed points of the projective-dynamics iteration (local step + global solve) that every
   solver here approximates. Each spring's Hessian block k (n nᵀ + max(0, 1 − L/l)(I − n nᵀ))
   is positive semi-definite, the Newton system is solved by conjugate gradients with a 3×3
   block-Jacobi preconditioner, and a backtracking line search keeps E falling. Gauss-Seidel
   needs 10⁵ sweeps and more for the stiff substeps of a 100×100 cloth; Newton needs tens of
   steps. x holds the start (usually y) and receives x*; stops when a step changes no
   coordinate by more than `tolerance` m, or after `max_steps`. Returns false when out of
   memory. */
bool cvk_ref_solve_newton(const cvk_build* build, const cvk_ref_params* params, const double* y,
                          double tolerance, uint32_t max_steps, uint32_t check_sweeps, double* x,
                          cvk_ref_newton_report* report);

#endif
