#version 450
#extension GL_GOOGLE_include_directive : require
// The convergence check of a projective-dynamics solve with a tolerance (lib/solvers/pd_passes.c):
//   MODE 0 (reduce): partial sum j (0 <= j < CVK_PD_PARTIALS) of the squared residuals the
//                    checking sweep wrote, over particles j, j + P, j + 2P, ... in order: the
//                    same bits whatever the workgroup size or count;
//   MODE 1 (decide): one invocation sums the partials in order, compares with tol2 times the
//                    sum at the substep's first iterate (the first check's) and, once
//                    converged, zeroes the indirect commands of every later pass of the
//                    substep (and arms the copy when the solution lies in u1); it counts the
//                    sweeps that ran into the substep's, the frame's and the total count;
//   MODE 2 (copy):   u0 = u1 for the free particles (set u1 -> u0), dispatched indirectly:
//                    zero groups unless the solve stopped with its solution in u1.
layout(local_size_x_id = 0) in;

#include "shared/layout.h"

#if MODE == 2
// The family's set (u1 -> u0), whose reads are image loads (pd_common.glsl).
layout(set = 0, binding = CVK_PD_BINDING_SRC, rgba32f) uniform readonly imageBuffer src;
layout(std430, set = 0, binding = CVK_PD_BINDING_DST) writeonly buffer Dst { vec4 dst[]; };
#else
// The check's own set: only the decision writes the indirect commands.
#define CONVERGE_SUMS CVK_PD_CONVERGE_BINDING_SUMS
#include "solvers/pd_converge.glsl"
layout(std430, set = 0, binding = CVK_PD_CONVERGE_BINDING_SCALARS) buffer Scalars {
    cvk_pd_scalars scalars;
};
#endif

CVK_DECLARE_PUSH(CVK_PD_CONVERGE_PUSH_FIELDS)

uint invocation_stride()
{
    return gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}

#if MODE == 1
void count_sweeps(uint used)
{
    scalars.iterations = used;
    scalars.frame_iterations += used;
    scalars.total_iterations += used;
}
#endif

void main()
{
#if MODE == 0
    for (uint j = gl_GlobalInvocationID.x; j < CVK_PD_PARTIALS; j += invocation_stride()) {
        float sum = 0.0;
        for (uint p = j; p < pc.stride; p += CVK_PD_PARTIALS)
            sum += residual[p];
        partials[j] = sum;
    }
#elif MODE == 1
    if (gl_GlobalInvocationID.x != 0u || pc.stride == 0u)
        return; // and the warm-up dispatch (zero push data) changes nothing
    float sum = 0.0;
    for (uint j = 0u; j < CVK_PD_PARTIALS; j++)
        sum += partials[j];
    if (pc.first_check != 0u)
        scalars.start = sum;
    float start = scalars.start;
    scalars.residual = start > 0.0 ? sqrt(sum / start) : 0.0;
    scalars.checks += 1u;
    // The first check never stops the solve (its outer iteration's tether and contact passes
    // run, which the measure does not see: a cloth falling freely onto a collider solves the
    // springs' system exactly at the prediction) unless the sum is not finite (the divergence
    // watch in finalize reports it).
    bool done = pc.first_check != 0u ? !(sum <= 3.0e38) : !(sum > pc.tol2 * start);
    uint groups = done ? 0u : 1u;
    scalars.converged = done ? 1u : 0u;
    scalars.sweep_groups = groups * pc.sweep_groups;
    scalars.sweep_y = 1u;
    scalars.sweep_z = 1u;
    scalars.contact_groups = groups * pc.contact_groups;
    scalars.contact_y = 1u;
    scalars.contact_z = 1u;
    scalars.reduce_groups = groups * pc.reduce_groups;
    scalars.reduce_y = 1u;
    scalars.reduce_z = 1u;
    scalars.single_groups = groups;
    scalars.single_y = 1u;
    scalars.single_z = 1u;
    scalars.copy_groups = done && pc.in_u1 != 0u ? pc.sweep_groups : 0u;
    scalars.copy_y = 1u;
    scalars.copy_z = 1u;
    if (done)
        count_sweeps(pc.swept);
    else if (pc.last_check != 0u)
        count_sweeps(pc.sweeps);
#else
    for (uint i = gl_GlobalInvocationID.x; i < pc.stride; i += invocation_stride())
        dst[i] = imageLoad(src, int(i));
#endif
}
