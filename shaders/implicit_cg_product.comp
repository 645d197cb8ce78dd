#version 450
#extension GL_GOOGLE_include_directive : require
// CG: q = A p and the partial sums of p.q, one per invocation over a fixed stride (pc.partials
// invocations), so the sum is the same bits every run.
#include "implicit_common.glsl"

void main()
{
    if (scalars.converged != 0u)
        return;
    uint j = gl_GlobalInvocationID.x;
    if (j >= pc.partials)
        return;
    float sum = 0.0;
    for (uint p = j; p < pc.count; p += pc.partials) {
        vec3 pp = pdir[p].xyz;
        vec3 qp = sym_mul(diag[4u * p], diag[4u * p + 1u], pp);
        for (uint s = 0u; s < MAX_DEGREE; s++) {
            uint e = s * pc.stride + p;
            qp -= sym_mul(offdiag[2u * e], offdiag[2u * e + 1u], pdir[slot_neighbour(e, p)].xyz);
        }
        q[p] = vec4(qp, 0.0);
        sum += dot(pp, qp);
    }
    partials[j] = sum;
}
