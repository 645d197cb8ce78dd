/* Structs and binding numbers that C and GLSL both read, declared once. A shader includes this
   file (GL_GOOGLE_include_directive) and gets GLSL blocks; C gets structs with the same layout,
   checked by static asserts in lib/core/pipelines.c. Push constants use std430-like packing: scalars
   at 4 bytes, vec4 at 16; keep vec4 members on 16-byte offsets. */
#ifndef CVK_SHARED_LAYOUT_H
#define CVK_SHARED_LAYOUT_H

#ifdef GL_core_profile
#define CVK_UINT(name) uint name;
#define CVK_FLOAT(name) float name;
#define CVK_VEC4(name) vec4 name;
#define CVK_UVEC4(name) uvec4 name;
/* A shader declares its one push block itself: CVK_DECLARE_PUSH(CVK_PD_PUSH_FIELDS). */
#define CVK_PUSH_BLOCK(type, fields)
#define CVK_DECLARE_PUSH(fields) layout(push_constant) uniform Push { fields } pc;
/* A struct both sides use as an array element of a storage buffer (std430). */
#define CVK_STRUCT(type, fields) struct type { fields };
#else
#include <stdint.h>
#define CVK_UINT(name) uint32_t name;
#define CVK_FLOAT(name) float name;
#define CVK_VEC4(name) float name[4];
#define CVK_UVEC4(name) uint32_t name[4];
#define CVK_PUSH_BLOCK(type, fields) typedef struct type { fields } type;
#define CVK_STRUCT(type, fields) typedef struct type { fields } type;
#endif

/* ---- projective dynamics: predict, finalize, pd_gauss_seidel, pd_jacobi ------------------ */

#define CVK_PD_PUSH_FIELDS                                                              \
    CVK_UINT(first)        /* first particle of this dispatch */                         \
    CVK_UINT(count)        /* particles in this dispatch */                              \
    CVK_UINT(stride)       /* free particle count: adjacency slot stride */              \
    CVK_FLOAT(max_u2)      /* finalize: |u|^2 beyond this is a run-away, m^2; 0: none */\
    CVK_FLOAT(inv_h2)      /* 1 / h^2, 1/s^2 */                                          \
    CVK_FLOAT(omega)       /* SOR factor (Gauss-Seidel) or relaxation (Jacobi) */        \
    CVK_FLOAT(cheb)        /* Chebyshev weight of this sweep; 1 = plain sweep */         \
    CVK_FLOAT(keep)        /* 1 - damping (0 when integration is off) */                 \
    CVK_VEC4(gravity_h2)   /* h^2 g, m (0 when integration is off) */                 \
    CVK_FLOAT(rest_rate)   /* rest memory's rate (lib/solvers/solve_pd.h); 0: none */

CVK_PUSH_BLOCK(cvk_pd_push, CVK_PD_PUSH_FIELDS)

/* The fused Gauss-Seidel pass (shaders/solvers/pd_fused.comp): every outer iteration of a
   substep in one workgroup, each one's sweeps colour by colour, and after them the passes
   between outer iterations that follow them there (`after`: the strain limit's round, tethers,
   contact, after the last outer iteration the strain limit's 3 rounds after contact, finalize).
   cvk_pd_push first (first: 0, count: the free particles), then the iterations (sweeps of an
   outer iteration in bits 0-15, outer iterations in bits 16-31), colours (bits 0-7) and copies
   (bits 8-31: instances, a workgroup each, or 1), each colour's end in a copy as 16-bit halves:
   colour c ends at half c % 2 of uint (c / 2) % 4 of ends[c / 8] (copy k's colour c: [C s + k
   n, C s + (k + 1) n), s and n its start and size in a copy, lib/topology/build.h); `after`
   holds the CVK_PD_FUSED_* bits of every outer iteration but the last in bits 0-7
   (CVK_PD_FUSED_TETHERS there: after every `tether_every`-th), the last one's in bits 8-15,
   tether_every in bits 16-30 and CVK_PD_FUSED_PREDICT in bit 31 (the prediction first,
   predict.glsl). So at most CVK_PD_FUSED_MAX_COLOURS colours and CVK_PD_FUSED_MAX_PARTICLES
   free particles a copy. 128 bytes: Vulkan's guaranteed push constant size. */
#define CVK_PD_FUSED_MAX_COLOURS 24u
#define CVK_PD_FUSED_MAX_PARTICLES 65535u
#define CVK_PD_FUSED_STRAIN 1u       /* after: one round of the strain limit */
#define CVK_PD_FUSED_CLOTH_CONTACT 2u /* after: contact between cloths (listed particles) */
#define CVK_PD_FUSED_CONTACT 4u      /* after: contact over contact_count particles */
#define CVK_PD_FUSED_LAST 8u         /* after: the strain limit's three rounds after contact */
#define CVK_PD_FUSED_TETHERS 16u     /* after: the tethers (after the strain limit's round) */
#define CVK_PD_FUSED_FINALIZE 32u    /* last: finalize over finalize_count particles */
#define CVK_PD_FUSED_TETHERED 64u    /* finalize projects the last tethers first */
#define CVK_PD_FUSED_PREDICT 0x80000000u /* before the first outer iteration: predict */
#define CVK_PD_FUSED_PUSH_FIELDS                                                        \
    CVK_PD_PUSH_FIELDS                                                                  \
    CVK_UINT(iterations)   /* inner | outer << 16 (solver.inner/outer_iterations) */    \
    CVK_UINT(colours)      /* colours (at most CVK_PD_FUSED_MAX_COLOURS) | copies << 8 */\
    CVK_FLOAT(last_omega)  /* omega of the last sweep (cvk_gs_sweep_omega) */             \
    CVK_UVEC4(ends0)       /* colour ends 0..7 */                                       \
    CVK_UVEC4(ends1)       /* 8..15 */                                                  \
    CVK_UVEC4(ends2)       /* 16..23 */                                                 \
    CVK_UINT(after)        /* the passes after the sweeps: CVK_PD_FUSED_* bits (above) */\
    CVK_UINT(contact_count) /* particles of the contact pass (CVK_PD_FUSED_CONTACT) */   \
    CVK_FLOAT(strain_limit) /* 1 + solver.strain_limit, as the strain pass's omega */   \
    CVK_UINT(finalize_count) /* particles of finalize (CVK_PD_FUSED_FINALIZE) */

CVK_PUSH_BLOCK(cvk_pd_fused_push, CVK_PD_FUSED_PUSH_FIELDS)

