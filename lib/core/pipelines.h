/* The one table of compute pipelines of the step: pipeline id -> shader, specialisation
   constants, label (for --plan). A family or feature that needs a pipeline adds one line to
   CVK_PIPELINE_LIST; a simulation asks for each on first use, and the context makes it once for
   every simulation that needs it with the same specialisation and layout (core/gpu_cache.h). */
#ifndef CVK_PIPELINES_H
#define CVK_PIPELINES_H

#include "core/gpu.h"
#include "core/shaders.h"

/* Where each specialisation constant (ids 0, 1, 2, ...) takes its value from. */
typedef enum cvk_spec_source {
    CVK_SPEC_WORKGROUP_SIZE, /* local_size_x_id = 0 */
    CVK_SPEC_PARTICLE_WORKGROUP_SIZE, /* local_size_x_id = 0 of the passes that stream over
                                         particles (sweeps, prediction, finalize, tethers) */
    CVK_SPEC_MAX_DEGREE,     /* springs per particle, at most (build) */
    CVK_SPEC_TRUE,           /* a boolean switch set to true (e.g. FIRST) */
    CVK_SPEC_FALSE,          /* a boolean switch left false */
    CVK_SPEC_COLLIDER_TYPES, /* bit t: the scene has colliders of type t */
    CVK_SPEC_SELF_CONTACT,   /* the scene has particle–triangle contact between cloths */
    CVK_SPEC_WIND,           /* the scene has air (lib/features/aero.h): predict adds its force */
    CVK_SPEC_TETHERS,        /* a cloth has tethers (lib/topology/build.h) */
    CVK_SPEC_TETHER_SLOTS,   /* tether slots in use (cvk_build.tether_slots), at least 1 */
    CVK_SPEC_FUSED_WORKGROUP_SIZE, /* local_size_x_id = 0 of the fused sweeps (one workgroup) */
    CVK_SPEC_REST,           /* the scene's solves keep a rest memory (lib/solvers/solve_pd.h) */
    CVK_SPEC_FUSED_SHARED,   /* the fused sweeps' iterate slots in shared memory, 0: none */
    CVK_SPEC_FUSED_ONE_COPY, /* the fused sweeps take the whole scene as one copy */
    CVK_SPEC_LITERAL,        /* and after it: the value n (CVK_SPEC_VALUE) */
} cvk_spec_source;

/* The value n itself (a switch of several ways, e.g. PREDICTS, or a pass's phase). */
#define CVK_SPEC_VALUE(n) ((cvk_spec_source)(CVK_SPEC_LITERAL + (n)))

typedef struct cvk_spec_recipe {
    uint32_t count;
    cvk_spec_source source[CVK_SPEC_MAX];
} cvk_spec_recipe;

/* The first sweep that predicts (id 6, PREDICTS, of shaders/solvers/pd_gauss_seidel.comp): the
   last substep's displacements in src (1) or in dst (2). */
#define CVK_SPEC_PD_FIRST_PREDICT(WHERE) {7, {CVK_SPEC_PARTICLE_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, \
                                           CVK_SPEC_TRUE, CVK_SPEC_FALSE, CVK_SPEC_FALSE, \
                                           CVK_SPEC_SELF_CONTACT, WHERE}}
/* Id 5 of shaders/solvers/pd_common.glsl, BOUNDED: sweeps keep particles within their bounds
   (self-contact). */
#define CVK_SPEC_PD {6, {CVK_SPEC_PARTICLE_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, CVK_SPEC_FALSE, \
                         CVK_SPEC_FALSE, CVK_SPEC_FALSE, CVK_SPEC_SELF_CONTACT}}
