/* The simulation object; private so later passes (mesh generation, rendering) can reach its
   buffers. */
#ifndef CVK_SIM_H
#define CVK_SIM_H

#include "build.h"
#include "gpu.h"
#include "plan.h"
#include "reference.h"

struct cvk_sim {
    cvk_context* context;
    cvk_build build;
    cvk_plan plan;
    char name[64];
    float dt;
    cvk_solver_desc solver;
    cvk_scene_desc params;  /* the scene's step, gravity and damping (no cloths): plan input */
    int timing_request;     /* cvk_sim_desc.timing */
    double rho_estimate;    /* Chebyshev's spectral radius estimated for rho_omega; < 0: none */
    float rho_omega;
    cvk_ref_params ref;
    bool host_solver; /* gs-cpu: the state lives in the host arrays below */

    /* Device state: positions (w: m/h²), two displacement iterates (u[0] holds the last
       substep's displacement: the velocity times h), the predicted displacement, the
       right-hand side. Adjacency: uvec2 (neighbour, bits of k) and float k·L per slot. */
    cvk_buffer positions, u[2], y, rhs;
    cvk_buffer adjacency, adjacency_kl;
    cvk_buffer spring_alive; /* uint per spring of build.springs: 1, 0 once torn; the mesh reads it */
    cvk_buffer staging; /* host-visible, 2 vec4 per particle: uploads and readback */
    VkBufferView view_positions, view_u[2], view_y, view_rhs, view_adjacency, view_adjacency_kl;
    VkBufferView view_spring_alive;

    cvk_descriptors descriptors;     /* the PD set layout and its CVK_SET_COUNT sets */
    VkPipelineLayout pipeline_layout; /* descriptors.pipeline_layout */
    cvk_pipelines pipelines;

    bool timing;
    VkQueryPool queries;
    uint32_t query_count;   /* per frame: one at the start, one per pass run */
    cvk_pass_id* query_pass; /* query q > 0 closes this pass */

    cvk_submitter submitter;
    VkCommandBuffer frame_cmd;    /* one frame, recorded once, submitted again and again */
    VkCommandBuffer readback_cmd; /* x[0] -> staging, recorded once */
    VkCommandBuffer transfer_cmd; /* re-recorded for each upload */
    VkCommandBuffer* batch;       /* frame_cmd repeated, for one submission of many frames */
    uint32_t batch_capacity;

    uint64_t frames;
    double host_pass_ms[CVK_PASS_COUNT]; /* gs-cpu: host time of the last frame */
    bool host_timed;

    double* hx;    /* gs-cpu state, 3 doubles per particle, internal order */
    double* hprev;
    double* hy;
    double* hrhs;  /* 4 doubles per particle */
    float* scratch;   /* positions, 3 floats per particle, internal order */
    float* scratch_u; /* last displacements x_n − x_{n−1}, same layout */
    float* scratch_v; /* velocities, same layout */
};

/* Reads the state back: positions into sim->scratch, last displacements into
   sim->scratch_u (internal order, 3 floats per particle). */
cvk_result cvk_sim_read_internal(cvk_sim* sim, cvk_error* error);

#endif