/* Bindings of the projective-dynamics set (shaders/solvers/pd_common.glsl). */
#define CVK_PD_BINDING_SRC 0           /* texel: displacement iterate read */
#define CVK_PD_BINDING_DST_READ 1      /* texel: iterate being written, read */
#define CVK_PD_BINDING_DST 2           /* storage: iterate written */
#define CVK_PD_BINDING_Y_READ 3        /* texel: predicted u, w: m/h^2 */
#define CVK_PD_BINDING_Y 4             /* storage */
#define CVK_PD_BINDING_X_READ 5        /* texel: x_n, w: m/h^2 */
#define CVK_PD_BINDING_X 6             /* storage */
#define CVK_PD_BINDING_RHS_READ 7      /* texel: w y + r, w (solvers/pd_common.glsl local_step) */
#define CVK_PD_BINDING_RHS 8           /* storage */
#define CVK_PD_BINDING_ADJACENCY 9     /* texel: neighbours, bits of k, by quad */
#define CVK_PD_BINDING_ADJACENCY_REST 10 /* texel: rest lengths, by quad */
#define CVK_PD_BINDING_WATCH 11        /* storage: cvk_gpu_watch */
#define CVK_PD_BINDING_EXTERNAL 12     /* texel: h^2 F / m of the air per free particle (WIND) */
#define CVK_PD_BINDING_TETHER_ANCHOR 13 /* texel: uvec4 per free particle, pinned indices */
#define CVK_PD_BINDING_TETHER_LENGTH 14 /* texel: vec4 per free particle, m */
#define CVK_PD_BINDING_CONVERGE 15     /* storage: partial sums, squared residuals */
#define CVK_PD_BINDING_REST 16        /* storage: rest memory, mean correction (solve_pd.h) */
#define CVK_PD_BINDING_SRC_BUFFER 17  /* storage: the iterate SRC reads (the fused sweeps) */
#define CVK_PD_BINDING_COUNT 18

/* Solves that stop when converged (solver.tolerance; lib/solvers/pd_passes.c,
   shaders/solvers/pd_converge.comp).
   The measure: the first sweep of every outer iteration computes, besides its local step, the
   residual of the springs' system at the iterate it reads, scaled by the diagonal:
   d_p = (b_p + sum_c k_c u_c) / diag_p - u_p (the move one Jacobi sweep would make there), and
   writes |d_p|^2; a reduction sums them in a fixed order into CVK_PD_PARTIALS partial sums
   whatever the dispatch shape, and one invocation compares the sum with tol2 (the squared
   tolerance) times the sum at the substep's first iterate: the relative residual is |d| / |d_0|.
   Once below, it zeroes the indirect commands of every later pass of the substep. */
#define CVK_PD_PARTIALS 256u

/* Bindings of the check's own set (shaders/solvers/pd_converge.comp, MODE 0 and 1): the partial
   sums and residuals (the buffer the checking sweeps write as CVK_PD_BINDING_CONVERGE) and the
   cvk_pd_scalars, which hold the indirect commands and which nothing else binds. */
#define CVK_PD_CONVERGE_BINDING_SUMS 0
#define CVK_PD_CONVERGE_BINDING_SCALARS 1
#define CVK_PD_CONVERGE_BINDING_COUNT 2

#define CVK_PD_CONVERGE_PUSH_FIELDS                                                     \
    CVK_UINT(stride)       /* free particle count */                                     \
    CVK_UINT(swept)        /* decide: sweeps run when the measured sweep ends */         \
    CVK_UINT(sweeps)       /* decide: sweeps the plan records per substep */             \
    CVK_UINT(in_u1)        /* decide: the measured iterate lies in u1 (else u0) */       \
    CVK_UINT(first_check)  /* decide: the substep's first check: its first iterate */    \
    CVK_UINT(last_check)   /* decide: no check after this one */                         \
    CVK_FLOAT(tol2)        /* decide: stop when |d|^2 <= tol2 |d_0|^2 */                 \
    CVK_UINT(sweep_groups) /* decide: groups of the sweeps, tethers and the copy */      \
    CVK_UINT(contact_groups) /* decide: groups of the contact pass */                    \
    CVK_UINT(reduce_groups)  /* decide: groups of the reduction */

CVK_PUSH_BLOCK(cvk_pd_converge_push, CVK_PD_CONVERGE_PUSH_FIELDS)

/* The convergence state, on the device (host-visible, read for the statistics): converged
   this substep; iterations (sweeps) of the last substep, of this frame (zeroed by a fill at its
   first substep) and since creation; residual: the last relative residual measured; checks:
   decisions taken since creation; start: |d_0|^2 of this substep's first iterate; then the
   indirect commands (x, y, z groups) of the passes after the substep's first check: sweeps
   (also tethers), contact, the reduction, the one-invocation decision and the copy of a
   converged iterate from u1 to u0 (finalize reads u0). */
#define CVK_PD_SCALARS_FIELDS       \
    CVK_UINT(converged)             \
    CVK_UINT(iterations)            \
    CVK_UINT(frame_iterations)      \
    CVK_UINT(total_iterations)      \
    CVK_FLOAT(residual)             \
    CVK_UINT(checks)                \
    CVK_FLOAT(start)                \
    CVK_UINT(pad1)                  \
    CVK_UINT(sweep_groups)          \
    CVK_UINT(sweep_y)               \
    CVK_UINT(sweep_z)               \
    CVK_UINT(contact_groups)        \
    CVK_UINT(contact_y)             \
    CVK_UINT(contact_z)             \
    CVK_UINT(reduce_groups)         \
    CVK_UINT(reduce_y)              \
    CVK_UINT(reduce_z)              \
    CVK_UINT(single_groups)         \
    CVK_UINT(single_y)              \
    CVK_UINT(single_z)              \
    CVK_UINT(copy_groups)           \
    CVK_UINT(copy_y)                \
    CVK_UINT(copy_z)                \
    CVK_UINT(pad2)
CVK_STRUCT(cvk_pd_scalars, CVK_PD_SCALARS_FIELDS)

/* Tethers (lib/topology/build.h, shaders/solvers/pd_tether.comp): a particle is projected onto each of its
   tethers' spheres in turn, at most this many rounds (a round that moves nothing ends it):
   one projection can take it out of another sphere, and repeating them converges into the
   intersection. */
#define CVK_TETHER_ROUNDS 2u

/* The divergence watch (lib/sim/sim.h): predict counts substeps and flags a spring stretched past
   CVK_DIVERGED_STRETCH in the positions it starts from (nothing writes them while it runs);
   finalize records the first substep at which a particle's new position is not finite, its
   step exceeds max_u2 or predict raised the flag, and from then on moves no particle.
   Host-visible: cvk_sim_step reads it after its fence, with no extra submission. */
#define CVK_WATCH_NONE 0xffffffffu
#define CVK_WATCH_NONFINITE 1u
#define CVK_WATCH_RUNAWAY 2u
#define CVK_GPU_WATCH_FIELDS                                                            \
    CVK_UINT(substep)      /* substeps predicted since the watch was reset */           \
    CVK_UINT(diverged_at)  /* the substep (counted from 1) it diverged at, or NONE */    \
    CVK_UINT(particle)     /* the lowest internal index that diverged then */           \
    CVK_UINT(reason)       /* CVK_WATCH_NONFINITE | CVK_WATCH_RUNAWAY */                \
    CVK_UINT(stretched)    /* set by predict: a spring is past the stretch bound */     \
    CVK_UINT(contact_cut)  /* the contact frame state's cut, copied at each frame's end */ \
    CVK_UINT(sweeps_cut)   /* the fused sweeps' loops ended early (pd_fused.comp) */
CVK_STRUCT(cvk_gpu_watch, CVK_GPU_WATCH_FIELDS)

/* ---- implicit Euler: solvers/implicit_*.comp (lib/solvers/solve_implicit.c) ----------------------- */