/* The fused sweeps: as CVK_SPEC_PD, in the fused pass's workgroup size, with the tether
   pass's slots (id 2, as CVK_SPEC_PD_TETHER's), the contact passes' collider types and
   self-contact (ids 3 and 4, as CVK_SPEC_PD_CONTACT's), the prediction's wind (id 6), the
   rest memory (id 7, REST of shaders/solvers/pd_common.glsl), the iterate's slots in shared
   memory (id 8, SHARED_SLOTS of shaders/solvers/pd_fused.comp) and whether it sweeps one copy
   (id 9, ONE_COPY there). */
#define CVK_SPEC_PD_FUSED {10, {CVK_SPEC_FUSED_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, CVK_SPEC_TETHER_SLOTS, \
                                CVK_SPEC_COLLIDER_TYPES, CVK_SPEC_SELF_CONTACT, \
                                CVK_SPEC_SELF_CONTACT, CVK_SPEC_WIND, CVK_SPEC_REST, \
                                CVK_SPEC_FUSED_SHARED, CVK_SPEC_FUSED_ONE_COPY}}
/* The tether pass (id 2 of shaders/solvers/pd_tether.comp: the slots it reads). */
#define CVK_SPEC_PD_TETHER {3, {CVK_SPEC_PARTICLE_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, CVK_SPEC_TETHER_SLOTS}}
/* finalize (id 7: REST of shaders/solvers/pd_common.glsl), and with the tethers' projection
   (ids 2 and 6 of shaders/solvers/finalize.comp: the tether slots, TETHERED). */
#define CVK_SPEC_FINALIZE {8, {CVK_SPEC_PARTICLE_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, CVK_SPEC_FALSE, \
                               CVK_SPEC_FALSE, CVK_SPEC_FALSE, CVK_SPEC_SELF_CONTACT, \
                               CVK_SPEC_FALSE, CVK_SPEC_REST}}
#define CVK_SPEC_FINALIZE_TETHERED {8, {CVK_SPEC_PARTICLE_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, \
                                        CVK_SPEC_TETHER_SLOTS, CVK_SPEC_FALSE, CVK_SPEC_FALSE, \
                                        CVK_SPEC_SELF_CONTACT, CVK_SPEC_TRUE, CVK_SPEC_REST}}
/* The last sweep that finalizes (shaders/solvers/pd_gauss_seidel.comp built with
   LAST_FINALIZES; id 7: REST). */
#define CVK_SPEC_PD_LAST {8, {CVK_SPEC_PARTICLE_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, CVK_SPEC_FALSE, \
                              CVK_SPEC_FALSE, CVK_SPEC_FALSE, CVK_SPEC_SELF_CONTACT, \
                              CVK_SPEC_FALSE, CVK_SPEC_REST}}
#define CVK_SPEC_PD_FIRST {6, {CVK_SPEC_PARTICLE_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, CVK_SPEC_TRUE, \
                               CVK_SPEC_FALSE, CVK_SPEC_FALSE, CVK_SPEC_SELF_CONTACT}}
/* The checking first sweeps (id 3: TETHERS of shaders/solvers/pd_common.glsl). */
#define CVK_SPEC_PD_FIRST_CHECK {6, {CVK_SPEC_PARTICLE_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, \
                                 CVK_SPEC_TRUE, CVK_SPEC_TETHERS, CVK_SPEC_FALSE, \
                                 CVK_SPEC_SELF_CONTACT}}
/* The contact passes (ids 2, 3, 4 of shaders/solvers/pd_contact.comp and .glsl): over every
   particle, and over the particles in listed pairs (LISTED, id 2). */
#define CVK_SPEC_PD_CONTACT {5, {CVK_SPEC_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, CVK_SPEC_FALSE, \
                             CVK_SPEC_COLLIDER_TYPES, CVK_SPEC_SELF_CONTACT}}
#define CVK_SPEC_PD_CLOTH_CONTACT {5, {CVK_SPEC_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, CVK_SPEC_TRUE, \
                                   CVK_SPEC_FALSE, CVK_SPEC_TRUE}}
/* The prediction (id 3 of shaders/solvers/predict.comp, WIND; id 7, REST of
   shaders/solvers/pd_common.glsl; ids 2, 4 and 6 unused, 5 BOUNDED). */
