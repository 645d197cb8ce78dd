/* Collisions on the device: the colliders' keyframed poses advanced by the recorded work itself
   (one frame buffer, no host writes per frame), contact with colliders projected inside every
   solver sweep (continuous: a particle's path over the substep, in the collider's moving frame,
   is traced against the collider thickened by the cloth thickness, so nothing tunnels), Coulomb
   friction against the surface's own motion, and contact between cloths with a guarantee.

   Cloth against cloth (Offset Geometric Contact, Chen et al. 2025): every face, edge and vertex
   of the cloths is offset by the thickness, and a vertex–feature pair (the feature the nearest
   point lies on: a face, an edge or a vertex) or an edge–edge pair (nearest points inside both
   edges) closer than the thickness is pushed apart along the line between the nearest points, so
   a large thickness leaves no artefacts. No cloth passes through cloth because of bounds, not
   continuous collision detection: detection (hashes of the triangles' centroids and of the
   edges' midpoints, then every vertex against the faces and every edge against the edges within
   the contact radius, all pairs, shaders/contact/contact_detect.comp and contact_edges.comp)
   gives each vertex v the nearest distance d_v from it, from the faces around it and from its
   edges to anything not adjacent (the radius where nothing is nearer), and the bound b_v = gamma
   (d_v - f_v) with gamma < 1/2 and f_v v's gap floor (shared/layout.h, contact_bound.comp).
   Every pass that moves v keeps it within b_v of where detection saw it plus a shift M common to
   all particles (the cloths' common motion, which changes no distance): two features that were d
   apart then each moved at most gamma (d - f) relative to the other's frame (f their corners'
   floors), so they stay at least (1 - 2 gamma) d + 2 gamma f apart — never nearer than about f,
   however often they are squeezed — and never cross. A start free of intersections stays free.
   Those passes are pd's sweeps, strain limit, tethers and contact passes, and implicit Euler's
   integration, which keeps each substep's displacement within the bound before
   implicit_self.comp pushes the listed particles off the cloth features and moves them.
   Colliders push after the bound: the push (a funnel's edge test's too) is brought back within
   it where the particle stays outside every solid collider and on its side of every funnel
   (pd_contact.glsl; implicit's integration likewise keeps the bound only where that leaves the
   particle outside every solid collider), the shift is 0 at a detection while a particle is
   near a collider, and a substep detects rather than centre a bound nearer a collider than the
   thickness less the bound (contact_check.comp). At the start of each substep the device decides (contact_check.comp,
   contact_decide.comp) whether some particle's move, extrapolated from its last substep, would
   pass `redetect` of its bound from the shift the substep would take; only then does detection
   run (the hash build and the passes are dispatched indirectly, with no workgroups otherwise),
   so one recorded frame replays with no host work and a cloth at rest or moving as one detects
   nothing. With collision.detection_interval N > 1 such a detection waits for substep N, 2N,
   ... of the run, the particles held at their bounds until then (the bounds keep the
   guarantee whatever the moves); a bound centred too near a collider, an attached particle's
   move, or a particle a collider's push left past its bound still detects at once
   (CVK_EXCEED_NOW).

   The module owns one descriptor set, the contact set, which every solver family's pipelines
   bind as set 1 (shaders/contact/collide.glsl declares it); a scene without colliders and
   without self-contact still gets a small set (so layouts stay one shape) but records no
   collision pass and compiles no contact code (specialisation constant CONTACT). */
#ifndef CVK_COLLIDE_H
#define CVK_COLLIDE_H

#include "topology/build.h"
#include "contact/hash.h"
#include "scene/motion.h"
#include "contact/sdf.h"
#include "shared/layout.h"

struct cvk_sim;

/* The bound's fraction of the nearest distance (< 1/2; the margin covers a collider's push
   after the bound, which is at most the penetration of a point already within it). */
#define CVK_BOUND_GAMMA 0.45f
/* Detect when a particle's extrapolated move would pass this fraction of its bound. */
#define CVK_REDETECT_FRACTION 0.9f