#define CVK_IMPLICIT_PUSH_FIELDS                                                        \
    CVK_UINT(count)        /* particles (or partial sums, for reductions) covered */     \
    CVK_UINT(stride)       /* free particle count: adjacency slot stride */              \
    CVK_UINT(partials)     /* invocations of a reduction pass = partial sums */          \
    CVK_UINT(clamp)        /* 1: compressive part of each spring block clamped at 0 */   \
    CVK_FLOAT(h)           /* substep, s */                                              \
    CVK_FLOAT(tol2)        /* squared relative residual where the solve stops */         \
    CVK_FLOAT(kd)          /* spring damping, N s/m */                                   \
    CVK_FLOAT(keep)        /* 1 - damping (velocity kept per substep) */                 \
    CVK_VEC4(gravity)      /* m/s^2 (0 when integration is off) */

CVK_PUSH_BLOCK(cvk_implicit_push, CVK_IMPLICIT_PUSH_FIELDS)

/* The solve's scalars, on the device only: CG's rho (r.z), its first value, alpha and beta;
   converged: every pass of the solve does nothing once set; iterations of this substep and of
   this frame (the frame's is zeroed by a fill at its first substep); result: the iterate
   holding the solution (Jacobi ping-pongs); breakdown: substeps whose CG met p.Ap <= 0;
   total_iterations: since the simulation started. Then three indirect dispatch commands
   (x, y, z groups) the solve's passes are dispatched with: reductions, particle passes and
   one-invocation passes; the assembly fills them and the stop test zeroes them, so a
   converged solve's remaining passes dispatch no workgroups at all. */
#define CVK_IMPLICIT_SCALARS_FIELDS \
    CVK_FLOAT(rho)                  \
    CVK_FLOAT(rho0)                 \
    CVK_FLOAT(alpha)                \
    CVK_FLOAT(beta)                 \
    CVK_UINT(converged)             \
    CVK_UINT(iterations)            \
    CVK_UINT(frame_iterations)      \
    CVK_UINT(result)                \
    CVK_UINT(breakdown)             \
    CVK_UINT(total_iterations)      \
    CVK_UINT(pad1)                  \
    CVK_UINT(pad2)                  \
    CVK_UINT(reduce_groups)         \
    CVK_UINT(reduce_y)              \
    CVK_UINT(reduce_z)              \
    CVK_UINT(particle_groups)       \
    CVK_UINT(particle_y)            \
    CVK_UINT(particle_z)            \
    CVK_UINT(single_groups)         \
    CVK_UINT(single_y)              \
    CVK_UINT(single_z)
CVK_STRUCT(cvk_implicit_scalars, CVK_IMPLICIT_SCALARS_FIELDS)

/* Bindings of the implicit set (shaders/solvers/implicit_common.glsl), vec4 per item. */
#define CVK_IMPLICIT_BINDING_X 0          /* positions, all particles */
#define CVK_IMPLICIT_BINDING_V 1          /* velocities, all particles (w: mass, kg) */
#define CVK_IMPLICIT_BINDING_ADJACENCY 2  /* per slot (slot-major): neighbour, k, rest (bits) */
#define CVK_IMPLICIT_BINDING_DIAG 3       /* 4 per free particle: A_pp, then its inverse */
#define CVK_IMPLICIT_BINDING_OFFDIAG 4    /* 2 per slot: the block H with A_pc = -H */
#define CVK_IMPLICIT_BINDING_B 5          /* right-hand side */
#define CVK_IMPLICIT_BINDING_DV0 6        /* the unknown dv (CG; Jacobi's first iterate) */
#define CVK_IMPLICIT_BINDING_DV1 7        /* Jacobi's second iterate */
#define CVK_IMPLICIT_BINDING_R 8          /* CG residual */
#define CVK_IMPLICIT_BINDING_Z 9          /* preconditioned residual */
#define CVK_IMPLICIT_BINDING_P 10         /* search direction */
#define CVK_IMPLICIT_BINDING_Q 11         /* A p */
#define CVK_IMPLICIT_BINDING_PARTIALS 12  /* float per reduction invocation */
#define CVK_IMPLICIT_BINDING_SCALARS 13   /* cvk_implicit_scalars */
/* The product's reads as texels (a gather on lavapipe, where storage loads go lane by lane) */
#define CVK_IMPLICIT_BINDING_P_READ 14          /* texel: search direction */
#define CVK_IMPLICIT_BINDING_OFFDIAG_READ 15    /* texel: off-diagonal blocks */
/* Per free particle: the contact filter of this substep, (n, 1 + k) for a particle held on
   collider k along its unit normal n (S = I - n n^T; -(1 + k) once released), 0 for a free one
   (solvers/implicit_contact.comp, solvers/implicit_integrate.comp) */
#define CVK_IMPLICIT_BINDING_FILTER 16
#define CVK_IMPLICIT_BINDING_COUNT 17

/* ---- explicit integrators: solvers/explicit_{force,update}.comp (lib/solvers/solve_explicit.c) ----- */

/* What explicit_update does (mode) */
#define CVK_EXPLICIT_EULER 0u       /* v' = v + h a, x' = x + h v */
#define CVK_EXPLICIT_RK2_STAGE 1u   /* xs = x + h v, vs = v + h a */
#define CVK_EXPLICIT_RK2_COMBINE 2u /* x' = (x + xs + h vs) / 2, v' = (v + vs + h as) / 2 */
#define CVK_EXPLICIT_AB4 3u         /* 4th-order Adams-Bashforth from the history (euler at first) */
#define CVK_EXPLICIT_VERLET 4u      /* v' = v + h a, x' = x + h v' */
#define CVK_EXPLICIT_HISTORY 6u     /* vec4 per free particle: a_n-1..a_n-3 (w of the first: steps
                                       held), then v_n-1..v_n-3 */

#define CVK_EXPLICIT_PUSH_FIELDS                                                          \
    CVK_UINT(count)        /* free particles */                                            \
    CVK_UINT(stride)       /* free particle count: adjacency slot stride */                \
    CVK_UINT(mode)         /* update: CVK_EXPLICIT_*; force: 1 counts the substep */       \
    CVK_UINT(viscosity)    /* 1: artificial viscosity, 0: damping along the spring */      \
    CVK_FLOAT(h)           /* substep, s */                                                \
    CVK_FLOAT(kd)          /* damping, N s/m */                                            \
    CVK_FLOAT(keep)        /* 1 - damping (velocity kept per substep) */                   \
    CVK_FLOAT(max_u2)      /* |x' - x|^2 beyond this is a run-away, m^2 */                 \
    CVK_VEC4(gravity)      /* m/s^2 (0 when integration is off) */

CVK_PUSH_BLOCK(cvk_explicit_push, CVK_EXPLICIT_PUSH_FIELDS)

/* Bindings of the explicit set (two sets: the force pass reads X_IN/V_IN, the state in set 0
   and the RK2 stage in set 1); storage buffers, vec4 per particle. */