#define CVK_SPEC_PREDICT {8, {CVK_SPEC_PARTICLE_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, CVK_SPEC_FALSE, \
                          CVK_SPEC_WIND, CVK_SPEC_FALSE, CVK_SPEC_FALSE, CVK_SPEC_FALSE, \
                          CVK_SPEC_REST}}
/* The implicit passes (id 2 of shaders/solvers/implicit_common.glsl: the contact filter is compiled in
   only for a scene with colliders). */
#define CVK_SPEC_IMPLICIT {3, {CVK_SPEC_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, CVK_SPEC_COLLIDER_TYPES}}
/* The integration (id 3 of shaders/solvers/implicit_integrate.comp: SELF, the displacement
   kept within the bounds for implicit_self.comp) and implicit_self.comp's two passes (id 4:
   LISTED). */
#define CVK_SPEC_IMPLICIT_INTEGRATE {4, {CVK_SPEC_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, \
                                     CVK_SPEC_COLLIDER_TYPES, CVK_SPEC_SELF_CONTACT}}
#define CVK_SPEC_IMPLICIT_SELF_LISTED {5, {CVK_SPEC_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, \
                                       CVK_SPEC_COLLIDER_TYPES, CVK_SPEC_FALSE, CVK_SPEC_TRUE}}
/* implicit_self.comp's pass over the attached particles (id 5: ATTACHED). */
#define CVK_SPEC_IMPLICIT_SELF_ATTACHED {6, {CVK_SPEC_WORKGROUP_SIZE, CVK_SPEC_MAX_DEGREE, \
                                         CVK_SPEC_COLLIDER_TYPES, CVK_SPEC_FALSE, CVK_SPEC_FALSE, \
                                         CVK_SPEC_TRUE}}
/* The collider types (CONTACT_TYPES_ID of shaders/contact/collide.glsl): for the decision's
   check (id 1 of contact_check.comp: which colliders are near), and for the detection passes
   whether the scene has one instance. */
#define CVK_SPEC_CONTACT_TYPES {2, {CVK_SPEC_WORKGROUP_SIZE, CVK_SPEC_COLLIDER_TYPES}}
/* The check's phases (id 2, PHASE, of shaders/contact/contact_check.comp): a pipeline each, as
   edge detection's below. */
#define CVK_SPEC_CONTACT_CHECK(PHASE) {3, {CVK_SPEC_WORKGROUP_SIZE, CVK_SPEC_COLLIDER_TYPES, PHASE}}
/* Edge detection's phases (id 3, PHASE, of shaders/contact/contact_edges.comp): a pipeline
   each, so that a dispatch runs its phase's code alone (llvmpipe runs the code an `if` on a push
   constant skips, under an empty mask). */
#define CVK_SPEC_CONTACT_EDGES(PHASE) {4, {CVK_SPEC_WORKGROUP_SIZE, CVK_SPEC_FALSE, \
                                           CVK_SPEC_COLLIDER_TYPES, PHASE}}
#define CVK_SPEC_CONTACT_EDGES_FUSED {2, {CVK_SPEC_FUSED_WORKGROUP_SIZE, CVK_SPEC_COLLIDER_TYPES}}
/* The decision with the faces' detection in one workgroup (shaders/contact/
   contact_faces_fused.comp). */
#define CVK_SPEC_CONTACT_FACES_FUSED {2, {CVK_SPEC_FUSED_WORKGROUP_SIZE, CVK_SPEC_COLLIDER_TYPES}}
#define CVK_SPEC_NONE {0, {CVK_SPEC_WORKGROUP_SIZE}}
#define CVK_SPEC_WORKGROUP {1, {CVK_SPEC_WORKGROUP_SIZE}}
/* The edge detection's listing pass (id 1, LISTING, of shaders/contact/contact_edges.comp). */
#define CVK_SPEC_LISTING {4, {CVK_SPEC_WORKGROUP_SIZE, CVK_SPEC_TRUE, CVK_SPEC_COLLIDER_TYPES, \
                          CVK_SPEC_FALSE}}
