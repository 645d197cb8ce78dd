/* clothvk/sim.h — steps 3 and 4: the simulation made from a scene description, advanced
 * frame by frame in your command buffer or in a blocking step, read back, measured, and
 * pulled by a user (picking and dragging).
 */
#ifndef CLOTHVK_SIM_H
#define CLOTHVK_SIM_H

#include "context.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ----------------------------------------------------------------------------------------
 * Simulation
 * ------------------------------------------------------------------------------------- */

typedef struct cvk_sim cvk_sim;

/* Start from cvk_default_sim_desc() and set scene; the other fields are the library's choices
   until you change them:

       cvk_sim_desc desc = cvk_default_sim_desc();
       desc.scene = &scene;
       cvk_sim* sim;
       cvk_sim_create(ctx, &desc, &sim, &err); */
typedef struct cvk_sim_desc {
    const cvk_scene_desc* scene; /* copied; need not outlive the call */
    uint32_t workgroup_size;     /* compute workgroup size for every pass, 0 = the library's
                                    choice: 64, and on CPU devices the device's subgroup size
                                    for the passes that stream over particles (the sweeps) */
    uint32_t max_workgroups;     /* workgroups per dispatch, 0 = the library's choice: a few on
                                    CPU devices, where each costs a thread hand-off (and for
                                    the passes over particles one per 16,384 particles at
                                    most; detection and contact 8 items an invocation), one
                                    per workgroup_size particles elsewhere; any other value
                                    gives detection and contact one item an invocation */
    int timing;                  /* GPU timestamps per pass: 0 = on where supported, -1 = off */
    bool grab;                   /* true: the frame has the grab pass from the start, so frames
                                    you record now follow cvk_sim_grab; false: the first
                                    cvk_sim_grab adds it (see there) */
    int fused_shared_memory;     /* where the fused sweeps (solver.fuse on) keep a copy's
                                    iterate while they sweep: 1 = in the workgroup's shared
                                    memory where it fits (16 bytes a free particle), -1 = in
                                    global memory, 0 = the library's choice: 1 on a GPU, -1 on
                                    a CPU device (slower there); the same bits either way */
    uint32_t search_lanes;       /* no effect: a setting of an earlier contact's search,
                                    kept so that programs that set it still build; 0 */
    uint32_t cookie_;            /* set by cvk_default_sim_desc; do not touch */
} cvk_sim_desc;

/* The defaults: no scene yet, every other field above 0 or false (each says what that means). */
CVK_API cvk_sim_desc cvk_default_sim_desc(void);

/* desc must come from cvk_default_sim_desc(): one that did not (a zero-initialised struct or a
   compound literal) is refused with CVK_ERROR_INVALID_ARGUMENT, as are NULL and a description
   without a scene. The scene is checked as cvk_scene_desc_validate does. */
CVK_API cvk_result cvk_sim_create(cvk_context* context, const cvk_sim_desc* desc, cvk_sim** out_sim,
                          cvk_error* error);
/* Waits until the context's queue is idle (work you recorded may still use the simulation's
   buffers), then frees everything the simulation made. */
CVK_API void cvk_sim_destroy(cvk_sim* sim);

/* Records `frames` frames (each dt · substeps of simulated time) into `cmd`, which must be
   in the recording state, outside a render pass, from a pool of the context's queue family.
   Nothing is submitted and nothing waits. Each submission of `cmd` advances the simulation
   by `frames` frames; `cmd` may be submitted again without re-recording.

   Synchronisation contract:
   - The library binds its own compute pipelines, descriptor sets and push constants: state
     you bound for compute before the call is lost.
   - It begins with a barrier that makes earlier compute-shader and transfer writes visible
     to its compute shaders, records barriers between its own passes, and ends after its last
     dispatch without a trailing barrier.
   - Before another stage reads the particle positions you record a barrier from
     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT / VK_ACCESS_SHADER_WRITE_BIT to that stage.
   - Once the simulation has the grab pass (cvk_sim_grab, cvk_sim_desc.grab), every frame
     reads a host-visible buffer that cvk_sim_grab and cvk_sim_release write from the host:
     call them only while no submission of these frames is executing (see cvk_sim_grab).
   - Fails with CVK_ERROR_UNSUPPORTED for the host solver "gs-cpu" (use cvk_sim_step). */