#define CVK_EXPLICIT_BINDING_X 0          /* positions, all particles */
#define CVK_EXPLICIT_BINDING_V 1          /* velocities, all particles (w: mass, kg) */
#define CVK_EXPLICIT_BINDING_XS 2         /* RK2 stage positions, free particles */
#define CVK_EXPLICIT_BINDING_VS 3         /* RK2 stage velocities, free particles */
#define CVK_EXPLICIT_BINDING_ADJACENCY 4  /* per slot (slot-major): neighbour, k, rest (bits) */
#define CVK_EXPLICIT_BINDING_A 5          /* accelerations, free particles */
#define CVK_EXPLICIT_BINDING_HISTORY 6    /* Adams-Bashforth history, CVK_EXPLICIT_HISTORY each */
#define CVK_EXPLICIT_BINDING_WATCH 7      /* cvk_gpu_watch */
#define CVK_EXPLICIT_BINDING_X_IN 8       /* the force pass's positions (X or XS) */
#define CVK_EXPLICIT_BINDING_V_IN 9       /* the force pass's velocities (V or VS) */
#define CVK_EXPLICIT_BINDING_COUNT 10

/* ---- mesh generation: render/mesh.comp ----------------------------------------------------- */

#define CVK_MESH_PUSH_FIELDS \
    CVK_UINT(vertex_count)   \
    CVK_UINT(triangle_count) \
    CVK_UINT(rim_edge_count)

CVK_PUSH_BLOCK(cvk_mesh_push, CVK_MESH_PUSH_FIELDS)

/* In the mesh generation's vertex table (vertex -> particle): the vertex is drawn at its
   particle, never smoothed along a torn border (lib/render/mesh.c, make_particle_of). */
#define CVK_MESH_HELD 0x80000000u

/* ---- collisions: the contact set (lib/contact/collide.h, shaders/contact/collide.glsl) ----------- */

/* The frame state the recorded work advances itself: substeps simulated so far (simulated
   time at the start of substep n is n · dt), and for cloth contact when detection runs and the
   common shift of the displacement bounds (lib/contact/collide.h: contact_check.comp and
   contact_decide.comp). */
#define CVK_GPU_FRAME_FIELDS                                                                 \
    CVK_UINT(step)                                                                          \
    CVK_UINT(search)   /* 1: this substep detects (the hash build and the detection run) */ \
    CVK_UINT(longest)  /* detecting: the longest edge now (float bits, contact_edges.comp) */ \
    CVK_UINT(force)    /* 1: detect at the next substep whatever moved (start, state written) */ \
    CVK_UINT(searches) /* detections so far */                                              \
    CVK_FLOAT(shift_x) /* m: the common shift M of the bounds (collide.h): every particle */ \
    CVK_FLOAT(shift_y) /* stays within its bound of where detection saw it plus M */        \
    CVK_FLOAT(shift_z)                                                                      \
    CVK_UINT(held_lo)  /* free particles that ended a substep past redetect of their bound, */ \
    CVK_UINT(held_hi)  /* summed over the substeps so far: a 64-bit count, low word first */  \
    CVK_UINT(held_substeps) /* the substeps counted (each but a first after a state write) */ \
    CVK_UINT(cut)      /* 1 once a detection pass's loops ended early (bounds.glsl's note_loops_cut) */ \
    CVK_UINT(crowded_lo) /* particles a corner in more pairs than their side lists hold,   */ \
    CVK_UINT(crowded_hi) /* summed over the detections so far: 64 bits, low word first    */
CVK_STRUCT(cvk_gpu_frame, CVK_GPU_FRAME_FIELDS)

/* After the frame state in its buffer: what the decision at the start of a substep gathers
   (contact_check.comp) — per axis, order-preserving bits of the floats, the bounds of each
   particle's displacement since detection extrapolated over the substep (e) and of its last
   substep's displacement (v); why it must or may detect (exceed: bounds.glsl's bits); whether
   a particle is near a collider (no shift at a detection then); the shift for the substep if
   it does not detect. Reset by the decision, so snapshots need not carry them. */
#define CVK_GPU_MOTION_BOUNDS_FIELDS \
    CVK_UINT(e_low_x)                \
    CVK_UINT(e_low_y)                \
    CVK_UINT(e_low_z)                \
    CVK_UINT(e_high_x)               \
    CVK_UINT(e_high_y)               \
    CVK_UINT(e_high_z)               \
    CVK_UINT(v_low_x)                \
    CVK_UINT(v_low_y)                \
    CVK_UINT(v_low_z)                \
    CVK_UINT(v_high_x)               \
    CVK_UINT(v_high_y)               \
    CVK_UINT(v_high_z)               \
    CVK_UINT(exceed)                 \
    CVK_UINT(near)                   \
    CVK_UINT(spread) /* detecting: the farthest a triangle's corner is from its centroid (float bits) */ \
    CVK_FLOAT(next_x)                \
    CVK_FLOAT(next_y)                \
    CVK_FLOAT(next_z)                \
    CVK_UINT(held) /* free particles the last substep ended near their bound (frame.held_*) */
CVK_STRUCT(cvk_gpu_motion_bounds, CVK_GPU_MOTION_BOUNDS_FIELDS)
#define CVK_MOTION_LOW_EMPTY 0xffffffffu /* the bounds' reset state: low above high */
#define CVK_MOTION_HIGH_EMPTY 0u

/* A collider's rigid pose at the start (0) and end (1) of the current substep: a point p of the
   collider at rest is at translation + rotate(rotation, p). Quaternions as (x, y, z, w). After
   a frame, pose 1 is the pose at the frame's end (what a renderer draws). */
#define CVK_GPU_POSE_FIELDS  \
    CVK_VEC4(rotation0)      \
    CVK_VEC4(translation0)   \
    CVK_VEC4(rotation1)      \
    CVK_VEC4(translation1)
CVK_STRUCT(cvk_gpu_pose, CVK_GPU_POSE_FIELDS)

/* One collider's shape at rest (scene coordinates before its motion). */
#define CVK_COLLIDER_PLANE_ID 0
#define CVK_COLLIDER_SPHERE_ID 1
#define CVK_COLLIDER_BOX_ID 2
#define CVK_COLLIDER_CAPSULE_ID 3
#define CVK_COLLIDER_FUNNEL_ID 4
#define CVK_COLLIDER_MESH_ID 5
#define CVK_GPU_COLLIDER_FIELDS                                                            \
    CVK_UINT(type)            /* CVK_COLLIDER_*_ID */                                       \
    CVK_UINT(keyframe_first)  /* into the keyframe buffer */                                \
    CVK_UINT(keyframe_count)                                                                \
    CVK_UINT(loop)                                                                          \
    CVK_FLOAT(friction)       /* kinetic */                                                 \
    CVK_FLOAT(static_friction)                                                              \
    CVK_UINT(sdf_first)       /* mesh: first value in the field buffer */                   \
    CVK_UINT(pad0)                                                                          \
    CVK_VEC4(a)  /* plane point | sphere centre, radius | box centre | capsule a, radius |   \
                    funnel apex, growth length | mesh field origin, voxel */                \
    CVK_VEC4(b)  /* plane unit normal | box half extents | capsule b | funnel height |       \
                    mesh field dims (as floats) */                                          \
    CVK_VEC4(c)  /* box rotation (x, y, z, w) */
CVK_STRUCT(cvk_gpu_collider, CVK_GPU_COLLIDER_FIELDS)

/* Cloth contact (lib/contact/collide.h): per particle, the nearest features (a triangle's
   face, an edge or a vertex) within the contact radius at the last detection, nearest first;
   per edge, the nearest other edges. An entry is feature << 2 | kind. */