typedef struct cvk_collide {
    bool colliding;              /* colliders or self-contact: contact passes are recorded */
    bool self;                   /* contact between and within cloths */
    uint32_t types;              /* bit t: colliders of type t (a funnel, a surface rather
                                    than a solid, has the cloth's edges kept off it too, so
                                    the triangle tables are built for it); an instance's
                                    colliders as runs of one type; and
                                    CVK_COLLIDERS_IN_STORAGE
                                    (shared/layout.h) */
    uint32_t runs;               /* runs of one type an instance's colliders make, when in
                                    `types` (the contact pass's build for that many), or 0 */
    float thickness;             /* m, resolved (collision.thickness or its default) */
    float radius;                /* m: the contact radius, resolved */
    uint32_t detection_interval; /* collision.detection_interval, resolved (>= 1) */
    float longest;               /* m: the longest an edge may be (1.5 × the longest at rest) */
    float friction, static_friction;

    uint32_t collider_count;
    cvk_collider_desc* colliders;/* deep copies (keyframes, names and files owned here) */
    cvk_sdf* sdfs;               /* per collider; all zero but for CVK_COLLIDER_MESH */

    cvk_buffer frame;            /* cvk_gpu_frame, then cvk_gpu_motion_bounds */
    cvk_buffer poses;            /* cvk_gpu_pose per collider (at least one element) */
    cvk_buffer shapes;           /* cvk_gpu_collider per collider */
    cvk_buffer uniform_stub;     /* bound as the uniform arrays when there are more colliders
                                    than they hold (the shaders then read shapes and poses) */
    cvk_buffer keyframes;        /* 2 vec4 per keyframe: (time, translation), rotation (x, y, z, w) */
    cvk_buffer sdf_values;       /* every mesh collider's field, back to back */
    cvk_buffer params;           /* cvk_gpu_contact_params */
    cvk_buffer triangles;        /* uvec4 per cloth triangle: internal particle indices, and
                                    in w the border bits of its edges (collide.c) */
    cvk_buffer incident;         /* per particle + 1 offsets, then the ids of its triangles */
    uint32_t edge_count;
    cvk_buffer edges;            /* uvec4 per edge: its ends (lower first), 0, 0 */
    cvk_buffer triangle_edges;   /* uvec4 per triangle: edge k runs from corner k to k + 1 */
    cvk_buffer particle_edges;   /* per particle + 1 offsets, then the ids of its edges */
    cvk_buffer contacts;         /* CVK_CONTACTS_PER_PARTICLE uint per particle */
    cvk_buffer edge_contacts;    /* CVK_CONTACTS_PER_EDGE uint per edge */
    cvk_buffer nearest;          /* uint per particle, then per edge (float bits) */
    cvk_buffer searched;         /* vec4 per particle: where detection saw it, w: its bound */
    cvk_buffer previous;         /* vec4 per particle: its position a substep before */
    cvk_buffer sides;            /* per particle a count, then CVK_SIDES_PER_PARTICLE pairs
                                    (vertex, entry) in which it is a corner of the feature */
    cvk_buffer lists;            /* detection's indirect commands (shared/layout.h: CVK_LIST_*) */
    cvk_buffer midpoints;        /* vec4 per edge: its midpoint at the last detection */
    cvk_buffer centroids;        /* vec4 per triangle: its centroid at the last detection */
    cvk_buffer cells, cell_pool; /* edge detection's cell lists (shared/layout.h: CVK_CELLS_*) */
    /* The scene's instances (copies that never touch one another: lib/scene/scene_instances.c
       lays them out copy by copy, each with cloth_count / instance_count cloths and
       collider_count / instance_count colliders): a particle meets its own copy's colliders
       and cloth features only. */
    uint32_t instance_count;     /* 1 when the scene is not copied */
    uint32_t instance_colliders; /* colliders per instance */
    uint32_t* instance_of;       /* per particle (internal): its instance; NULL with one */
    cvk_buffer instances;        /* the same on the device (zeros with one instance) */
    cvk_buffer edge_instances;   /* uint per edge: its instance (self-contact with several
                                    instances; 16 bytes otherwise) */
    cvk_buffer triangle_instances; /* uint per triangle: the same */
    cvk_hash face_hash;          /* only with self-contact: the triangles' centroids */
    cvk_hash edge_hash;          /* only with self-contact: the edges' midpoints */
    VkBufferView view_triangles, view_incident, view_contacts, view_searched;
    VkBufferView view_edges, view_triangle_edges, view_particle_edges, view_edge_contacts;
    VkBufferView view_sides, view_instances, view_cell_pool,
        view_edge_ends; /* the cell pool's first part: each edge's ends at detection */
    VkBufferView view_nearest, view_previous;

    cvk_descriptors descriptors; /* the contact set; its pipeline layout: the contact set alone */
    VkDescriptorSetLayout set_layout; /* = descriptors.set_layout, for the families' layouts */
    VkDescriptorSet set;              /* = descriptors.sets[0] */
    VkPipelineLayout detect_layout;   /* contact set, then the hash's set */
    VkPipelineLayout fused_layout; /* fused detection: contact set, a hash, the midpoints' hash;
                                      cvk_contact_hash_push */
} cvk_collide;

