/* Tearing (cvk_tearing_desc): one pass per substep, once the substep's positions are final,
   over the springs of the cloths that tear (shaders/features/tear.comp). A spring whose relative
   stretch |xa − xb| / L − 1 passes its cloth's max_stretch is marked dead in the simulation's
   spring flags (which the mesh generation, the exports and the contact statistics already
   follow) and its k is set to 0 in both ends' entries of the solver family's adjacency: the
   PD sweeps (rbgs, jacobi, chebyshev), their diagonal and the divergence watch, which
   multiply what they read of a spring by k, then forget it, and the implicit and explicit families take k = 0 as
   no spring (no force, no damping). Breaking is permanent: nothing sets a flag back, not
   cvk_sim_write_state, not a solver switch (a new family gets the torn state through its
   set_torn, solver.h); a snapshot carries the flags and loading one rebuilds the adjacency
   from them. gs-cpu tears on the host (cvk_tear_host) on its own copy of the adjacency's k
   and uploads its flags after every step. A scene without tearing records nothing of this
   module. */
#ifndef CVK_TEAR_H
#define CVK_TEAR_H

#include "topology/build.h"
#include "core/gpu.h"
#include "plan/plan.h"

struct cvk_sim;

/* Which family's adjacency a descriptor set of the pass writes: one set each, so that a
   family being created beside another (a solver switch that may still fail) never rebinds the
   running one's. */
typedef enum cvk_tear_family {
    CVK_TEAR_FOR_PD,
    CVK_TEAR_FOR_IMPLICIT,
    CVK_TEAR_FOR_EXPLICIT,
    CVK_TEAR_FAMILIES
} cvk_tear_family;

typedef struct cvk_tear {
    uint32_t count;              /* springs that may tear; 0: the scene does not tear */
    uint32_t* spring;            /* host: each one's index into build.springs */
    float* limit2;               /* host: each one's squared breaking length, m² */
    uint32_t* entry;             /* host: 2 per spring, its entry in each end's adjacency
                                    (build.h layout; UINT32_MAX for a pinned end) */
    cvk_buffer table;            /* 2 uvec4 per such spring (shaders/shared/layout.h) */
    VkBufferView view_table;
    cvk_descriptors descriptors; /* a set per family, bound to its adjacency by cvk_tear_bind */
    bool bound[CVK_TEAR_FAMILIES];
} cvk_tear;

/* The springs of cloths with tearing, and where each sits in its ends' adjacency. */
cvk_result cvk_tear_create(struct cvk_sim* sim, const cvk_scene_desc* scene, cvk_error* error);
void cvk_tear_destroy(struct cvk_sim* sim);

/* Points `family`'s set of the pass at the buffer of its adjacency that holds the bits of k:
   projective dynamics' uvec4 quads of neighbours and k bits, or the one uvec4 buffer of the
   implicit and explicit families (the pass then reads their element indices). The family
   calls it when it creates them. */
void cvk_tear_bind(struct cvk_sim* sim, cvk_tear_family family, const cvk_buffer* adjacency);

/* The pass ("tear") with `family`'s set, once the substep's positions are final; none in a
   scene without tearing. */
cvk_result cvk_tear_add_passes(struct cvk_sim* sim, cvk_tear_family family, cvk_plan* plan,
                               cvk_error* error);

/* The spring flags as the device holds them (uint per spring of build.springs, 1 or 0);
   waits for the queue. */
cvk_result cvk_tear_read_flags(struct cvk_sim* sim, uint32_t* alive, cvk_error* error);

/* Whether adjacency entry `entry` (build.h's layout) holds a spring whose flag in `alive` is 0
   (alive NULL: nothing is torn). */
bool cvk_tear_entry_torn(const cvk_build* build, const uint32_t* alive, size_t entry);

/* The host reference of the pass (gs-cpu): every live spring that may tear and is longer than
   its breaking length in positions x (3 doubles per particle, internal order) gets alive 0
   and k 0 in adj_k (the build's adjacency layout). Returns the springs it tore. */
uint32_t cvk_tear_host(const struct cvk_sim* sim, const double* x, uint32_t* alive, float* adj_k);

/* adj_k (the build's layout) as the build has it, with k 0 for every spring whose flag in
   `alive` is 0. */
void cvk_tear_host_adjacency(const cvk_build* build, const uint32_t* alive, float* adj_k);

/* The spring flags as they are, in a new array (*out) the caller frees; *out NULL on failure. */
cvk_result cvk_tear_copy_flags(struct cvk_sim* sim, uint32_t** out, cvk_error* error);

/* Snapshot part: the spring flags when the scene tears (0 bytes otherwise), as the device
   holds them (gs-cpu uploads its flags after every step). Loading hands them to the family
   (set_torn, solver.h), which rebuilds its adjacency without the dead springs. */
uint64_t cvk_tear_snapshot_size(const struct cvk_sim* sim);
cvk_result cvk_tear_save_snapshot(struct cvk_sim* sim, void* data, cvk_error* error);
cvk_result cvk_tear_load_snapshot(struct cvk_sim* sim, const void* data, cvk_error* error);

#endif
