/* The step plan: the operations of one substep, made once from the scene by the solver family
   and the features a scene uses, recorded by walking the list. An operation is a dispatch over
   a domain, an indirect dispatch whose size the device computed, a fill or a copy; each names
   its pipeline (from the one table in pipelines.h), its descriptor set, its push data and the
   barrier after it. Passes are named groups of operations (timed together, shown by --plan);
   any module may add its own. A scene without a feature records none of its passes. */
#ifndef CVK_PLAN_H
#define CVK_PLAN_H

#include "core/gpu.h"
#include "core/pipelines.h"

typedef enum cvk_op_kind {
    CVK_OP_DISPATCH,          /* vkCmdDispatch over `count` items of a domain */
    CVK_OP_DISPATCH_INDIRECT, /* vkCmdDispatchIndirect: group count at buffer + offset */
    CVK_OP_FILL,              /* vkCmdFillBuffer: size bytes at buffer + offset = value */
    CVK_OP_COPY,              /* vkCmdCopyBuffer: size bytes src + src_offset -> buffer + offset */
} cvk_op_kind;

/* What one invocation of a dispatch works on. */
typedef enum cvk_domain {
    CVK_DOMAIN_PARTICLES,
    CVK_DOMAIN_SPRINGS,
    CVK_DOMAIN_TRIANGLES,
    CVK_DOMAIN_CELLS, /* of a spatial grid */
} cvk_domain;

/* The barrier after an operation: what it wrote -> who reads next. */
typedef enum cvk_barrier {
    CVK_BARRIER_NONE,
    CVK_BARRIER_COMPUTE_TO_COMPUTE,
    CVK_BARRIER_COMPUTE_TO_INDIRECT, /* a dispatch wrote the size of an indirect one */
    CVK_BARRIER_COMPUTE_TO_TRANSFER,
    CVK_BARRIER_TRANSFER_TO_COMPUTE,
    CVK_BARRIER_TRANSFER_TO_TRANSFER,
} cvk_barrier;

#define CVK_PUSH_MAX_BYTES 128u /* Vulkan's guaranteed maxPushConstantsSize */

typedef struct cvk_op {
    cvk_op_kind kind;
    uint32_t pass;              /* index into cvk_plan.pass_names */
    cvk_barrier barrier;
    /* dispatches */
    cvk_pipeline_id pipeline;
    VkPipelineLayout layout;
    VkDescriptorSet set;
    VkDescriptorSet set1;       /* bound as set 1 when not VK_NULL_HANDLE (another module's
                                   set the pipeline also reads, e.g. the contact set) */
    VkDescriptorSet set2;       /* and as set 2 (the fused decision: the midpoints' hash) */
    cvk_domain domain;
    uint32_t first, count;      /* the items covered, for --plan */
    uint32_t groups;            /* direct dispatches; invocations stride over the rest */
    uint32_t push_bytes;
    _Alignas(16) unsigned char push[CVK_PUSH_MAX_BYTES];
    /* indirect dispatches, fills and copies */
    VkBuffer buffer, src;
    VkDeviceSize offset, src_offset, size;
    uint32_t value;
    uint32_t every;             /* 0 or 1: every substep; k: substeps 0, k, 2k, ... of a frame
                                   only (work whose result the substeps between reuse, e.g.
                                   contact candidates) */
    char note[192];             /* the family's details for --plan (iteration, buffers); as
                                   long as the notes the contact passes compose */
} cvk_op;

typedef struct cvk_plan {
    cvk_op* ops;                /* one substep */
    uint32_t op_count, op_capacity;
    const char** pass_names;    /* static strings, in order of first registration */
    uint32_t* pass_dispatches;  /* per substep, by pass */
    uint32_t pass_count, pass_capacity;
    uint32_t substeps;          /* times the op list repeats in a frame: the step parameters'
                                   substeps when the plan was made; only the plan's own
                                   recording and reports read it, everything else reads
                                   cvk_sim.params */
    uint32_t workgroup_size;
    uint32_t particle_workgroup_size; /* of the pipelines that stream over particles
                                         (cvk_pipeline_streams_particles); init: workgroup_size */
    uint32_t fused_workgroup_size; /* of the fused sweeps' one workgroup (lib/solvers/solve_pd.h);
                                      init: workgroup_size */
    bool fused; /* the solve's passes fused (cvk_family_api.fuse_refusal), and with them the
                   detection's hash builds (lib/contact/hash.h) */
    uint32_t max_groups;
    uint32_t particle_group_items; /* dispatches of the pipelines that stream over particles
                                      give each workgroup at least this many items (fewer
                                      workgroups than max_groups); 0 or 1: no floor */
    uint32_t walk_items;        /* items per invocation of the passes whose items loop over
                                   hash slots or colliders (detection, contact:
                                   cvk_plan_walk_groups); 0 or 1: one item an invocation */
    bool uses[CVK_PIPE_COUNT];
    bool has_transfer;          /* some op fills, copies or dispatches indirectly */
    bool host;                  /* the family steps on the host: no operations are recorded */
    bool out_of_memory;         /* an append failed; cvk_plan_check reports it */
    char solver_note[128];      /* appended to the solver line of --plan */
    char host_note[160];        /* --plan's per-frame line when `host` */
} cvk_plan;

