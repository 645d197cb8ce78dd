#version 450
#extension GL_GOOGLE_include_directive : require
// The solve's scalars from the partial sums, by one invocation, summed in a fixed order:
//   MODE 0 (CG start):  rho = rho0 = r.z; nothing to solve when it is 0
//   MODE 1 (CG alpha):  alpha = rho / p.Ap
//   MODE 2 (CG beta):   rho' = r.z, one iteration more, converged when rho' <= tol^2 rho0
//   MODE 3 (Jacobi):    delta = r.D^-1 r of the iterate the sweep read; one sweep more, the
//                       result is the iterate it wrote; converged when delta <= tol^2 delta0
// The residual is measured in the preconditioner's norm (Baraff & Witkin's stopping rule).
// A negative or non-finite r.z, p.Ap or delta means A or its diagonal blocks are not positive
// definite (what the clamp prevents): the solve stops there and counts a breakdown.
#include "solvers/implicit_common.glsl"

void stop()
{
    scalars.converged = 1u;
    scalars.reduce_groups = 0u;
    scalars.particle_groups = 0u;
    scalars.single_groups = 0u;
}

void main()
{
    if (gl_GlobalInvocationID.x != 0u || pc.partials == 0u || scalars.converged != 0u)
        return;
    float sum = 0.0;
    for (uint j = 0u; j < pc.partials; j++)
        sum += partials[j];
    if (sum < 0.0 || isnan(sum) || isinf(sum)) {
        stop();
        scalars.breakdown += 1u;
        return;
    }
#if MODE == 0
    scalars.rho = sum;
    scalars.rho0 = sum;
    if (sum == 0.0)
        stop();
#elif MODE == 1
    if (sum == 0.0) {
        stop();
        scalars.breakdown += 1u;
        return;
    }
    scalars.alpha = scalars.rho / sum;
#elif MODE == 2
    scalars.iterations += 1u;
    scalars.frame_iterations += 1u;
    scalars.total_iterations += 1u;
    scalars.beta = sum / scalars.rho;
    scalars.rho = sum;
    if (!(sum > pc.tol2 * scalars.rho0))
        stop();
#else
    if (scalars.iterations == 0u)
        scalars.rho0 = sum;
    scalars.iterations += 1u;
    scalars.frame_iterations += 1u;
    scalars.total_iterations += 1u;
    scalars.result = scalars.iterations & 1u;
    scalars.rho = sum;
    if (!(sum > pc.tol2 * scalars.rho0))
        stop();
#endif
}