#define CVK_SPEC_PARTICLE_WORKGROUP {1, {CVK_SPEC_PARTICLE_WORKGROUP_SIZE}}

/* A pass whose colliders come in runs of one type (cvk_collide.runs, lib/contact/collide.h):
   CVK_PIPE_<ID> for any colliders, then CVK_PIPE_<ID>_RUNS2..4, built from SHADER's
   COLLIDER_RUNS variants (shaders/meson.build), in that order (cvk_collide_pipeline). SPEC
   reaches X expanded (its braces' commas split it): X takes the recipe and label as `...`. */
#define CVK_COLLIDER_RUN_PIPELINES(X, ID, SHADER, SPEC, LABEL)                   \
    X(ID, SHADER##_COMP, SPEC, LABEL)                                           \
    X(ID##_RUNS2, SHADER##_RUNS2_COMP, SPEC, LABEL ", 2 runs of one collider type") \
    X(ID##_RUNS3, SHADER##_RUNS3_COMP, SPEC, LABEL ", 3 runs of one collider type") \
    X(ID##_RUNS4, SHADER##_RUNS4_COMP, SPEC, LABEL ", 4 runs of one collider type")

/* X(ID, SHADER, spec recipe, "label"): CVK_PIPE_<ID> runs CVK_SHADER_<SHADER>. */
#define CVK_PIPELINE_LIST(X)                                                    \
    X(PREDICT, PREDICT_COMP, CVK_SPEC_PREDICT, "predict (Verlet)")              \
    X(FINALIZE, FINALIZE_COMP, CVK_SPEC_FINALIZE, "x += u")                     \
    X(FINALIZE_TETHERED, FINALIZE_COMP, CVK_SPEC_FINALIZE_TETHERED, "tethers, x += u") \
    X(GS_FIRST, PD_GAUSS_SEIDEL_COMP, CVK_SPEC_PD_FIRST, "gauss-seidel + local step") \
    X(GS_FIRST_PREDICT_SRC, PD_GAUSS_SEIDEL_COMP, CVK_SPEC_PD_FIRST_PREDICT(CVK_SPEC_TRUE), "predict + gauss-seidel + local step") \
    X(GS_FIRST_PREDICT_DST, PD_GAUSS_SEIDEL_COMP, CVK_SPEC_PD_FIRST_PREDICT(CVK_SPEC_VALUE(2)), "predict (last in dst) + gauss-seidel + local step") \
    X(GS, PD_GAUSS_SEIDEL_COMP, CVK_SPEC_PD, "gauss-seidel")                    \
    X(GS_LAST, PD_GAUSS_SEIDEL_LAST_COMP, CVK_SPEC_PD_LAST, "gauss-seidel + x += u") \
    X(GS_FUSED, PD_FUSED_COMP, CVK_SPEC_PD_FUSED, "gauss-seidel, fused sweeps") \
    X(GS_FUSED_PLAIN, PD_FUSED_PLAIN_COMP, CVK_SPEC_PD_FUSED, "gauss-seidel, fused sweeps") \
    X(JACOBI_FIRST, PD_JACOBI_COMP, CVK_SPEC_PD_FIRST, "jacobi + local step")   \
    X(JACOBI, PD_JACOBI_COMP, CVK_SPEC_PD, "jacobi")                            \
    X(GS_FIRST_CHECK, PD_GAUSS_SEIDEL_CHECK_COMP, CVK_SPEC_PD_FIRST_CHECK, "gauss-seidel + local step + residual") \
    X(JACOBI_FIRST_CHECK, PD_JACOBI_CHECK_COMP, CVK_SPEC_PD_FIRST_CHECK, "jacobi + local step + residual") \
    X(PD_REDUCE, PD_REDUCE_COMP, CVK_SPEC_WORKGROUP, "residual: partial sums")  \
    X(PD_DECIDE, PD_DECIDE_COMP, CVK_SPEC_NONE, "residual: stop or go on")      \
    X(PD_COPY, PD_COPY_COMP, CVK_SPEC_PARTICLE_WORKGROUP, "u0 = u1 (stopped in u1)")    \
    CVK_COLLIDER_RUN_PIPELINES(X, PD_CONTACT, PD_CONTACT, CVK_SPEC_PD_CONTACT, "contact (colliders, bounds)") \
    CVK_COLLIDER_RUN_PIPELINES(X, PD_CONTACT_PLAIN, PD_CONTACT_PLAIN, CVK_SPEC_PD_CONTACT, "contact (colliders, bounds)") \
    X(PD_CLOTH_CONTACT, PD_CLOTH_CONTACT_COMP, CVK_SPEC_PD_CLOTH_CONTACT, "contact between cloths (listed particles)") \
    X(PD_TETHER, PD_TETHER_COMP, CVK_SPEC_PD_TETHER, "tethers")                        \
    X(PD_STRAIN, PD_STRAIN_COMP, CVK_SPEC_PD, "strain limit (one colour)")              \
    X(COLLIDER_POSES, COLLIDER_POSES_COMP, CVK_SPEC_NONE, "collider poses, frame state") \
    X(ATTACH, ATTACH_COMP, CVK_SPEC_NONE, "attached particles, frame state") \
    X(ATTACH_IMPLICIT, ATTACH_IMPLICIT_COMP, CVK_SPEC_NONE, "attached particles: v or x (implicit)") \
    X(GRAB, GRAB_COMP, CVK_SPEC_NONE, "grabbed particle -> target") \
    X(PICK, PICK_COMP, CVK_SPEC_NONE, "nearest particle on a ray (outside the frame)") \
    X(TEAR, TEAR_COMP, CVK_SPEC_WORKGROUP, "tear overstretched springs") \
    X(AERO_TRIANGLES, AERO_TRIANGLES_COMP, CVK_SPEC_WORKGROUP, "air force per triangle") \
    X(AERO_GATHER, AERO_GATHER_COMP, CVK_SPEC_WORKGROUP, "air force per particle") \
    CVK_COLLIDER_RUN_PIPELINES(X, CONTACT_CHECK, CONTACT_CHECK, CVK_SPEC_CONTACT_CHECK(CVK_SPEC_VALUE(0)), "bounds of the extrapolated moves") \
    CVK_COLLIDER_RUN_PIPELINES(X, CONTACT_CHECK_EXCEED, CONTACT_CHECK, CVK_SPEC_CONTACT_CHECK(CVK_SPEC_VALUE(1)), "moves past their bounds?") \
    X(CONTACT_DECIDE, CONTACT_DECIDE_COMP, CVK_SPEC_NONE, "detect or not, shift") \
    X(CONTACT_DETECT, CONTACT_DETECT_COMP, CVK_SPEC_CONTACT_TYPES, "detection: vertices against faces") \
    X(CONTACT_EDGES, CONTACT_EDGES_COMP, CVK_SPEC_CONTACT_EDGES(CVK_SPEC_VALUE(0)), "detection: edges against edges") \
    X(CONTACT_EDGES_MEASURE, CONTACT_EDGES_COMP, CVK_SPEC_CONTACT_EDGES(CVK_SPEC_VALUE(1)), "detection: the edges measured") \
    X(CONTACT_EDGES_NEAREST, CONTACT_EDGES_COMP, CVK_SPEC_CONTACT_EDGES(CVK_SPEC_VALUE(2)), "detection: the edges' nearest pairs") \
    X(CONTACT_EDGES_CELLS, CONTACT_EDGES_COMP, CVK_SPEC_CONTACT_EDGES(CVK_SPEC_VALUE(3)), "detection: the edges' cells") \
    X(CONTACT_EDGES_GATHER, CONTACT_EDGES_COMP, CVK_SPEC_CONTACT_EDGES(CVK_SPEC_VALUE(4)), "detection: the edge cells' lists") \
    X(CONTACT_EDGES_WALK, CONTACT_EDGES_COMP, CVK_SPEC_CONTACT_EDGES(CVK_SPEC_VALUE(5)), "detection: the edges that walk") \
    X(CONTACT_EDGES_LISTS, CONTACT_EDGES_COMP, CVK_SPEC_LISTING, "detection: the edges' pairs") \
    X(CONTACT_BOUND, CONTACT_BOUND_COMP, CVK_SPEC_CONTACT_TYPES, "detection: bounds") \
    X(CONTACT_FACES_FUSED, CONTACT_FACES_FUSED_COMP, CVK_SPEC_CONTACT_FACES_FUSED, "detect or not, faces' hash and detection, one workgroup") \
    X(CONTACT_EDGES_FUSED, CONTACT_EDGES_FUSED_COMP, CVK_SPEC_CONTACT_EDGES_FUSED, "midpoints' hash, edges' detection and bounds, one workgroup") \
    X(HASH_CLEAR, HASH_CLEAR_COMP, CVK_SPEC_WORKGROUP, "hash: clear")           \
    X(HASH_COUNT, HASH_COUNT_COMP, CVK_SPEC_WORKGROUP, "hash: count")           \
    X(HASH_CHUNK_SUMS, HASH_CHUNK_SUMS_COMP, CVK_SPEC_WORKGROUP, "hash: chunk sums") \
    X(HASH_SCAN_CHUNKS, HASH_SCAN_CHUNKS_COMP, CVK_SPEC_WORKGROUP, "hash: scan chunks") \
    X(HASH_SCAN, HASH_SCAN_COMP, CVK_SPEC_WORKGROUP, "hash: scan")              \
    X(HASH_SCATTER, HASH_SCATTER_COMP, CVK_SPEC_WORKGROUP, "hash: scatter")     \
    X(HASH_COMMANDS, HASH_COMMANDS_COMP, CVK_SPEC_NONE, "hash: build or not")   \
    X(HASH_NEIGHBOURS, HASH_NEIGHBOURS_COMP, CVK_SPEC_WORKGROUP, "hash: neighbours") \
    X(IMPLICIT_CONTACT, IMPLICIT_CONTACT_COMP, CVK_SPEC_IMPLICIT, "implicit: held on colliders, S") \
    X(IMPLICIT_ASSEMBLE, IMPLICIT_ASSEMBLE_COMP, CVK_SPEC_IMPLICIT, "implicit: blocks, b, dv = 0") \
    X(IMPLICIT_CG_START, IMPLICIT_CG_START_COMP, CVK_SPEC_IMPLICIT, "cg: z = P^-1 r, p = z, r.z") \
    X(IMPLICIT_CG_RHO0, IMPLICIT_RHO0_COMP, CVK_SPEC_IMPLICIT, "cg: rho0") \
    X(IMPLICIT_CG_PRODUCT, IMPLICIT_CG_PRODUCT_COMP, CVK_SPEC_IMPLICIT, "cg: q = A p, p.q") \
    X(IMPLICIT_CG_ALPHA, IMPLICIT_ALPHA_COMP, CVK_SPEC_IMPLICIT, "cg: alpha") \
    X(IMPLICIT_CG_UPDATE, IMPLICIT_CG_UPDATE_COMP, CVK_SPEC_IMPLICIT, "cg: dv, r, z, r.z") \
    X(IMPLICIT_CG_BETA, IMPLICIT_BETA_COMP, CVK_SPEC_IMPLICIT, "cg: beta, stop test") \
    X(IMPLICIT_CG_DIRECTION, IMPLICIT_CG_DIRECTION_COMP, CVK_SPEC_IMPLICIT, "cg: p = z + beta p") \
    X(IMPLICIT_JACOBI_EVEN, IMPLICIT_JACOBI_EVEN_COMP, CVK_SPEC_IMPLICIT, "block jacobi: dv0 -> dv1") \
    X(IMPLICIT_JACOBI_ODD, IMPLICIT_JACOBI_ODD_COMP, CVK_SPEC_IMPLICIT, "block jacobi: dv1 -> dv0") \
    X(IMPLICIT_JACOBI_CHECK, IMPLICIT_JACOBI_CHECK_COMP, CVK_SPEC_IMPLICIT, "block jacobi: stop test") \
    X(IMPLICIT_INTEGRATE, IMPLICIT_INTEGRATE_COMP, CVK_SPEC_IMPLICIT_INTEGRATE, "v += dv, x += h v") \
    X(IMPLICIT_SELF_LISTED, IMPLICIT_SELF_COMP, CVK_SPEC_IMPLICIT_SELF_LISTED, "implicit: contact between cloths (listed particles)") \
    X(IMPLICIT_SELF_APPLY, IMPLICIT_SELF_COMP, CVK_SPEC_IMPLICIT, "implicit: x += the kept displacement") \
    X(IMPLICIT_SELF_ATTACHED, IMPLICIT_SELF_COMP, CVK_SPEC_IMPLICIT_SELF_ATTACHED, "implicit: attached particles within their bounds") \
    X(EXPLICIT_FORCE, EXPLICIT_FORCE_COMP, CVK_SPEC_PD, "explicit: a = f(x, v) / m") \
    X(EXPLICIT_UPDATE, EXPLICIT_UPDATE_COMP, CVK_SPEC_PD, "explicit: x, v from a (the integrator's rule)")

typedef enum cvk_pipeline_id {
#define CVK_PIPE_ID(id, ...) CVK_PIPE_##id,
    CVK_PIPELINE_LIST(CVK_PIPE_ID)
#undef CVK_PIPE_ID
    CVK_PIPE_COUNT
} cvk_pipeline_id;

const char* cvk_pipeline_label(cvk_pipeline_id id);
/* Whether pipeline `id` runs with the particle passes' workgroup size (its local size is
   CVK_SPEC_PARTICLE_WORKGROUP_SIZE), so its dispatches count groups of that size. */
bool cvk_pipeline_streams_particles(cvk_pipeline_id id);

/* The values the recipes draw from. */
typedef struct cvk_spec_inputs {
    uint32_t workgroup_size;
    uint32_t particle_workgroup_size; /* 0: workgroup_size */
    uint32_t fused_workgroup_size;    /* 0: workgroup_size */
    uint32_t fused_shared_slots;      /* the fused sweeps' iterate in shared memory: its slots */
    bool fused_one_copy;              /* the fused sweeps take the whole scene as one copy */
    uint32_t max_degree;
    uint32_t collider_types; /* bit t: colliders of type t */
    bool self_contact;
    bool wind;
    bool tethers;
    uint32_t tether_slots;
    bool rest; /* the scene's rest rate is above 0 (solvers/reference.h) */
} cvk_spec_inputs;

typedef struct cvk_pipelines {
    VkPipeline pipeline[CVK_PIPE_COUNT];
    VkPipelineLayout layout[CVK_PIPE_COUNT]; /* the layout each was created with */
    bool fresh[CVK_PIPE_COUNT];              /* created since the last warm-up */
} cvk_pipelines;

/* Creates pipeline `id` with `layout` unless it exists. */
cvk_result cvk_pipelines_require(cvk_context* context, cvk_pipelines* pipelines,
                                 cvk_pipeline_id id, VkPipelineLayout layout,
                                 const cvk_spec_inputs* inputs, cvk_error* error);
void cvk_pipelines_destroy(cvk_context* context, cvk_pipelines* pipelines);

#endif
