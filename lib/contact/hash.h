/* The uniform-grid spatial hash on the device (Green 2010, seed 002 §3.4): every point is put in
   the cell of side cell_size that holds it, cells are hashed into a table of table_size slots (a
   power of two), and a counting sort groups the points by slot — count, prefix sum, scatter —
   which writes each point with its position into its slot's range. Within a slot the points
   come in the order the scatter's atomics took them, which depends on thread timing: every
   reader must give the same result whatever that order (the detections keep sets of pairs,
   nearest first with ties by index, and minimum distances; lib/contact/collide.h). Queries
   visit the 27 cells around a point and check each candidate's own cell (two cells may share
   a slot).

   The module owns its buffers, one descriptor set (shaders/contact/hash_common.glsl declares it, at
   the set index the including shader chooses) and its pipelines' layout; it reads the points
   from a buffer it is given (vec4 per point, xyz used), so a solver can hash its predicted
   positions and a test random ones.

   A build can be skipped on the device: recorded with on_device (cvk_hash_add_passes), its
   passes are dispatched indirectly, with no workgroups while the parameters' `build` is 0 (1
   from creation). A module that decides on the device when the points have moved enough to
   need a new build writes it (lib/contact/collide.c's adaptive search); queries then read the last
   build. A build recorded without on_device always runs. */
#ifndef CVK_HASH_H
#define CVK_HASH_H

#include "plan/plan.h"
#include "shared/layout.h"

typedef struct cvk_hash_desc {
    uint32_t capacity;          /* points at most, ≥ 1 */
    float cell_size;            /* m, > 0 */
    const cvk_buffer* points;   /* vec4 per point, made with VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT
                                   (read through a storage texel view); must outlive the hash */
    bool cell_on_device;        /* the parameters' cell size is written on the device before
                                   each build (cell_size is only the first); builds keep it */
    const cvk_buffer* salts;    /* uint per point mixed into its slot (a texel view reads it),
                                   or NULL: 0 for every point. Points of different salts in one
                                   cell mostly take different slots, so a query that wants one
                                   salt's points walks past few others (hash_walk_begin's
                                   salt); must outlive the hash */
} cvk_hash_desc;

typedef struct cvk_hash {
    uint32_t capacity;
    uint32_t table_size;        /* slots: a power of two ≥ 2 · capacity */
    float cell_size;
    bool cell_on_device;
    cvk_buffer params;          /* cvk_hash_params (shaders/shared/layout.h) */
    cvk_buffer keys;            /* uint per point: its slot */
    cvk_buffer starts;          /* uint per slot, + 1: slot s holds entries [starts[s], starts[s + 1]) */
    cvk_buffer scratch;         /* counts and cursors per slot, partial sums of the scan */
    cvk_buffer entries;         /* uvec4 per point grouped by slot, in the order the scatter's
                                   atomics took them: xyz bits, index (what queries read) */
    VkBufferView points_view;   /* storage texel views the shaders read (R32G32B32A32_SFLOAT, */
    VkBufferView starts_view;   /* R32_UINT, R32G32B32A32_UINT) with imageLoad: on lavapipe an */
    VkBufferView entries_view;  /* inline vectorised gather (docs/performance.md) */
    cvk_buffer zero_salt;       /* one zero uint: the salts without desc.salts */
    VkBufferView salts_view;    /* R32_UINT */
    VkBufferView scratch_view;  /* R32_UINT: the counts and chunk sums as the scan reads them */
    VkDescriptorSetLayout set_layout;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    VkPipelineLayout layout;    /* set 0 = the hash's set; push constants cvk_hash_push */
} cvk_hash;

/* Creates the buffers and the set. On failure nothing is left to destroy. */
cvk_result cvk_hash_create(cvk_context* context, const cvk_hash_desc* desc, cvk_hash* out,
                           cvk_error* error);
void cvk_hash_destroy(cvk_context* context, cvk_hash* hash);

/* Appends the build over points [0, count) (count ≤ capacity) to `plan` as pass "hash":
   clear, count, scan, scatter. After its last op (barrier compute -> compute, and
   -> indirect with on_device) starts and
   entries are ready for queries. Dispatches only (compute barriers); with count 0 only the clear
   is recorded, which leaves every start 0 and the parameters' count 0.
   With `on_device` the build is for a module that opens and closes it on the device (the
   parameters' `build`, written before these ops by a dispatch followed by a compute barrier):
   a first dispatch of one invocation writes the passes' indirect commands, with the workgroups
   they would have directly while the build is open and none while it is closed, and the passes
   are dispatched through them, so a closed build costs no workgroups (on lavapipe with its
   default threads a dispatch of workgroups that return at once still costs their hand-off to
   the worker threads). */
cvk_result cvk_hash_add_passes(const cvk_hash* hash, cvk_plan* plan, uint32_t count,
                               bool on_device, cvk_error* error);

/* The push data of a build over points [0, count) (count ≤ capacity, else
   CVK_ERROR_INVALID_ARGUMENT): what cvk_hash_add_passes pushes, for a shader that runs the
   whole build itself in one workgroup with what queries the hash after it (hash_common.glsl's
   HASH_BUILD and HASH_FUSED: contact_faces_fused.comp, contact_edges_fused.comp), the same
   hash, bit for bit, where the plan fuses. */
cvk_result cvk_hash_build_push(const cvk_hash* hash, uint32_t count, cvk_hash_push* push,
                               cvk_error* error);

/* The host reference, for tests: the slot of a point of salt 0, as the device computes it. */
uint32_t cvk_hash_slot(const cvk_hash* hash, const float p[3]);

#endif