CVK_API cvk_result cvk_sim_record(cvk_sim* sim, VkCommandBuffer cmd, uint32_t frames, cvk_error* error);

/* Advances `frames` frames and waits until they are done: one submission of a command
   buffer recorded once at creation, one host wait at the end. CVK_ERROR_DIVERGED when the
   simulation blew up (now or before; the message names the frame and the cloth): its
   positions stopped advancing there, and stepping on changes nothing until a state is
   written (cvk_sim_write_state, cvk_sim_load_snapshot). CVK_ERROR_DEVICE_LIMIT when the
   device's loop limit cut a contact detection short (now or before, since the state was last
   written; lavapipe's 65,535 loop iterations an invocation, docs/limits.md): the frames ran,
   but cloth may have passed through cloth; a larger cvk_sim_desc.max_workgroups gives
   detection one item an invocation, and a state written clears it as it does a divergence.
   CVK_ERROR_DEVICE_LIMIT too when that limit cut the fused sweeps short (solver.fuse on in a
   caller's small workgroup_size: particles were left unswept). */
CVK_API cvk_result cvk_sim_step(cvk_sim* sim, uint32_t frames, cvk_error* error);

/* Number of particles over all cloths. */
CVK_API uint64_t cvk_sim_particle_count(const cvk_sim* sim);

/* Copies positions out (3 floats per particle, cloth by cloth; a grid in row-major order, i
   fastest; a mesh in file order, see cvk_cloth_desc). Waits for the device to be idle on the context's queue; `count` is the number
   of particles the array holds and must be cvk_sim_particle_count(). */
CVK_API cvk_result cvk_sim_read_positions(cvk_sim* sim, float* xyz, uint64_t count, cvk_error* error);

/* Replaces all positions (same order) and sets every velocity to zero. Pinned particles
   are held at their new place. */
CVK_API cvk_result cvk_sim_write_positions(cvk_sim* sim, const float* xyz, uint64_t count,
                                   cvk_error* error);

/* The full state, for snapshots: positions (m) and velocities (m/s), 3 floats per particle in
   the order of cvk_sim_read_positions. The velocity is Verlet's at the end of the last
   substep, (x_n − x_{n−1}) / h + h g / 2 (0 for a cloth at rest; for a pinned particle 0, for an
   attached one the motion's (x_n − x_{n−1}) / h).
   Either array may be NULL; waits like cvk_sim_read_positions. */
CVK_API cvk_result cvk_sim_read_state(cvk_sim* sim, float* xyz, float* velocity, uint64_t count,
                              cvk_error* error);

/* Replaces positions and velocities (velocity NULL: at rest). Writing back what
   cvk_sim_read_state returned continues the same motion, to float rounding of the velocity.
   Pinned particles are held at their new place and keep no velocity. Non-finite values are
   rejected with CVK_ERROR_INVALID_ARGUMENT and change nothing. */
CVK_API cvk_result cvk_sim_write_state(cvk_sim* sim, const float* xyz, const float* velocity,
                               uint64_t count, cvk_error* error);

