/* Projective dynamics (Liu et al. 2013) with Verlet prediction in displacement form: the one
   solver family today. Its linear solvers: rbgs (multi-colour Gauss-Seidel), jacobi and
   chebyshev on the device; gs-cpu, the sequential double-precision host reference. */
#ifndef CVK_SOLVE_PD_H
#define CVK_SOLVE_PD_H

#include "shared/layout.h"
#include "plan/state.h"
#include "solvers/solver.h"

/* Descriptor sets differ only in which displacement buffer is src and which is dst. */
typedef enum cvk_pd_set {
    CVK_PD_SET_U0_TO_U1,
    CVK_PD_SET_U1_TO_U0,
    CVK_PD_SET_U0_TO_U0,
    CVK_PD_SET_COUNT
} cvk_pd_set;

typedef struct cvk_pd {
    /* Two displacement iterates (u[0] holds the last substep's displacement: the velocity
       times h), the predicted displacement, the right-hand side; adjacency in quads of slots:
       uvec4 neighbours and bits of k, and vec4 L (see pd_common.glsl). */
    cvk_buffer u[2], y, rhs, adjacency, adjacency_rest;
    VkBufferView view_u[2], view_y, view_rhs, view_adjacency, view_adjacency_rest;
    /* Tethers (tether.h): uvec4 pins and vec4 lengths per free particle; one texel each
       when the scene has none. */
    cvk_buffer tether_anchor, tether_length;
    VkBufferView view_tether_anchor, view_tether_length;
    /* Solves that stop when converged (shared/layout.h): CVK_PD_PARTIALS partial sums and a
       squared residual per free particle (`sums`), and cvk_pd_scalars with the indirect
       commands (`scalars`, host-visible: read for the statistics), which only the check's own
       set binds. */
    cvk_buffer sums, scalars;
    /* The rest memory (see below): vec4 per free particle (one when none), zero from the
       host; read back through cvk_buffer_download. */
    cvk_buffer rest;
    cvk_descriptors converge_descriptors; /* one set: sums, scalars */
    cvk_descriptors descriptors; /* CVK_PD_SET_COUNT sets */
    VkCommandBuffer readback_cmd; /* positions and u[0] -> staging, recorded once */

    double rho_estimate;  /* Chebyshev's spectral radius estimated for rho_omega; < 0: none */
    float rho_omega;
    double chebyshev_rho; /* of the current plan, after the stability cap */
    double chebyshev_rho_estimated;

    bool host;            /* gs-cpu: the state lives in the host arrays below */
    double* hx;           /* 3 doubles per particle, internal order */
    double* hprev;
    double* hy;
    double* hrhs;         /* 4 doubles per particle */
    double* hrest;        /* the rest memory, 3 doubles per particle (pinned: 0) */
    uint32_t* h_alive;    /* gs-cpu with tearing: its spring flags (tear.h) */
    float* h_adj_k;       /* gs-cpu with tearing: build.adj_k with torn springs at 0 */
    float* scratch_u;     /* last displacements x_n − x_{n−1}, 3 floats per particle */
} cvk_pd;

/* The rest memory. A truncated solve started from the prediction y = x_n + (1 − damping) u +
   h² g leaves part of every error it starts with: at rest (x_n the equilibrium x*, u = 0) it
   returns x* + E (y − x*) = x* + E h² g, where E is the error operator of the substep's sweeps,
   close to the identity for the smooth modes of a stiff cloth; so a cloth came to rest millimetres
   from its equilibrium. The solve therefore starts from y + r, where r, per free particle, is a
   low-pass of the corrections the solves made to their predictions:
       r ← r + rate · ((x_{n+1} − y_n) − r)   after each substep,
   while the inertial target of the solve stays y. At rest r converges to the exact correction
   x* − y, the first iterate becomes x* itself, which every sweep keeps, and the cloth rests at
   its equilibrium to float rounding, for every linear solver and iteration count. The rate is
   tied to the damping: rate = CVK_REST_RATE_PER_DAMPING · damping (cvk_ref_params_of), 0 without
   damping or integration. Modelling one mode (exact solve y / (1 + s), truncated solve leaving
   c of the error, velocity kept times 1 − damping), the memory is stable for real c in [0, 1)
   (Gauss-Seidel at omega 1, Jacobi) when rate ≤ damping, and unstable for every rate when the
   damping is 0; a full memory (rate 1) is unstable for c > 1/2 (a limit cycle of 1 mm with
   rbgs 4 x 4). Complex c (SOR) and negative c (Chebyshev) grow marginally at rate = damping and
   less at a quarter of it. r relaxes with a time constant of 1 / rate substeps (longer for soft
   modes the sweeps barely correct); it is reset to 0 wherever positions are written from the
   host, and travels in snapshots and solver switches.
   Scenes with contact (colliders or self-contact) have none: the memory is per particle while a
   contact correction belongs to a place, so a cloth sliding over a collider carried corrections
   it no longer needed (funnel.json at frame 60: largest stretch 8.3 % -> 26.5 %, residual 3x;
   sphere-hit.json +25 %, box-stack.json +23 %).
   Solves that stop when converged (solver.tolerance on the device) have none: their measure is
   relative to the residual at the first iterate, which the memory makes vanish at rest, so the
   solve would never stop there (a tethered cloth at rest: 3200 sweeps a frame, the cap, where
   it stopped at well under half its first frames'). */

/* Uploads the adjacency tables from the build, the springs whose flag in `alive` is 0 (torn;
   alive NULL: none) with k = 0, as tearing leaves them (tear.h). */