void cvk_plan_init(cvk_plan* plan, uint32_t substeps, uint32_t workgroup_size, uint32_t max_groups);
void cvk_plan_destroy(cvk_plan* plan);
/* CVK_ERROR_OUT_OF_MEMORY if an append failed while the plan was made. */
cvk_result cvk_plan_check(const cvk_plan* plan, cvk_error* error);

/* The index of pass `name` (a static string), registered on first use. */
uint32_t cvk_plan_pass(cvk_plan* plan, const char* name);
/* The index of pass `name`, or UINT32_MAX. */
uint32_t cvk_plan_find_pass(const cvk_plan* plan, const char* name);

/* Appenders; each returns the op (barrier: what its kind usually needs), or NULL when there
   is nothing to do (count 0) or no memory (then cvk_plan_check fails). */
/* Workgroups of a direct dispatch over `count` items: one invocation per item, at most
   max_groups (invocations stride over the rest). */
uint32_t cvk_plan_groups(const cvk_plan* plan, uint32_t count);
/* The same for dispatches of `pipeline`, whose workgroups may be of the particle passes' size. */
uint32_t cvk_plan_groups_of(const cvk_plan* plan, cvk_pipeline_id pipeline, uint32_t count);
/* The items each workgroup of a walking pass takes (walk_items per invocation), and the
   workgroups of such a pass over `count` items, up to 65535 whatever max_groups says: lavapipe
   ends a shader's loops silently after 65535 iterations in all, counted over every loop an
   invocation runs, so these passes never stride over more than walk_items items an invocation
   (lib/sim/sim.c says why 8 on a CPU device is safe). */
uint32_t cvk_plan_walk_group_items(const cvk_plan* plan);
uint32_t cvk_plan_walk_groups(const cvk_plan* plan, uint32_t count);
cvk_op* cvk_plan_dispatch(cvk_plan* plan, uint32_t pass, cvk_pipeline_id pipeline,
                          VkPipelineLayout layout, VkDescriptorSet set, cvk_domain domain,
                          uint32_t first, uint32_t count, const void* push, uint32_t push_bytes);
cvk_op* cvk_plan_dispatch_indirect(cvk_plan* plan, uint32_t pass, cvk_pipeline_id pipeline,
                                   VkPipelineLayout layout, VkDescriptorSet set,
                                   cvk_domain domain, VkBuffer buffer, VkDeviceSize offset,
                                   const void* push, uint32_t push_bytes);
cvk_op* cvk_plan_fill(cvk_plan* plan, uint32_t pass, VkBuffer buffer, VkDeviceSize offset,
                      VkDeviceSize size, uint32_t value);
cvk_op* cvk_plan_copy(cvk_plan* plan, uint32_t pass, VkBuffer src, VkDeviceSize src_offset,
                      VkBuffer dst, VkDeviceSize dst_offset, VkDeviceSize size);

/* Whether op runs in substep `sub` of a frame (its `every`). */
bool cvk_op_runs(const cvk_op* op, uint32_t sub);
/* Operations one frame records: all of them, or those of `pass` (UINT32_MAX: every pass). */
uint32_t cvk_plan_frame_ops(const cvk_plan* plan, uint32_t pass);

/* Creates every pipeline the plan uses, with the layout of its first op; *created tells
   whether any is new (fresh pipelines then want cvk_plan_record_warm_up). */
cvk_result cvk_plan_require_pipelines(const cvk_plan* plan, cvk_context* context,
                                      cvk_pipelines* pipelines, const cvk_spec_inputs* inputs,
                                      bool* created, cvk_error* error);

/* Timestamps of a recorded frame: one at the start, one after each run of ops of one pass. */
typedef struct cvk_plan_queries {
    VkQueryPool pool;           /* VK_NULL_HANDLE: untimed */
    uint32_t count;
} cvk_plan_queries;

/* Queries per frame of `plan`, and fills pass_of[q] (q ≥ 1) with the pass query q closes when
   pass_of is not NULL. */
uint32_t cvk_plan_query_count(const cvk_plan* plan, uint32_t* pass_of);

/* One frame: an opening barrier (earlier compute and transfer writes), every substep's ops
   with their barriers, none after the last (the next frame opens with its own). */
void cvk_plan_record_frame(const cvk_plan* plan, const cvk_pipelines* pipelines,
                           const cvk_plan_queries* queries, VkCommandBuffer cmd);

/* Dispatches every fresh pipeline once with zero push data (no items): lavapipe compiles a
   pipeline on its first dispatch, so no timed frame pays for it. Clears the fresh flags. */
void cvk_plan_record_warm_up(const cvk_plan* plan, cvk_pipelines* pipelines, VkCommandBuffer cmd);

const char* cvk_op_kind_name(cvk_op_kind kind);
const char* cvk_domain_name(cvk_domain domain);
const char* cvk_barrier_name(cvk_barrier barrier);

#endif