/* Resolves the scene's collision settings, reads mesh colliders into fields, makes the buffers
   and the contact set. Messages name the key ("colliders.1.file: ..."). */
cvk_result cvk_collide_create(struct cvk_sim* sim, const cvk_scene_desc* scene, cvk_error* error);
void cvk_collide_destroy(struct cvk_sim* sim);

/* The collision passes at the start of every substep, before the family's: the colliders'
   poses ("colliders"), and with self-contact the decision ("contacts"), the hashes of the
   triangles' centroids and the edges' midpoints ("hash") and detection with the bounds. Nothing when the scene does not collide. */
cvk_result cvk_collide_add_passes(struct cvk_sim* sim, cvk_plan* plan, cvk_error* error);

/* The hash and the detection pass's layout (self-contact only); called by cvk_collide_create. */
cvk_result cvk_collide_create_detection(struct cvk_sim* sim, cvk_error* error);

/* Puts the device's substep counter at `step` and asks for detection at the next substep; the
   colliders' poses too (cvk_collide_write_poses). */
cvk_result cvk_collide_set_step(struct cvk_sim* sim, uint64_t step, cvk_error* error);
/* Writes the colliders' poses as `step` substeps leave them (the last substep's start and end),
   so what draws them before the next step sees them where the clock says. */
cvk_result cvk_collide_write_poses(struct cvk_sim* sim, uint64_t step, cvk_error* error);
/* The poses over the substep that ends after `step` substeps of dt (both at time 0 before the
   first), as collider_poses.comp leaves them; one per collider. */
void cvk_collide_poses_at(const cvk_collide* collide, uint64_t step, double dt, cvk_gpu_pose* poses);

/* After the state was written from the host (x and v: 3 floats per particle, internal order;
   v NULL: at rest): the next substep detects again, and its shift follows the written
   velocities — the substep before is taken to have moved each particle by v dt. */
cvk_result cvk_collide_positions_written(struct cvk_sim* sim, const float* x, const float* v,
                                         cvk_error* error);

/* Since creation (a snapshot carries them; 0 without self-contact): the detections run, and
   the free particles that ended a substep past CVK_REDETECT_FRACTION of their bound, summed
   over the substeps — where the bounds held motion back (a cloth moving faster than a bound a
   substep relative to the rest, or squeezed: docs/limits.md) — and that count as a fraction
   of the free particles' substeps (the first after the state was written not counted); the
   particles found crowded (a corner in more pairs than their side lists hold, which then keep
   none: contact_bound.glsl), summed over the detections. */
cvk_result cvk_collide_counts(struct cvk_sim* sim, uint64_t* searches, uint64_t* held,
                              double* held_fraction, uint64_t* crowded, bool* cut,
                              cvk_error* error);

/* The contact state a snapshot carries so that stepping on from it gives the same bits: the
   frame state, where the last detection saw each particle and its bound, the lists, and each
   particle's position a substep before (self-contact; 0 bytes otherwise). Save writes exactly
   cvk_collide_snapshot_size bytes; load takes them. */
uint64_t cvk_collide_snapshot_size(const struct cvk_sim* sim);
cvk_result cvk_collide_save_snapshot(struct cvk_sim* sim, unsigned char* data, cvk_error* error);
cvk_result cvk_collide_load_snapshot(struct cvk_sim* sim, const unsigned char* data,
                                     cvk_error* error);

