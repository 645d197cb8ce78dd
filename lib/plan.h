/* The step plan: the dispatches of one substep, derived once from the scene. Only the
   passes a scene needs appear; recording walks this list. */
#ifndef CVK_PLAN_H
#define CVK_PLAN_H

#include "build.h"

typedef enum cvk_pipeline_id {
    CVK_PIPE_PREDICT,
    CVK_PIPE_GS_FIRST,     /* Gauss-Seidel colour sweep that also computes b */
    CVK_PIPE_GS,
    CVK_PIPE_JACOBI_FIRST, /* Jacobi / Chebyshev sweep that also computes b */
    CVK_PIPE_JACOBI,
    CVK_PIPE_COUNT
} cvk_pipeline_id;

/* Descriptor sets differ only in which position buffer is src and which is dst. */
typedef enum cvk_set_id {
    CVK_SET_X0_TO_X1,
    CVK_SET_X1_TO_X0,
    CVK_SET_X0_TO_X0,
    CVK_SET_COUNT
} cvk_set_id;

typedef enum cvk_pass_id {
    CVK_PASS_PREDICT,
    CVK_PASS_SOLVE,
    CVK_PASS_COUNT
} cvk_pass_id;

/* Mirrors the push_constant block of shaders/pd_common.glsl. */
typedef struct cvk_push {
    uint32_t first;
    uint32_t count;
    uint32_t stride;
    uint32_t pad0;
    float inv_h2;
    float omega;
    float cheb;
    float keep;
    float gravity_h2[4];
} cvk_push;

typedef struct cvk_op {
    cvk_pipeline_id pipeline;
    cvk_set_id set;
    cvk_pass_id pass;
    uint32_t groups;             /* invocations stride over the rest */
    cvk_push push;
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
    double chebyshev_rho;        /* used by the chebyshev plan; 0 otherwise */
} cvk_plan;

/* max_groups caps the workgroups of one dispatch; the kernels loop over the rest. */
cvk_result cvk_plan_create(const cvk_scene_desc* scene, const cvk_build* build,
                           uint32_t workgroup_size, uint32_t max_groups, cvk_plan* out,
                           cvk_error* error);
void cvk_plan_destroy(cvk_plan* plan);

const char* cvk_pass_name(cvk_pass_id pass);

/* Chebyshev weight of sweep s (0-based, counted over a whole substep): 1 for s < delay
   (at least one plain sweep), then Wang's recurrence w = 2/(2 − ρ²), w ← 4/(4 − ρ² w). */
double cvk_chebyshev_weight(uint32_t sweep, uint32_t delay, double rho);

/* Spectral radius of the relaxed Jacobi iteration matrix I − omega D⁻¹A of the PD system
   (A = M/h² + spring Laplacian over free particles), by power iteration on its square. */
double cvk_estimate_jacobi_rho(const cvk_build* build, double inv_h2, double omega);

#endif