#define CVK_CONTACTS_PER_PARTICLE 8
#define CVK_CONTACTS_PER_EDGE 4
/* Per edge, the pairs edge detection's distance pass keeps to list (more: walked again). */
#define CVK_EDGE_BUCKET 16
/* Per particle, the pairs in which it is a corner of the feature: (the vertex, its entry). */
#define CVK_SIDES_PER_PARTICLE 32
/* The gap kept between any two cloth features: the bound is gamma (d - floor), floor this many
   thicknesses or CVK_GAP_FLOOR_RELATIVE times the particle's largest coordinate, whichever is
   more (contact_bound.comp). Two features d >= floor apart stay 0.1 d + 0.9 floor >= floor apart:
   a squeezed pair nears the floor, not the float rounding of its positions, where the bounds
   could not keep it apart (2^-19 of a coordinate: 16 float steps or more; 1.9 mm 1 km out). */
#define CVK_GAP_FLOOR_THICKNESSES 1.0e-3
#define CVK_GAP_FLOOR_RELATIVE 1.9073486328125e-6
#define CVK_NO_CONTACT 0xffffffffu
#define CVK_FEATURE_FACE 0u
#define CVK_FEATURE_EDGE 1u
#define CVK_FEATURE_VERTEX 2u
#define CVK_MAX_FEATURES 1073741823u /* feature indices in 30 bits */

#define CVK_GPU_CONTACT_PARAMS_FIELDS                                                       \
    CVK_UINT(collider_count)                                                                \
    CVK_UINT(particle_count)                                                                \
    CVK_UINT(free_count)                                                                    \
    CVK_UINT(triangle_count)                                                                \
    CVK_FLOAT(thickness)      /* m: kept between cloth features and off colliders */       \
    CVK_FLOAT(friction)       /* between cloths */                                          \
    CVK_FLOAT(static_friction)                                                              \
    CVK_FLOAT(dt)             /* s per substep */                                           \
    CVK_FLOAT(radius)         /* m: the contact radius (features nearer are listed) */      \
    CVK_UINT(instance_colliders) /* colliders per instance (i's: [i × this, (i + 1) × this)) */ \
    CVK_FLOAT(gamma)          /* the bound: this fraction of the nearest distance */        \
    CVK_FLOAT(redetect)       /* detect when a move would pass this fraction of a bound */ \
    CVK_UINT(detection_interval) /* collision.detection_interval, >= 1 (contact_decide.glsl) */ \
    CVK_UINT(edge_count)                                                                    \
    CVK_UINT(shift)           /* 1: the bounds may share a common shift (no kinematic particle) */ \
    CVK_FLOAT(longest)        /* m: the longest an edge may be for the hash's cells (1.5 × at rest) */ \
    CVK_UINT(cloth_count)
CVK_STRUCT(cvk_gpu_contact_params, CVK_GPU_CONTACT_PARAMS_FIELDS)

/* The work lists (uint), written on the device: a header of indirect commands and counts,
   then three lists, each appended to in no particular order (the passes that read them give
   each item a result that does not depend on it):
   - the free particles in some listed pair, the cloth contact pass's work until the next
     detection (contact_bound.comp; shaders/solvers/pd_contact.comp), particle_count entries
     from CVK_LIST_HEADER;
   - the edges with more pairs to list (another edge within the radius, their nearest points
     inside both) than the bucket the distance pass keeps them in holds, edge_count entries
     after those: the work of the edge detection's second walk (contact_edges.comp). */
#define CVK_LIST_PARTICLE_GROUPS 0 /* x, y, z: detection and bounds over the particles */
#define CVK_LIST_EDGE_GROUPS 4     /* x, y, z: detection over the edges */
#define CVK_LIST_LISTED_GROUPS 8   /* x, y, z: the cloth contact pass over the listed particles */
#define CVK_LIST_LISTED_COUNT 11   /* how many particles that list holds */
#define CVK_LIST_EDGE_PAIRS_GROUPS 12 /* x, y, z: listing the edges' pairs with edges */
#define CVK_LIST_EDGE_PAIRS_COUNT 15
#define CVK_LIST_HEADER 16

/* Push data of the contact passes (collider_poses, contact_check, contact_decide, contact_detect,
   contact_edges, contact_bound): items [first, first + count); the phase of contact_check and
   contact_decide (contact_edges' is its pipeline's). A dispatch with count 0 (the pipelines'
   warm-up) does nothing, not even advance the frame state. */
#define CVK_CONTACT_PUSH_FIELDS \
    CVK_UINT(first)             \
    CVK_UINT(count)             \
    CVK_UINT(phase)             \
    CVK_UINT(per_group) /* items per workgroup of the dispatches whose commands are written */
CVK_PUSH_BLOCK(cvk_contact_push, CVK_CONTACT_PUSH_FIELDS)

/* Bindings of the contact set (set 1 of the solver pipelines, set 0 of the contact passes). */
#define CVK_CONTACT_BINDING_FRAME 0
#define CVK_CONTACT_BINDING_PARAMS 1
#define CVK_CONTACT_BINDING_SHAPES 2
#define CVK_CONTACT_BINDING_KEYFRAMES 3
#define CVK_CONTACT_BINDING_POSES 4
#define CVK_CONTACT_BINDING_SDF 5
#define CVK_CONTACT_BINDING_TRIANGLES 6
#define CVK_CONTACT_BINDING_INCIDENT 7
#define CVK_CONTACT_BINDING_EDGES 8 /* texel, uvec4 per edge: its ends (internal), 0, 0 */
#define CVK_CONTACT_BINDING_CONTACTS 9
#define CVK_CONTACT_BINDING_POSITIONS 10
/* The same params, shapes and poses as uniform buffers, for the solver sweeps: on lavapipe a
   storage-buffer load is a loop over the lanes while a uniform load is one load, and every
   lane of a sweep reads the same collider (3.4x on a 100x100 sweep with one plane). */
#define CVK_CONTACT_BINDING_PARAMS_UNIFORM 11
#define CVK_CONTACT_BINDING_SHAPES_UNIFORM 12
#define CVK_CONTACT_BINDING_POSES_UNIFORM 13
#define CVK_CONTACT_BINDING_CONTACTS_READ 14 /* texel view of the contacts */
#define CVK_CONTACT_BINDING_SEARCHED 15 /* vec4 per particle: where detection saw it, w: its bound */
#define CVK_CONTACT_BINDING_TRIANGLE_EDGES 16 /* texel, uvec4 per triangle: its edges, 0 */
#define CVK_CONTACT_BINDING_EDGE_CONTACTS 17 /* uint per edge × CVK_CONTACTS_PER_EDGE */
#define CVK_CONTACT_BINDING_EDGE_CONTACTS_READ 18 /* texel view of the same */
#define CVK_CONTACT_BINDING_NEAREST 19 /* uint per particle, then per edge: nearest distance's bits;
                                          then per edge: how many pairs it has to list; then
                                          per edge: CVK_EDGE_BUCKET of them (edge, distance) */
#define CVK_CONTACT_BINDING_LISTS 20 /* the work list header (above) */
#define CVK_CONTACT_BINDING_SEARCHED_READ 21 /* texel view of where detection saw them */
#define CVK_CONTACT_BINDING_PARTICLE_EDGES 22 /* texel, uint: n + 1 offsets, then edge ids */
#define CVK_CONTACT_BINDING_PREVIOUS 23 /* vec4 per particle: its position a substep before */
#define CVK_CONTACT_BINDING_SIDES 24 /* uint per particle (counts), then CVK_SIDES_PER_PARTICLE
                                        pairs (vertex, entry) per particle */