/* The scene's instances as the device keeps them apart: scene->instances.count when its cloths
   and colliders divide evenly into that many copies (as a file's "instances" block expands),
   else 1. */
uint32_t cvk_collide_instance_count(const cvk_build* build, const cvk_scene_desc* scene);

/* Sets collide's instance_count, instance_colliders and instance_of (per particle, internal
   order; NULL with one instance) for the simulation's build (cvk_collide_create). */
cvk_result cvk_collide_find_instances(struct cvk_sim* sim, cvk_collide* collide,
                                      const cvk_scene_desc* scene, cvk_error* error);

/* An instance's colliders as runs of one type, the bits of the collider types' specialisation
   constant (shared/layout.h), where every instance has the same and they make 2 to
   CVK_COLLIDER_RUNS runs of at most CVK_COLLIDER_RUN_MAX colliders; *runs is their count. 0
   and 0 otherwise (after cvk_collide_find_instances). */
uint32_t cvk_collide_runs(const cvk_collide* collide, uint32_t* runs);

/* Whether the scene has a funnel: the cloth tables for its edge test, and the builds of the
   contact passes with that test (shaders/solvers/pd_contact.glsl, NO_FUNNELS). */
bool cvk_collide_has_funnels(const cvk_collide* collide);

/* The build of a pass over the particles for the colliders' runs (cvk_collide.runs): runs2 for
   2 runs and the pipelines after it for more (pd_contact.comp's and contact_check.comp's), or
   `generic` without runs. */
cvk_pipeline_id cvk_collide_pipeline(const cvk_collide* collide, cvk_pipeline_id generic,
                                     cvk_pipeline_id runs2);

/* Per triangle (scene order): its instance, for the host's pair tests; NULL (and CVK_SUCCESS)
   with one instance. The caller frees it. */
cvk_result cvk_collide_triangle_instances(const cvk_build* build, uint32_t instance_count,
                                          uint32_t** out, cvk_error* error);

/* The pose of collider `index` at simulated time t (s), as the device computes it. */
cvk_pose cvk_collide_pose(const cvk_collide* collide, uint32_t index, double t);

/* The fastest any point of collider `index`'s surface moves under its keyframes, m/s: each
   segment's translation speed plus its turn rate times the surface's reach from the scene
   origin (keyframes are interpolated linearly and by slerp: a segment's speeds are constant).
   A plane's rotation is not counted (its surface has no reach); a loop's jump back is not a
   motion. 0 for a static collider. */
float cvk_collide_surface_speed(const cvk_collide* collide, uint32_t index);

/* With self-contact (called once the thickness is known, before anything reads the step): a
   collider's push must stay within the bounds, and the bound of a particle a thickness from
   other cloth is gamma times that, so a substep in which some keyframed collider's surface
   moves more than 0.35 thicknesses is split into as many equal substeps as keep it within
   that (s->params: the frame's time, and the damping over it, unchanged), and s->notes says
   so. sphere-hit.json's own steps, its 8.8 m/s ball 0.34 thicknesses a substep, pass; twice
   that (0.68) tore its cloths apart. Implicit Euler keeps the bounds only after its solve, so
   its neighbours do not make room for a particle the bound stops within the substep: for it
   the limit is half (`implicit`): sphere-hit at 0.34 tore its cloths (1060 % stretched,
   intersecting pairs from frame 32), at 0.17 it ran clean. */
void cvk_collide_split_substeps(struct cvk_sim* s, cvk_collide* c, bool implicit);

/* The most of the thickness the fastest keyframed collider's surface moves in one substep
   (0 for static colliders), and the most it may move with self-contact under the method. */
double cvk_collide_fastest_move(const struct cvk_sim* s, const cvk_collide* c);
double cvk_collide_move_limit(bool implicit);

/* Signed distance (m, negative inside) from p to collider `index` posed at time t, and the
   outward unit normal there (may be NULL). The funnel's is unsigned. */
float cvk_collide_distance(const cvk_collide* collide, uint32_t index, double t, const float p[3],
                           float normal[3]);

#endif
