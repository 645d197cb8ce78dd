/* Collisions on the device: the colliders' keyframed poses advanced by the recorded work itself
   (one frame buffer, no host writes per frame), contact with colliders projected inside every
   solver sweep (continuous: a particle's path over the substep, in the collider's moving frame,
   is traced against the collider thickened by the cloth thickness, so nothing tunnels), Coulomb
   friction against the surface's own motion, and particle–triangle contact between cloths
   found through the spatial hash (hash.h) and resolved in the same sweeps.

   The candidates are searched adaptively by default (Verlet lists, as molecular dynamics keeps
   neighbour lists with a skin): a search keeps the triangles within 2.5 thicknesses of each
   particle, and a new search runs only at a substep that starts with some particle's
   displacement since the last search more than a quarter thickness from the centre of all the
   displacements' bounds (two particles then approached by at most half a thickness, and a
   cloth that moves as one needs no search), so every pair within two thicknesses at the start
   of any substep (what one substep can bring into contact, as when searching every substep) is
   still among the candidates. The device decides (contact_check.comp,
   contact_decide.comp); the hash build (dispatched indirectly, with no workgroups: hash.h)
   and the search do nothing at the other substeps. A cloth
   at rest then costs no search at all. collision.detect_every = k searches every k substeps
   instead, whatever moved.

   Patches: a search first rules out, as a whole, the parts of the cloths that cannot hold a
   candidate. The triangles are grouped at creation into patches (per cloth, the connected
   pieces of the triangles whose rest centroids share a cube about six rest edges wide; at
   most CVK_MAX_PATCHES). At a search, each patch's bounding box and normal cone (the axis of
   its triangles' unit normals and the largest angle from it) are measured on the device, and
   a patch is active unless it is flat itself (every normal within CVK_FLAT_DEGREES of its
   axis, neither of a triangle's two shorter rest edges squeezed below CVK_PATCH_SQUEEZE of
   its rest length) and every other patch
   whose box comes within the detection radius of its own is a rest neighbour (triangles of
   the two meet at a particle or at a triangle's corners) with which it stays flat (every
   normal of both within CVK_FLAT_DEGREES of its axis). A surface that flat is a height field
   over its axis: a particle near a triangle of it is near it along the surface, a neighbour
   no contact is needed against (the springs keep those apart); layers stacked on it, its own
   folds, a border squeezed so hard that it may have slid over itself within its plane (a
   cloth crushed against a wall), and other cloths make it active. Only the free particles of active patches (and particles on no
   triangle) search, listed on the device and searched through an indirect dispatch; the
   particles that came out with candidates are listed too, and a scene without colliders
   visits only them in its contact passes. A flat cloth moving in space thus costs neither a
   hash build nor a walk, nor a contact pass.

   Untangling: contact keeps a pair on the side it was found on, so a region that went
   through another surface (a fold's tip pushed through a layer, particles written from the
   host on the wrong side) would be held there. After each search, the edges of the listed
   particles are tested against their candidate triangles; the cut edges divide each cloth
   into regions (labels propagated across uncut edges and pointer-jumped on the device,
   CVK_UNTANGLE_ROUNDS rounds), and a region that converged and is at most a quarter of its
   cloth's largest (CVK_UNTANGLE_SMALLER) is the part that went through (global intersection
   analysis, Baraff, Witkin and Kass 2003; "the small region is the wrong one"). Its pairs
   with the faces over it of the
   cloths that cut it are listed with the other side and marked (CVK_UNTANGLE_PAIR), and the
   contact pass brings them back by at most a tenth of a thickness a substep, from any depth
   (shaders/contact/untangle.comp). With no cut edge the step costs one pass over the listed
   particles and a few empty dispatches.

   The module owns one descriptor set, the contact set, which every solver family's pipelines
   bind as set 1 (shaders/contact/collide.glsl declares it); a scene without colliders and without
   self-contact still gets a small set (so layouts stay one shape) but records no collision
   pass and compiles no contact code (specialisation constant CONTACT). */
#ifndef CVK_COLLIDE_H
#define CVK_COLLIDE_H

#include "topology/build.h"
#include "contact/hash.h"
#include "scene/motion.h"
#include "contact/sdf.h"
#include "shared/layout.h"

struct cvk_sim;

/* Particle–triangle pairs nearer than this many thicknesses are kept as candidates, for the
   substeps until the next search (collision.detect_every): the margin beyond the thickness
   covers the approach in between. Searching every substep, two thicknesses; less often, three.
   Wider radii find more triangles per layer than a particle keeps (CVK_CONTACTS_PER_PARTICLE,
   nearest first), and a particle in a stack then loses the farther layer's. */