/* Exact snapshots, for resuming a run bit for bit (cvk_sim_read_state goes through float
   velocities and is not exact). A snapshot is an opaque byte string: a 72-byte header (magic
   "CVKSNAP", format version, particle count, frames simulated, a hash of the scene as built,
   the solver family and linear solver, a CRC-32 of every other byte) and the solver's state as
   it holds it (for the device solvers positions and last displacements, vec4 floats; for
   gs-cpu its double arrays).
   cvk_sim_snapshot_size is its size in bytes under the current solver (0 for NULL).
   cvk_sim_save_snapshot waits like cvk_sim_read_positions; `size` must be that size.
   cvk_sim_load_snapshot puts the state and the frame counter back, so stepping on gives the
   bits the saved simulation would have given. It refuses, with CVK_ERROR_INVALID_ARGUMENT
   (CVK_ERROR_UNSUPPORTED for another format version) and changing nothing: data that is not a
   snapshot, one of another format version (3 and before carry no checksum), a size other than
   the header says (truncated), a checksum other than the header says (damaged), one of
   another scene (particle count or build hash differ), and state the current solver cannot
   take exactly: a device solver's snapshot loads into any device solver (rbgs, jacobi,
   chebyshev), gs-cpu's only into gs-cpu. Byte order is the machine's. */
CVK_API uint64_t cvk_sim_snapshot_size(const cvk_sim* sim);
CVK_API cvk_result cvk_sim_save_snapshot(cvk_sim* sim, void* data, uint64_t size, cvk_error* error);
CVK_API cvk_result cvk_sim_load_snapshot(cvk_sim* sim, const void* data, uint64_t size,
                                         cvk_error* error);

/* The cloths as the simulation sees them: particle and triangle ranges, in scene order. */
typedef struct cvk_cloth_info {
    const char* name;            /* the scene's name for the cloth; "cloth<N>" when it has none */
    uint32_t first_particle;     /* range in the order of cvk_sim_read_positions */
    uint32_t particle_count;
    uint32_t first_triangle;     /* range in cvk_sim_read_mesh's triangles */
    uint32_t triangle_count;
    bool mesh;                   /* true: read from a mesh file; false: a grid */
} cvk_cloth_info;

CVK_API uint32_t cvk_sim_cloth_count(const cvk_sim* sim);
/* Zeroes for a cloth index out of range. */
CVK_API cvk_cloth_info cvk_sim_get_cloth(const cvk_sim* sim, uint32_t cloth);
/* Triangles over all cloths, torn ones included. */
CVK_API uint64_t cvk_sim_triangle_count(const cvk_sim* sim);

/* The cloths as triangles, for export through your own pipeline (clothvk-sim --obj uses it):
   positions (m) and unit vertex normals (the area-weighted average of the live triangles'
   normals, on the side the triangles wind counter-clockwise; zero at a vertex with none),
   3 floats per particle in the order of cvk_sim_read_positions, and 3 particle indices per
   triangle, cloth by cloth (cvk_cloth_info ranges). A triangle whose springs are gone (torn)
   has three equal indices: skip it. Any array may be NULL; vertex_count must be
   cvk_sim_particle_count() and triangle_count cvk_sim_triangle_count(). Waits like
   cvk_sim_read_positions. */
CVK_API cvk_result cvk_sim_read_mesh(cvk_sim* sim, float* xyz, float* normals, uint32_t* triangles,
                                     uint64_t vertex_count, uint64_t triangle_count,
                                     cvk_error* error);

/* Changes the solver (linear solver, iterations, omega, Chebyshev parameters) at run time,
   without rebuilding the scene; positions and velocities are kept, so the next step continues
   the same motion with the new solver. The description is checked as in a scene ("solver.omega:
   must be between 0 and 2, got 2.5"); a bad one, or a failure before the switch, leaves the
   old solver in place. Waits for the simulation's earlier work. Command buffers recorded with
   cvk_sim_record before the call still hold the old plan: record them again. */
CVK_API cvk_result cvk_sim_set_solver(cvk_sim* sim, const cvk_solver_desc* solver, cvk_error* error);

/* The solver settings in use. */
CVK_API cvk_solver_desc cvk_sim_get_solver(const cvk_sim* sim);

/* Every kind of pass the library plans fits (21 names at most in one plan). */
#define CVK_MAX_PASSES 24