#define CVK_CONTACT_BINDING_SIDES_READ 25 /* texel view of the same (R32_UINT) */
#define CVK_CONTACT_BINDING_MIDPOINTS 26 /* vec4 per edge: its midpoint at detection (the edge
                                            hash's points) */
#define CVK_CONTACT_BINDING_INSTANCES 27 /* texel, uint per particle (internal): its instance
                                          (the scene's "instances" copy; 0 with one) */
#define CVK_CONTACT_BINDING_CENTROIDS 28 /* vec4 per triangle: its centroid at detection (the
                                            face hash's points) */
#define CVK_CONTACT_BINDING_CELLS 29 /* uint: edge detection's cell lists (CVK_CELLS_*) */
#define CVK_CONTACT_BINDING_CELL_POOL 30 /* uint: per edge 2 uvec4 at detection, each end's
                                           position (float bits) and index (contact_edges.comp);
                                           then per entry of the cell lists an edge */
#define CVK_CONTACT_BINDING_CELL_POOL_READ 31 /* texel view of the same (R32_UINT) */
#define CVK_CONTACT_BINDING_EDGE_ENDS_READ 32 /* texel view of the same (R32G32B32A32_UINT):
                                                 the edges' ends, 2 texels an edge */
/* Texel views of the nearest distances and of the positions a substep before, for the passes
   that read them in loops after the passes that wrote them (the bounds, the edges' lists, the
   decision's check): on lavapipe a storage load there is a loop over the lanes. */
#define CVK_CONTACT_BINDING_NEAREST_READ 33 /* texel view of the nearest (R32_UINT) */
#define CVK_CONTACT_BINDING_PREVIOUS_READ 34 /* texel view of the previous (R32G32B32A32_SFLOAT) */
#define CVK_CONTACT_BINDING_COUNT 35

/* Edge detection's cell lists (contact_edges.comp phases 3 and 4): for each cell of the
   midpoints' hash that holds an edge, the edges of the half block of cells its edges walk, in
   the walk's order, gathered once for all of them, so that each edge loops over a list instead
   of walking the hash. The cells buffer: the indirect command (x, y, z) of the pass over one
   edge a cell and how many, the pool's fill, then those edges (edge_count), then per edge its
   list's start and length in the pool (CVK_CELL_OVERFLOW: the pool was full), then the edges
   that walk the hash (their list did not fit, or holds more to measure than the distance pass
   keeps: the walking pass's work, its command and count at CVK_CELLS_WALK). A cell takes room
   in the pool for every entry of the slots its walk visits (the half blocks an edge's midpoint
   can be in, 14 with one instance, and the entries of other cells that share those slots), so
   one walk writes its list: the pool holds CVK_CELL_POOL_PER_EDGE entries an edge, where the
   six-cloth pile took at most 15.4 and the drapes 11.6 (a test build), and a cell past it
   walks. The home cell's entries carry CVK_CELL_HOME. */
#define CVK_CELLS_COUNT 3
#define CVK_CELLS_POOL_USED 4
#define CVK_CELLS_WALK 8 /* x, y, z, count */
#define CVK_CELLS_HEADER 12
#define CVK_CELL_POOL_PER_EDGE 24
#define CVK_CELL_OVERFLOW 0xffffffffu
#define CVK_CELL_HOME 0x80000000u

/* Colliders the uniform arrays above hold; a scene with more reads the storage buffers (bit
   CVK_COLLIDERS_IN_STORAGE of the collider types' specialisation constant), one collider a
   particle at a time, its instance's (lib/contact/collide.h). */
#define CVK_UNIFORM_COLLIDERS 64u
#define CVK_COLLIDERS_IN_STORAGE 0x80000000u
/* Bits 0-5 of that constant: the types the scene has (bit CVK_COLLIDER_*_ID). Bits 6-29: an
   instance's colliders as runs of one type, where every instance has the same and they make 2
   to CVK_COLLIDER_RUNS runs of at most CVK_COLLIDER_RUN_MAX colliders each: 6 bits a run from
   bit CVK_COLLIDER_RUNS_SHIFT, its CVK_COLLIDER_*_ID + 1 in the low 3 (0 past the last) and its
   length in the high 3; all 0 otherwise (lib/contact/collide.c; collide.glsl's FOR_EACH_COLLIDER).
   Bit 30: one instance (contact_instance, collide.glsl, then reads nothing). */
#define CVK_COLLIDERS_ONE_INSTANCE 0x40000000u
#define CVK_COLLIDER_TYPE_MASK 0x3fu
#define CVK_COLLIDER_RUNS 4u
#define CVK_COLLIDER_RUN_MAX 7u
#define CVK_COLLIDER_RUNS_SHIFT 6u

/* ---- attachments: features/attach.comp (lib/features/attach.h) ------------------------------------ */

/* One attachment's motion: its keyframes in the attachment keyframe buffer (2 vec4 each, as
   the colliders'; shaders/scene/motion.glsl). */
#define CVK_GPU_ATTACHMENT_FIELDS \
    CVK_UINT(keyframe_first)      \
    CVK_UINT(keyframe_count)      \
    CVK_UINT(loop)                \
    CVK_UINT(pad0)
CVK_STRUCT(cvk_gpu_attachment, CVK_GPU_ATTACHMENT_FIELDS)

/* One attached particle: where it was when the simulation was created, which it is, whose. */
#define CVK_GPU_ATTACHED_FIELDS                                                   \
    CVK_VEC4(start)        /* xyz: position at creation, m */                      \
    CVK_UINT(particle)     /* internal index (a pinned one) */                     \
    CVK_UINT(attachment)   /* into the attachment table */                         \
    CVK_UINT(pad0)                                                                \
    CVK_UINT(pad1)
CVK_STRUCT(cvk_gpu_attached, CVK_GPU_ATTACHED_FIELDS)

/* Push data of features/attach.comp. count 0 (the warm-up dispatch) does nothing, not even
   advance the frame state. */
#define CVK_ATTACH_PUSH_FIELDS                                                     \
    CVK_UINT(count)        /* attached particles */                                \
    CVK_UINT(advance)      /* 1: this pass advances the frame state (no collider pass did) */ \
    CVK_FLOAT(dt)          /* s per substep */                                     \
    CVK_UINT(place)        /* implicit variant: 0 velocity pass, 1 place pass (features/attach.comp) */
CVK_PUSH_BLOCK(cvk_attach_push, CVK_ATTACH_PUSH_FIELDS)

#define CVK_ATTACH_BINDING_FRAME 0       /* cvk_gpu_frame (the contact module's buffer) */
#define CVK_ATTACH_BINDING_KEYFRAMES 1   /* 2 vec4 per keyframe */
#define CVK_ATTACH_BINDING_ATTACHMENTS 2 /* cvk_gpu_attachment per attachment */
#define CVK_ATTACH_BINDING_ATTACHED 3    /* cvk_gpu_attached per attached particle */
#define CVK_ATTACH_BINDING_POSITIONS 4   /* vec4 per particle: x_n */
#define CVK_ATTACH_BINDING_U0 5          /* pd: the displacement iterates (solvers/pd_common.glsl); */
#define CVK_ATTACH_BINDING_U1 6          /* implicit: both the velocities (w: mass) */
#define CVK_ATTACH_BINDING_COUNT 7

/* ---- tearing: features/tear.comp (lib/features/tear.h) ---------------------------------------------- */

/* Push data of features/tear.comp. count 0 (the warm-up dispatch) does nothing. */
#define CVK_TEAR_PUSH_FIELDS                                                       \
    CVK_UINT(count)        /* springs that may tear (of cloths with tearing) */    \
    CVK_UINT(entries)      /* 1: the family packs (neighbour, k, L, 0) entries */ \
    CVK_UINT(pad1)                                                                \
    CVK_UINT(pad2)
CVK_PUSH_BLOCK(cvk_tear_push, CVK_TEAR_PUSH_FIELDS)

/* Per spring that may tear, two uvec4 texels: (a, b, spring index, bits of the squared length
   at which it breaks, m^2); and where its stiffness sits in each free end's adjacency, as
   element indices of the adjacency's uint array: (k of a, k of b) as projective dynamics packs
   it (solvers/pd_common.glsl's quads), then (k of a, k of b) as the implicit and explicit families
   pack it (velocity_state.h's (neighbour, bits of k, bits of L, 0) per entry). Every family
   multiplies whatever it reads of a spring by k, so k = 0 is all a torn spring needs.
   CVK_TEAR_NONE for a pinned end. */
#define CVK_TEAR_NONE 0xffffffffu
#define CVK_TEAR_BINDING_POSITIONS 0    /* texel: vec4 per particle, x after the substep */
#define CVK_TEAR_BINDING_TABLE 1        /* texel: 2 uvec4 per spring that may tear */
#define CVK_TEAR_BINDING_ALIVE 2        /* storage: uint per spring, 1 / 0 once torn */
#define CVK_TEAR_BINDING_ADJACENCY 3    /* storage: the adjacency's neighbours and bits of k */
#define CVK_TEAR_BINDING_COUNT 4

/* ---- air: features/aero_triangles.comp, features/aero_gather.comp (lib/features/aero.h) ------------ */

/* Push data of both air passes. count 0 (the warm-up dispatch) does nothing, not even advance
   the frame state. */
#define CVK_AERO_PUSH_FIELDS                                                       \
    CVK_UINT(count)        /* triangles (aero_triangles) or free particles (aero_gather) */ \
    CVK_UINT(counted)      /* 1: a pass before counted this substep; 0: aero_gather counts it */ \
    CVK_FLOAT(dt)          /* s per substep */                                     \
    CVK_UINT(pad0)                                                                \
    CVK_VEC4(wind)         /* xyz: the mean wind, m/s */                           \
    CVK_VEC4(gusts)        /* x: amplitude; y: 2 pi / period, 1/s; z: jitter, radians */
CVK_PUSH_BLOCK(cvk_aero_push, CVK_AERO_PUSH_FIELDS)

/* Tables read per item are texel buffers (a gather on lavapipe, where a storage load is a loop
   over the lanes; solvers/pd_common.glsl). */
#define CVK_AERO_BINDING_FRAME 0        /* cvk_gpu_frame (the contact module's buffer) */
#define CVK_AERO_BINDING_POSITIONS 1    /* texel, vec4 per particle: x_n, w: m/h^2 (solvers/pd_common.glsl) */
#define CVK_AERO_BINDING_U 2            /* texel, vec4 per particle: the last displacement (velocity h) */
#define CVK_AERO_BINDING_TRIANGLES 3    /* texel, uvec4 per triangle: corners (internal), cloth */
#define CVK_AERO_BINDING_COEFFICIENTS 4 /* vec4 per cloth: rho/2 times drag, lift, friction */
#define CVK_AERO_BINDING_FORCES 5       /* vec4 per triangle: a third of its force, N */
#define CVK_AERO_BINDING_INCIDENCE 6    /* texel, uint: free_count + 1 offsets, then triangle ids */
#define CVK_AERO_BINDING_EXTERNAL 7     /* vec4 per free particle: h^2 F / m, read by predict */
#define CVK_AERO_BINDING_FORCES_READ 8  /* texel view of the forces */
#define CVK_AERO_BINDING_COUNT 9

/* ---- spatial hash (lib/contact/hash.h, shaders/contact/hash_common.glsl) -------------------------- */

/* The hash's parameters, in a small storage buffer of its set, so a shader that queries the hash
   needs no push data. Written by the build's first pass (shaders/contact/hash_clear.comp). */
#define CVK_HASH_PARAMS_FIELDS                                                          \
    CVK_FLOAT(cell_size)   /* m */                                                       \
    CVK_FLOAT(inv_cell)    /* 1 / cell_size, 1/m: cells are floor(p · inv_cell) */        \
    CVK_UINT(table_size)   /* slots, a power of two */                                   \
    CVK_UINT(count)        /* points hashed by the last build */                         \
    CVK_UINT(build)        /* 0: a build recorded on_device gets no workgroups (1 from creation) */ \
    CVK_UINT(pad0)                                                                      \
    CVK_UINT(pad1)                                                                      \
    CVK_UINT(pad2)
CVK_STRUCT(cvk_hash_params, CVK_HASH_PARAMS_FIELDS)

/* A build decided on the device (lib/contact/hash.h, cvk_hash_add_passes with on_device) dispatches
   its passes indirectly, with the commands (3 uints each: workgroups, 1, 1) in the parameters'
   buffer after cvk_hash_params, one per pass in the order clear, count, chunk sums, scan
   chunks, scan, scatter; shaders/contact/hash_commands.comp writes them from its push data,
   with no workgroups while the build is closed. */
#define CVK_HASH_BUILD_PASSES 6
#define CVK_HASH_COMMANDS_OFFSET 32 /* bytes: sizeof(cvk_hash_params) */
#define CVK_HASH_COMMANDS_PUSH_FIELDS                                                   \
    CVK_UINT(clear)        /* workgroups of each pass while the build is open */          \
    CVK_UINT(count)                                                                     \
    CVK_UINT(chunk_sums)                                                                \
    CVK_UINT(scan_chunks)                                                               \
    CVK_UINT(scan)                                                                      \
    CVK_UINT(scatter)                                                                   \
    CVK_UINT(pad0)                                                                      \
    CVK_UINT(pad1)
CVK_PUSH_BLOCK(cvk_hash_commands_push, CVK_HASH_COMMANDS_PUSH_FIELDS)

/* The build passes' push data (shaders/contact/hash_*.comp); the scan's chunks are `chunk` slots. */
#define CVK_HASH_PUSH_FIELDS                                                            \
    CVK_UINT(points)       /* points hashed */                                           \
    CVK_UINT(slots)        /* table_size */                                              \
    CVK_UINT(chunk)        /* slots per chunk of the scan, a power of two */             \
    CVK_UINT(chunks)       /* slots / chunk */                                           \
    CVK_FLOAT(cell_size)   /* m: written to the parameters by the clear pass */          \
    CVK_FLOAT(inv_cell)    /* 1/m */                                                     \
    CVK_UINT(pad0)                                                                      \
    CVK_UINT(pad1)
CVK_PUSH_BLOCK(cvk_hash_push, CVK_HASH_PUSH_FIELDS)

/* A hash build with the contact passes after it in one workgroup (shaders/contact/
   contact_faces_fused.comp, contact_edges_fused.comp): the build's push data, then the
   contact passes'. */
#define CVK_CONTACT_HASH_PUSH_FIELDS CVK_HASH_PUSH_FIELDS CVK_CONTACT_PUSH_FIELDS
CVK_PUSH_BLOCK(cvk_contact_hash_push, CVK_CONTACT_HASH_PUSH_FIELDS)

/* The neighbour query (shaders/contact/hash_neighbours.comp): per point, the other points within
   radius. */
#define CVK_HASH_QUERY_PUSH_FIELDS                                                      \
    CVK_UINT(count)        /* points queried: [0, count) */                              \
    CVK_FLOAT(radius2)     /* radius^2, m^2; radius at most the cell size */
CVK_PUSH_BLOCK(cvk_hash_query_push, CVK_HASH_QUERY_PUSH_FIELDS)

/* Bindings of the hash's set; scratch holds the count (then cursor) per slot, then the chunk
   sums of the scan. What the scan and queries read goes through
   texel buffers: on lavapipe a texel fetch is a vectorised gather while a storage-buffer load in
   a divergent loop is a loop over the lanes (the neighbour query runs 2.4x faster). */
#define CVK_HASH_BINDING_PARAMS 0       /* storage: cvk_hash_params */
#define CVK_HASH_BINDING_POINTS 1       /* texel (rgba32f): a point per texel, xyz hashed */
#define CVK_HASH_BINDING_KEYS 2         /* storage: uint per point, its slot */
#define CVK_HASH_BINDING_STARTS 3       /* storage: uint per slot + 1 */
#define CVK_HASH_BINDING_ENTRIES 4      /* storage: uvec4 per point grouped by slot, in the
                                           order the scatter's atomics took them: the point's
                                           xyz (float bits) and its index */
#define CVK_HASH_BINDING_SCRATCH 5      /* storage: counts per slot, sums per chunk */
#define CVK_HASH_BINDING_STARTS_READ 6  /* texel (r32ui): starts, as queries read them */
#define CVK_HASH_BINDING_ENTRIES_READ 7 /* texel (rgba32ui): entries, as queries read them (one
                                           fetch per entry instead of the index, then its point) */
