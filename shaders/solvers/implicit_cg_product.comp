#version 450
#extension GL_GOOGLE_include_directive : require
// CG: q = S A p (S the contact filter) and the partial sums of p.q, one per invocation over a fixed stride (pc.partials
// invocations), so the sum is the same bits every run. Reads go through texel buffers. A p is formed as m p_p + sum H (p_p -
// p_c) and p.Ap as m |p|^2 + sum w (p_p - p_c).H (p_p - p_c) (w = 1/2 per end of a spring
// between free particles, 1 towards a pinned one, whose p_c is 0): the diagonal form
// (m + sum H) p_p - sum H p_c cancels terms of size h^2 k |p| down to m |p|, which at large
// steps (h^2 k / m = 1e8 on hanging.json at h = 1/30 s) is below float rounding and made
// p.Ap negative; the sum of squares cannot be.
#include "solvers/implicit_common.glsl"

void main()
{
    if (scalars.converged != 0u)
        return;
    uint j = gl_GlobalInvocationID.x;
    if (j >= pc.partials)
        return;
    float sum = 0.0;
    for (uint p = j; p < pc.count; p += pc.partials) {
        vec3 pp = texelFetch(pdir_read, int(p)).xyz;
        float m = v[p].w;
        vec3 qp = m * pp;
        float energy = m * dot(pp, pp);
        for (uint s = 0u; s < MAX_DEGREE; s++) {
            uint e = s * pc.stride + p;
            uint c = adjacency[e].x;
            float free_c = c < pc.stride ? 1.0 : 0.0;
            vec3 d = pp - free_c * texelFetch(pdir_read, int(c < pc.stride ? c : p)).xyz;
            vec3 hd = sym_mul(texelFetch(offdiag_read, int(2u * e)),
                              texelFetch(offdiag_read, int(2u * e + 1u)), d);
            qp += hd;
            energy += (1.0 - 0.5 * free_c) * dot(d, hd);
        }
        q[p] = vec4(filtered(p, qp), 0.0); // p.S A p = p.A p: p is filtered

        sum += energy;
    }
    partials[j] = sum;
}