/* GPU time of one kind of pass over the last completed frame. */
typedef struct cvk_pass_stats {
    const char* name;          /* "predict", "solve" */
    double gpu_ms;             /* summed over the frame's substeps; < 0 when not measured */
    uint32_t dispatches;       /* per frame */
} cvk_pass_stats;

typedef struct cvk_sim_stats {
    uint64_t particles;        /* all particles */
    uint64_t pinned;           /* of which pinned */
    uint64_t springs[3];       /* structural, shear, bend */
    uint64_t torn_springs;     /* springs broken by tearing so far (cvk_tearing_desc); the spring
                                  metrics below leave them out */
    uint32_t colours;          /* particle colours of the Gauss-Seidel sweep */
    uint64_t frames;           /* frames advanced with cvk_sim_step */
    double residual;           /* Σ (|xa − xb| − L)² over structural springs (seed 002 eq. 4.1), m² */
    double residual_per_type[3];/* the same sum for structural, shear and bend springs, m² */
    double residual_normalized;/* residual / (structural springs · mean L²); dimensionless */
    double max_stretch;        /* max over all springs of |xa − xb| / L − 1 */
    double p99_stretch;        /* 99th percentile (nearest rank) of |xa − xb| / L − 1 over the
                                  structural springs: the stretch of all but the worst 1 % */
    uint64_t nan_count;        /* coordinates that are NaN or infinite; 0 in a healthy run */
    double kinetic_energy;     /* Σ ½ m |v|² over free particles, J */
    double gravitational_energy;/* −Σ m g·x over free particles (0 at the origin; 0 without
                                  integration), J */
    double elastic_energy;     /* Σ ½ k (|xa − xb| − L)² over all springs, J */
    double energy;             /* the sum, J: for stability studies (pinned particles moved
                                  by a write add or remove energy from outside) */
    double gpu_ms_per_frame;   /* GPU time of the last completed frame; < 0 when not measured */
    uint32_t dispatches_per_frame;
    uint32_t dispatches_per_substep;
    uint32_t pass_count;
    cvk_pass_stats passes[CVK_MAX_PASSES];
    /* Contact, at the end of the last frame (0 in a scene without collision). */
    uint64_t collider_contacts;  /* free particles within the thickness of a collider's surface */
    uint64_t self_contacts;      /* particle–triangle pairs of the cloths within the thickness
                                    (pairs skipped as close in the rest mesh not counted) */
    double max_penetration;      /* m: deepest a particle is inside any collider's surface
                                    (0 when none is; thickness not counted) */
    uint64_t intersecting_pairs; /* non-adjacent cloth triangle pairs that intersect
                                    (cvk_sim_count_intersections); 0 without collision */
    uint64_t contact_searches;   /* cloth-contact detections so far (since creation; a
                                    snapshot carries the count; each runs when a particle's move
                                    would pass its bound); 0 without self-contact */
    uint64_t contact_held;       /* free particles that ended a substep past 0.9 of their
                                    contact bound, summed over the same substeps: motion the
                                    bounds held back; 0 without self-contact */
    double contact_held_fraction; /* contact_held over the free particles' substeps counted
                                     (a substep after a state write is not) */
    bool contact_cut;            /* some detection since the state was last written (or the
                                    simulation made) was cut short by the device's loop limit
                                    (cvk_sim_step's CVK_ERROR_DEVICE_LIMIT): the guarantee no
                                    longer holds; false without self-contact */
    uint64_t contact_crowded;    /* particles found a corner of more cloth pairs than their list
                                    holds (32), summed over the detections: such a particle
                                    takes no share of those pairs as a corner (its own pairs
                                    still push it; docs/limits.md); 0 without self-contact */
    /* The linear solver: implicit's, and pd's sweeps (counted on the device with a tolerance;
       without one, every sweep the plan records). */
    uint32_t solver_iterations;       /* CG iterations or Jacobi sweeps (pd: sweeps) of the last
                                         frame, summed over its substeps */
    uint64_t solver_iterations_total; /* since the simulation started */
    uint32_t solver_breakdowns;       /* substeps whose solve found the system not positive
                                         definite (pᵀAp ≤ 0, rᵀP⁻¹r < 0) and stopped; 0 with
                                         the clamp */
    float solver_residual;            /* pd with a tolerance: the last relative residual
                                         measured (solver.tolerance's measure); else 0 */
    /* The divergence watch (GPU solvers): a non-finite position, a particle faster than
       10000 m/s or a spring ten times its rest length stops the simulation at the last sane
       state. */
    bool diverged;               /* the simulation blew up; its state stopped advancing */
    uint64_t diverged_frame;     /* the frame (0-based, as stats.frames counts) it happened in */
    uint32_t diverged_cloth;     /* the cloth (scene order) of the first particle that did */
    bool diverged_nonfinite;     /* true: a position became NaN or infinite; false: ran away */
} cvk_sim_stats;