#define CVK_HASH_BINDING_PARAMS_READ 8  /* uniform: the parameters, as queries read them (a
                                           storage load per cell visited was a lane loop) */
#define CVK_HASH_BINDING_SALTS 9        /* texel (r32ui): per point a salt mixed into its slot
                                           (the scene's instance, so copies at one place fill
                                           different slots); one zero texel without */
#define CVK_HASH_BINDING_SCRATCH_READ 10 /* texel (r32ui): scratch, as the scan reads the
                                            counts the pass before wrote */
#define CVK_HASH_BINDING_COUNT 11

/* Cells are clamped to ±CVK_HASH_CELL_LIMIT per axis so the float -> int conversion stays
   defined for far-away points (they share the border cells). */
#define CVK_HASH_CELL_LIMIT 1073741824.0

/* ---- picking and dragging: features/grab.comp, features/pick.comp (lib/features/grab.h, lib/features/pick.h) --- */

/* The grab, written by the host between frames (host-visible, coherent) and read by the
   recorded frame every substep: which particle follows which target. */
#define CVK_GPU_GRAB_FIELDS                                                         \
    CVK_VEC4(target)       /* xyz: where the particle is at the end of the frame, m */ \
    CVK_UINT(particle)     /* internal index (a free particle) */                    \
    CVK_UINT(held)         /* 0: nothing is grabbed, the pass does nothing */        \
    CVK_UINT(count)        /* particles held (cvk_sim_grab_within), 1 to CVK_GRAB_MAX */ \
    CVK_UINT(pad1)