#define CVK_DETECT_RADIUS_THICKNESSES(every) ((every) == 0 ? 2.5f : (every) > 1 ? 3.0f : 2.0f)
/* Particles of one cloth within this many thicknesses of a triangle's corner at rest are not in
   contact with it. Less than the nearest rest distance between a particle and a triangle not
   its own in a grid (a spacing from the corner, half the diagonal from the edge: 1.41 default
   thicknesses), so with the default thickness only the particle's own triangles are left out
   and a flat cloth is in contact with none; more than the thickness, so a particle is never
   pushed off a triangle whose corner lies within the thickness of it at rest. */
#define CVK_EXCLUSION_THICKNESSES 1.5f
/* Adaptive search: a new one once a particle's displacement since the last is this many
   thicknesses from the displacements' centre (two particles then approached by at most the
   margin beyond two thicknesses). */
#define CVK_SEARCH_AFTER_THICKNESSES 0.25f
/* Patches (above): about this many rest edges across, at most this many (larger ones in big
   scenes: the device compares every pair), flat within this angle. */
#define CVK_PATCH_EDGES 6.0f
#define CVK_MAX_PATCHES 2048u
#define CVK_FLAT_DEGREES 80.0f

typedef struct cvk_collide {
    bool colliding;              /* colliders or self-contact: contact passes are recorded */
    bool self;                   /* particle–triangle contact between cloths */
    bool edges;                  /* edge–edge contact too (collision.edges; with self only) */
    uint32_t types;              /* bit t: colliders of type t (a funnel, a surface rather
                                    than a solid, has the cloth's edges kept off it too, so
                                    the triangle tables are built for it) */
    float thickness;             /* m, resolved (collision.thickness or its default) */
    float friction, static_friction;
    uint32_t detect_every;       /* substeps from one candidate search to the next; 0: adaptive */

    uint32_t collider_count;
    cvk_collider_desc* colliders;/* deep copies (keyframes, names and files owned here) */
    cvk_sdf* sdfs;               /* per collider; all zero but for CVK_COLLIDER_MESH */

    cvk_buffer frame;            /* cvk_gpu_frame, then cvk_gpu_motion_bounds */
    cvk_buffer poses;            /* cvk_gpu_pose per collider (at least one element) */
    cvk_buffer shapes;           /* cvk_gpu_collider per collider */
    cvk_buffer keyframes;        /* 2 vec4 per keyframe: (time, translation), rotation (x, y, z, w) */
    cvk_buffer sdf_values;       /* every mesh collider's field, back to back */
    cvk_buffer params;           /* cvk_gpu_contact_params */
    cvk_buffer triangles;        /* uvec4 per cloth triangle: internal particle indices, and
                                    in w the border bits of its edges (collide.c) */
    cvk_buffer incident;         /* per particle + 1 offsets, then the ids of its triangles */
    cvk_buffer rest;             /* vec4 per particle: rest position, cloth index */
    float* rest_xyz;             /* the same on the host (self-contact only) */
    float exclusion;             /* m: pairs nearer than this at rest are never in contact */
    float longest_edge;          /* m: the longest edge of any cloth triangle at rest */
    float edge_exclusion;        /* m: edge pairs of one cloth with ends this near at rest are
                                    never in contact (collision.edges: the exclusion plus 1.5
                                    longest edges, so a flat cloth has no edge pairs of its own) */
    float detect_radius;         /* m: candidates are kept within it */
    cvk_buffer contacts;         /* CVK_CONTACTS_PER_PARTICLE uint per particle */
    cvk_buffer searched;         /* vec4 per particle: its position at the last search */
    cvk_hash hash;               /* only with self-contact */
    /* Surface patches (self-contact only): see "Patches" above. */
    uint32_t patch_count;
    uint32_t patch_neighbours;   /* where the neighbour offsets start in the patch table */
    uint32_t* patch_table;       /* the table on the host too (shared/layout.h) */
    size_t patch_table_size;     /* uints */
    cvk_buffer patch_table_buffer;
    cvk_buffer patch_bounds;     /* vec4 × 3 per patch: low, high, normal cone; then, with
                                    search lanes, vec4 × 3 per triangle: low, high, unit normal
                                    and whether it is degenerate or squeezed
                                    (shaders/contact/contact_patch.comp) */
    cvk_buffer patch_active;     /* uint per patch */
    cvk_buffer lists;            /* the work lists (shared/layout.h: CVK_LIST_*) */
    VkBufferView view_triangles, view_incident, view_rest, view_contacts; /* texel views */
    VkBufferView view_patch_table, view_patch_bounds, view_searched;

    cvk_descriptors descriptors; /* the contact set; its pipeline layout: the contact set alone */
    VkDescriptorSetLayout set_layout; /* = descriptors.set_layout, for the families' layouts */
    VkDescriptorSet set;              /* = descriptors.sets[0] */
    VkPipelineLayout detect_layout;   /* contact set, then the hash's set */
} cvk_collide;