/* ----------------------------------------------------------------------------------------
 * Picking and dragging: the interaction an engine needs (seed 002 §5.3.8)
 * ------------------------------------------------------------------------------------- */

/* A particle: its cloth (scene order) and its index in that cloth, in the order of
   cvk_sim_read_positions from cvk_cloth_info.first_particle (a grid's [i, j] is
   j · grid[0] + i). */
typedef struct cvk_particle {
    uint32_t cloth;
    uint32_t index;
} cvk_particle;

typedef struct cvk_pick_result {
    bool hit;                    /* false: the ray passes no particle within the radius */
    cvk_particle particle;       /* the particle hit nearest the origin */
    float distance;              /* m along the ray from its origin to the point of the ray
                                    nearest the particle */
    float position[3];           /* the particle's position, m: where a drag starts */
} cvk_pick_result;

/* The particle nearest the ray's origin among those the ray passes within `radius` (m, ≥ 0;
   usually about half the particle spacing) of, in front of the origin (distance ≥ 0), computed
   on the device over every particle, pinned ones included. The direction need not be unit
   length. Equal distances go to the cloth, then the index, that comes first: the answer is
   the same every run. A miss is not an error: out->hit is false. A ray with a non-finite
   origin, a zero or non-finite direction or a negative or non-finite radius is refused with
   CVK_ERROR_INVALID_ARGUMENT. It is a query outside the frame: one submission of its own,
   waited for like cvk_sim_read_positions; recorded frames are not touched. */
CVK_API cvk_result cvk_sim_pick(cvk_sim* sim, const float origin[3], const float direction[3],
                                float radius, cvk_pick_result* out, cvk_error* error);

/* Drags a particle: from the next frame on, `particle` moves in a straight line from where each
   frame finds it to `target` (m), evenly over the frame's substeps, and is at the target at its
   end (to float rounding); the solver holds it there as infinitely heavy, so the cloth follows
   through its springs (tethers and contact do not move it). Calling it again moves the target
   or grabs another particle (one at a time: the one before is released). A pinned or attached
   particle is refused (CVK_ERROR_INVALID_ARGUMENT), as is a non-finite target. Only the pd
   method with a device linear solver (rbgs, jacobi, chebyshev) holds a grab: the others are
   refused with CVK_ERROR_UNSUPPORTED, and cvk_sim_set_solver refuses to switch to them while a
   particle is grabbed.

   cvk_sim_release lets the particle go: it is free again from the next frame on, with the
   velocity of its last substep (still if the target stood still, moving if it was dragged).

   A grab is not part of the state: snapshots and cvk_sim_write_state neither save nor clear
   it.

   Synchronisation: the target lives in a small host-visible buffer that every recorded frame
   reads; cvk_sim_grab and cvk_sim_release write it at once from the host and submit nothing.
   So call them only while no submitted frame of this simulation is executing: cvk_sim_step has
   waited already; if you record frames yourself (cvk_sim_record), wait on your fence first.
   The frames submitted after the call see the new target; a command buffer recorded earlier
   does too, and need not be recorded again, with one exception: the first cvk_sim_grab of a
   simulation made without cvk_sim_desc.grab adds the grab pass to the frame (waiting for the
   queue, as cvk_sim_set_solver does), and command buffers recorded before it must be recorded
   again. */