CVK_STRUCT(cvk_gpu_grab, CVK_GPU_GRAB_FIELDS)

/* Particles a grab holds at once (features/grab.comp's workgroup); after the cvk_gpu_grab in the
   same buffer come CVK_GRAB_MAX vec4: xyz the member's offset from the target, w its internal
   index as float bits (member 0 is the grabbed particle, offset 0). */
#define CVK_GRAB_MAX 64

/* Push data of features/grab.comp. substeps 0 (the warm-up dispatch) does nothing. */
#define CVK_GRAB_PUSH_FIELDS                                                       \
    CVK_UINT(substeps)     /* substeps per frame */                                \
    CVK_FLOAT(weight)      /* m/h^2 the solver sees for the grabbed particle */     \
    CVK_UINT(pad0)                                                                \
    CVK_UINT(pad1)
CVK_PUSH_BLOCK(cvk_grab_push, CVK_GRAB_PUSH_FIELDS)

#define CVK_GRAB_BINDING_GRAB 0          /* cvk_gpu_grab (host-visible) */
#define CVK_GRAB_BINDING_WATCH 1         /* cvk_gpu_watch: its substep count places the substep */
#define CVK_GRAB_BINDING_POSITIONS 2     /* vec4 per particle: x_n */
#define CVK_GRAB_BINDING_Y 3             /* the solver's predicted displacement (solvers/pd_common.glsl) */
#define CVK_GRAB_BINDING_U0 4            /* the solver's displacement iterates */
#define CVK_GRAB_BINDING_U1 5
#define CVK_GRAB_BINDING_COUNT 6

/* The pick's answer (host-visible): the smallest distance along the ray as float bits (a
   non-negative float's bits order like the float), then the smallest user index at that
   distance, then that particle's position. NONE where nothing was hit. */
#define CVK_PICK_NONE 0xffffffffu
#define CVK_GPU_PICK_FIELDS                                                         \
    CVK_UINT(distance_bits) /* floatBitsToUint of the distance along the ray, m */   \
    CVK_UINT(user)          /* user index of the nearest particle hit */             \
    CVK_UINT(pad0)                                                                  \
    CVK_UINT(pad1)                                                                  \
    CVK_VEC4(position)      /* xyz: that particle's position, m */
CVK_STRUCT(cvk_gpu_pick, CVK_GPU_PICK_FIELDS)

/* Push data of features/pick.comp: stage 0 finds the distance, 1 the particle, 2 its position. */
#define CVK_PICK_PUSH_FIELDS                                                       \
    CVK_VEC4(origin)       /* xyz: the ray's origin, m */                           \
    CVK_VEC4(direction)    /* xyz: the ray's unit direction */                      \
    CVK_FLOAT(radius2)     /* radius^2, m^2 */                                      \
    CVK_UINT(count)        /* particles: [0, count) in internal order */           \
    CVK_UINT(stage)                                                                \
    CVK_UINT(pad0)
CVK_PUSH_BLOCK(cvk_pick_push, CVK_PICK_PUSH_FIELDS)

#define CVK_PICK_BINDING_POSITIONS 0     /* vec4 per particle, internal order */
#define CVK_PICK_BINDING_USER_OF 1       /* uint per particle: its user index */
#define CVK_PICK_BINDING_RESULT 2        /* cvk_gpu_pick (host-visible) */
#define CVK_PICK_BINDING_COUNT 3

#endif