cvk_result cvk_pd_upload_adjacency(cvk_sim* sim, cvk_pd* pd, const uint32_t* alive,
                                   cvk_error* error);

/* Puts the torn state `alive` (uint per spring, 0 = torn) in place everywhere: the spring
   flags, the device adjacency and, where gs-cpu's host arrays exist, those (tear.h). */
cvk_result cvk_pd_set_torn(cvk_sim* sim, void* pd, const uint32_t* alive, cvk_error* error);

/* Uploads the gs-cpu positions (hx) into the positions buffer, for drawing and reading. */
cvk_result cvk_pd_upload_host_positions(cvk_sim* sim, cvk_pd* pd, cvk_error* error);

/* Copies the staging buffer's positions (first n vec4) and last displacements (next n vec4)
   into the device state: positions, u[0], and u[1] and y, which start equal to u[0] (each
   substep overwrites them first). */
cvk_result cvk_pd_upload_staged_state(cvk_sim* sim, cvk_pd* pd, cvk_error* error);

/* Exact snapshots of the family's state (solve_pd_snapshot.c; see cvk_family_api). */
uint64_t cvk_pd_snapshot_size(const cvk_sim* sim, const void* self);
cvk_result cvk_pd_save_snapshot(cvk_sim* sim, void* self, void* data, cvk_error* error);
cvk_result cvk_pd_load_snapshot(cvk_sim* sim, void* self, const void* data, uint64_t size,
                                cvk_error* error);

/* The passes of one substep of `solver` (pd_passes.c). */
cvk_result cvk_pd_add_passes(cvk_sim* sim, void* self, const cvk_solver_desc* solver,
                             cvk_plan* plan, cvk_error* error);

/* Fused sweeps (pd_fused.c, shaders/solvers/pd_fused.comp). rbgs runs every sweep of an outer
   iteration (the local step's first sweep, then inner_iterations sweeps of every colour, colours
   in order) in one dispatch of one workgroup, whose invocations stride over each colour with a
   workgroup barrier between colours: the same floating-point operations in the same order per
   particle as the unfused dispatches, so the same iterate bit for bit. The passes between outer
   iterations — the strain limit's rounds, tethers, contact between cloths, contact — and after
   the last one finalize run in the same dispatch after the sweeps (pd_passes.c:
   fuse_after_outer), colour by colour and pass by pass with a barrier between. Every fused sweep keeps particles within their contact
   bounds as the unfused do. Where the sweeps fuse, so do the contact detection's decision and hash
   builds (cvk_plan.fused, lib/contact/collide.h).
   On an NVIDIA H200 two self-contact scenes of test_determinism gave other bits fused than
   unfused (docs/limits.md, Solvers; the cause is not found).
   A scene of instances (copies that never touch, without self-contact) runs a workgroup a copy
   in the same dispatch (cvk_pd_fused_copies), its prediction a dispatch of its own before it.
   Each workgroup keeps its copy's iterate in shared memory while it sweeps where it fits
   (cvk_sim.fused_shared_slots, cvk_sim_desc.fused_shared_memory), the same bits.
   Returns why the plan does not fuse (a sentence), or NULL when it does: solver.fuse auto never
   fuses, as the fused dispatch was slower on every device measured. */
const char* cvk_pd_fuse_refusal(const cvk_build* b, const cvk_solver_desc* solver, bool checking,
                                uint32_t copies);

/* The copies a fused dispatch takes a workgroup each: `instances` where the build lays them out
   as shared/layout.h's cvk_pd_fused_push says (equal copies, each's particles of a colour one
   after another, at most CVK_PD_FUSED_MAX_PARTICLES free particles a copy), else 1. */
uint32_t cvk_pd_fused_copies(const cvk_build* b, uint32_t instances);

/* cvk_pd_fuse_refusal for `requested` (resolved) on `sim`: the family's fuse_refusal
   (lib/plan/family.h). */
const char* cvk_pd_plan_fuse_refusal(const cvk_sim* sim, const cvk_solver_desc* requested);

/* The push data of the fused pass over every colour of `b`: `outers` outer iterations of
   `sweeps` sweeps, the last sweep of each at `last_omega` (cvk_gs_sweep_omega), `copies` a
   workgroup each (cvk_pd_fused_copies). */
cvk_pd_fused_push cvk_pd_fused_push_of(const cvk_pd_push* base, const cvk_build* b,
                                       uint32_t sweeps, uint32_t outers, float last_omega,
                                       uint32_t copies);

/* Appends the fused pass: a workgroup a copy, with `pipeline` (a build of pd_fused.comp). */
cvk_op* cvk_pd_add_fused(cvk_plan* plan, uint32_t pass, VkPipelineLayout layout,
                         VkDescriptorSet set, const cvk_pd_fused_push* push,
                         cvk_pipeline_id pipeline);

/* The pd family's part of the statistics: sweeps of the last frame and since creation, counted
   on the device when the plan checks for convergence, else the sweeps the plan records. */
void cvk_pd_stats(const cvk_sim* sim, cvk_sim_stats* st);

/* Chebyshev's ρ for `solver` at step h: solver->chebyshev_rho when set, else `estimated`
   when ≥ 0, else estimated here; capped for stability. *estimated_out (if not NULL) gets ρ
   before the cap. */
double cvk_pd_chebyshev_rho(const cvk_solver_desc* solver, double h, const cvk_build* build,
                            double estimated, double* estimated_out);

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
