#version 450
#extension GL_GOOGLE_include_directive : require
// One block-Jacobi sweep (seed 000 section 4.4.2) from dv0 into dv1 (or, with ODD, dv1 into
// dv0): dv'_p = A_pp^-1 (b_p + sum H dv_c), and the partial sums of r.A_pp^-1 r for the
// iterate read, whose residual is r = A_pp (dv' - dv). A particle held on a collider solves
// its block in the tangent plane: dv'_p = S (S A_pp S + m n n^T)^-1 S (b_p + sum H dv_c).
#include "solvers/implicit_common.glsl"

#ifndef ODD
#define ODD 0
#endif

vec3 src_at(uint p)
{
#if ODD
    return dv1[p].xyz;
#else
    return dv0[p].xyz;
#endif
}

void main()
{
    if (scalars.converged != 0u)
        return;
    uint j = gl_GlobalInvocationID.x;
    if (j >= pc.partials)
        return;
    float sum = 0.0;
    for (uint p = j; p < pc.count; p += pc.partials) {
        vec3 acc = b[p].xyz;
        for (uint s = 0u; s < MAX_DEGREE; s++) {
            uint e = s * pc.stride + p;
            acc += slot_free(e) *
                   sym_mul(offdiag[2u * e], offdiag[2u * e + 1u], src_at(slot_neighbour(e, p)));
        }
        float unused;
        vec3 next = filtered(p, precondition(p, filtered(p, acc), unused));
        // The residual of the iterate read is r = A_pp (next - src); r.A_pp^-1 r is then
        // change.A_pp change, formed as |D^1/2 L^T change|^2 with the clamped factors.
        vec3 change = next - src_at(p);
        vec3 f = diag[4u * p + 2u].xyz, g = diag[4u * p + 3u].xyz;
        vec3 u = vec3(change.x + f.x * change.y + f.y * change.z, change.y + f.z * change.z,
                      change.z);
        sum += dot(u * u, 1.0 / g);
#if ODD
        dv0[p] = vec4(next, 0.0);
#else
        dv1[p] = vec4(next, 0.0);
#endif
    }
    partials[j] = sum;
}
