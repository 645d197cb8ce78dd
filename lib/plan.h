/* The step plan: the dispatches of one substep, derived once from the scene. Only the
   passes a scene needs appear; recording walks this list. */
#ifndef CVK_PLAN_H
#define CVK_PLAN_H

#include "build.h"
#include "pipelines.h"
#include "shared/layout.h"

/* Descriptor sets differ only in which displacement buffer is src and which is dst. */
typedef enum cvk_set_id {
    CVK_SET_U0_TO_U1,
    CVK_SET_U1_TO_U0,
    CVK_SET_U0_TO_U0,
    CVK_SET_COUNT
} cvk_set_id;

typedef enum cvk_pass_id {
    CVK_PASS_PREDICT,
    CVK_PASS_SOLVE,
    CVK_PASS_FINALIZE,
    CVK_PASS_COUNT
} cvk_pass_id;

typedef struct cvk_op {
    cvk_pipeline_id pipeline;
    cvk_set_id set;
    cvk_pass_id pass;
    uint32_t groups;             /* invocations stride over the rest */
    cvk_pd_push push;
    uint32_t outer, inner, colour; /* for the printed plan */
} cvk_op;

typedef struct cvk_plan {
    cvk_op* ops;                 /* one substep */
    uint32_t op_count;
    uint32_t substeps;
    uint32_t workgroup_size;
    uint32_t max_groups;
    bool uses[CVK_PIPE_COUNT];
    uint32_t pass_dispatches[CVK_PASS_COUNT]; /* per substep */
    double chebyshev_rho;        /* used by the chebyshev plan (after the stability cap) */
    double chebyshev_rho_estimated; /* the spectral radius before the cap */
} cvk_plan;

/* max_groups caps the workgroups of one dispatch; the kernels loop over the rest. */
cvk_result cvk_plan_create(const cvk_scene_desc* scene, const cvk_build* build,
                           uint32_t workgroup_size, uint32_t max_groups, cvk_plan* out,
                           cvk_error* error);

/* The same with Chebyshev's spectral-radius estimate given (estimated_rho ≥ 0), so a caller
   that changes the solver often estimates it once; estimated_rho < 0 estimates it here. A
   nonzero solver.chebyshev_rho still takes precedence. */
cvk_result cvk_plan_create_with_rho(const cvk_scene_desc* scene, const cvk_build* build,
                                    uint32_t workgroup_size, uint32_t max_groups,
                                    double estimated_rho, cvk_plan* out, cvk_error* error);
void cvk_plan_destroy(cvk_plan* plan);

const char* cvk_pass_name(cvk_pass_id pass);

/* Stability of a truncated solve inside Verlet. Model one stiff mode: if the substep's
   sweeps leave the error times P (the solver's error polynomial at that mode's eigenvalue),
   the (velocity, constraint violation) pair evolves by [[2P, −1], [P, 0]], whose eigenvalues
   P ± √(P² − P) leave the unit circle exactly when P < −1/3. Gauss-Seidel's spectrum is
   non-negative; Jacobi's reaches −1 (the checkerboard mode), so an odd number of Jacobi
   sweeps explodes (measured: hanging.json with 1 x 3 sweeps); Chebyshev's equi-oscillating
   polynomial dips to −1/T_m(1/ρ), near −1 when sweeps are few. The plan therefore keeps P
   above −1/3 by construction:
   - with an odd number of sweeps per substep, the first sweep is relaxed to omega ≤ 0.6,
     whose spectrum starts at −0.2;
   - Chebyshev's ρ is capped so that T_m(1/ρ) ≥ 3 over its m accelerated sweeps. */
#define CVK_STABLE_FIRST_OMEGA 0.6f

/* Chebyshev runs in cycles: its recurrence assumes one fixed iteration map, so it restarts
   with every outer iteration (whose local step changes the linear system) when an outer
   iteration has several sweeps; with one sweep per outer iteration it runs across them, as
   Wang 2015 does (local step and sweep then form one fixed nonlinear map). Plain Jacobi is
   one cycle per substep. Returns the cycle length in sweeps. */
uint32_t cvk_sweep_cycle(const cvk_solver_desc* solver);

/* Relaxation of sweep c (0-based) of a cycle of `cycle` sweeps. */
float cvk_jacobi_sweep_omega(uint32_t sweep, uint32_t cycle, float omega);

/* Largest ρ whose Chebyshev polynomial over m sweeps stays above −1/3: T_m(1/ρ) = 3. */
double cvk_chebyshev_stable_rho(uint32_t accelerated_sweeps);

/* Chebyshev weight of sweep s (0-based, counted within its cycle): 1 for s < delay
   (at least one plain sweep), then Wang's recurrence w = 2/(2 − ρ²), w ← 4/(4 − ρ² w). */
double cvk_chebyshev_weight(uint32_t sweep, uint32_t delay, double rho);

/* Spectral radius of the relaxed Jacobi iteration matrix I − omega D⁻¹A of the PD system
   (A = M/h² + spring Laplacian over free particles), by power iteration on its square. */
double cvk_estimate_jacobi_rho(const cvk_build* build, double inv_h2, double omega);

#endif