CVK_API cvk_result cvk_sim_grab(cvk_sim* sim, cvk_particle particle, const float target[3],
                                cvk_error* error);
/* As cvk_sim_grab, with a hand instead of a fingertip: every free particle of the same cloth
   within `radius` m of `particle`, where they are when the grab starts, is held too, each at its
   offset from `particle` (so the region moves rigidly with the target); at most 64, the
   nearest first (ties: the lower index). A load on one particle concentrates in its own
   springs, so with tearing a one-particle drag plucks that particle out; spread over a region
   it tears the cloth. The grab starts by reading the positions back (it waits, like
   cvk_sim_read_positions); calling it again with the same particle and radius only moves the
   target (no wait). Radius 0 grabs the one particle. A negative or non-finite radius is
   refused with CVK_ERROR_INVALID_ARGUMENT; the rest as cvk_sim_grab. */
CVK_API cvk_result cvk_sim_grab_within(cvk_sim* sim, cvk_particle particle, float radius,
                                       const float target[3], cvk_error* error);
CVK_API void cvk_sim_release(cvk_sim* sim);

/* The number of pairs of cloth triangles that share no particle and intersect, computed exactly
   on the host from the current positions (waits like cvk_sim_read_positions). Torn triangles
   are skipped; a scene's instances (copies that never touch) pair a copy's triangles with its
   own only. A cloth that does not pass through itself or another has 0. */
CVK_API cvk_result cvk_sim_count_intersections(cvk_sim* sim, uint64_t* out_pairs, cvk_error* error);

/* Notes on the scene the simulation was made from: one sentence for each key it sets that has
   no effect (collision.edges, collision.exclusion, collision.detect_every: keys of an earlier
   contact, read so that old scenes load), such as "collision.edges has no effect: edge-edge
   contact is always on"; and, with self-contact, one when a fast keyframed collider made the
   simulation split its substeps ("substeps split: 16 substeps of 1 ms a frame run as 32 of
   0.5 ms, so that collider 7 "ball" (8.8 m/s) moves at most 0.34 of the thickness a substep";
   docs/collisions.md). cvk_sim_note returns note `index` (0 to cvk_sim_note_count − 1), or
   NULL past the end or for a NULL simulation; the text lives as long as the simulation. The
   tools print them (clothvk-sim: "note: ..." lines on stderr, "notes" in --json). */
CVK_API uint32_t cvk_sim_note_count(const cvk_sim* sim);
CVK_API const char* cvk_sim_note(const cvk_sim* sim, uint32_t index);

/* Reads positions back (as cvk_sim_read_positions) and computes the statistics. For frames
   you recorded yourself, call it once their submission has completed. */
CVK_API cvk_result cvk_sim_get_stats(cvk_sim* sim, cvk_sim_stats* out_stats, cvk_error* error);

/* Fills only the counting and timing fields of `out_stats` (GPU time of the last completed
   frame, per pass, dispatch counts) without reading anything back; cheap enough per frame. */
CVK_API void cvk_sim_get_timing(const cvk_sim* sim, cvk_sim_stats* out_stats);

/* Writes a human-readable description of the step plan (passes, dispatches, workgroups)
   into `text`, truncated to `capacity` bytes; returns the length it needed. */
CVK_API size_t cvk_sim_describe_plan(const cvk_sim* sim, char* text, size_t capacity);

#ifdef __cplusplus
}
#endif
#endif /* CLOTHVK_SIM_H */