/* Resolves the scene's collision settings, reads mesh colliders into fields, makes the buffers
   and the contact set. Messages name the key ("colliders.1.file: ..."). */
cvk_result cvk_collide_create(struct cvk_sim* sim, const cvk_scene_desc* scene, cvk_error* error);
void cvk_collide_destroy(struct cvk_sim* sim);

/* The collision passes at the start of every substep, before the family's: the colliders'
   poses ("colliders"), and with self-contact the hash of the positions ("hash") and the
   particle–triangle candidates ("contacts"). Nothing when the scene does not collide. */
cvk_result cvk_collide_add_passes(struct cvk_sim* sim, cvk_plan* plan, cvk_error* error);

/* The hash and the detection pass's layout (self-contact only); called by cvk_collide_create. */
cvk_result cvk_collide_create_detection(struct cvk_sim* sim, cvk_error* error);

/* Puts the device's substep counter at `step` and asks for a search at the next substep. */
cvk_result cvk_collide_set_step(struct cvk_sim* sim, uint64_t step, cvk_error* error);

/* After the positions were written from the host: the next substep searches again, and the
   candidates keep no side from before. */
cvk_result cvk_collide_positions_written(struct cvk_sim* sim, cvk_error* error);

/* Candidate searches run so far (since creation or the last snapshot loaded); 0 without
   self-contact. */
cvk_result cvk_collide_searches(struct cvk_sim* sim, uint64_t* out, cvk_error* error);

/* The contact state a snapshot carries so that stepping on from it gives the same bits: the
   frame state, where the last search saw each particle and the candidates (adaptive search;
   0 bytes otherwise). Save writes exactly cvk_collide_snapshot_size bytes; load takes them. */
uint64_t cvk_collide_snapshot_size(const struct cvk_sim* sim);
cvk_result cvk_collide_save_snapshot(struct cvk_sim* sim, unsigned char* data, cvk_error* error);
cvk_result cvk_collide_load_snapshot(struct cvk_sim* sim, const unsigned char* data,
                                     cvk_error* error);
/* Whether the contact state `data` can be loaded into this simulation (before anything is):
   edge pairs only where the scene has edge contact. */
cvk_result cvk_collide_check_snapshot(const struct cvk_sim* sim, const unsigned char* data,
                                      cvk_error* error);

/* uints in the work-list buffer of a simulation with self-contact: header, search and contact
   lists (what a snapshot carries), then the untangling step's arrays (shared/layout.h). */
static inline uint64_t cvk_collide_lists_size(uint64_t particles, uint64_t cloths)
{
    return CVK_LIST_HEADER + (2u + CVK_UNTANGLE_ARRAYS) * particles + 2u * cloths;
}

/* The patches (collide_patches.c) from the rest mesh: triangles (4 uint per triangle, internal
   corners) and the triangles around each particle (particle_count + 1 offsets, then ids). */
cvk_result cvk_collide_make_patches(cvk_collide* collide, const cvk_build* build,
                                    const uint32_t* triangles, const uint32_t* incident,
                                    cvk_error* error);

/* The patch activity a search computes on the device ("Patches" above), on the host in double
   from positions x (vec4 per particle, internal order): active[patch] = 1 or 0. slack > 0
   makes it more ready to call a patch active (a wider radius, a narrower flat angle, both by
   the factor 1 + slack), < 0 less: tests bracket the device's float rounding with it. */
void cvk_collide_patch_activity(const cvk_collide* collide, const cvk_build* build,
                                const float* x, double slack, uint8_t* active);

/* Whether particle p and triangle tri (internal indices) are of one cloth and near each other
   at rest (a corner within `exclusion` of p): such pairs are skipped by the contact. */
bool cvk_collide_rest_near(const cvk_collide* collide, uint32_t p, const uint32_t tri[3]);

/* The pose of collider `index` at simulated time t (s), as the device computes it. */
cvk_pose cvk_collide_pose(const cvk_collide* collide, uint32_t index, double t);

/* Signed distance (m, negative inside) from p to collider `index` posed at time t, and the
   outward unit normal there (may be NULL). The funnel's is unsigned. */
float cvk_collide_distance(const cvk_collide* collide, uint32_t index, double t, const float p[3],
                           float normal[3]);

#endif
