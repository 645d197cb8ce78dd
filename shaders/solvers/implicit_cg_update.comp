#version 450
#extension GL_GOOGLE_include_directive : require
// CG: dv += alpha p, r -= alpha q, z = S P^-1 r (block Jacobi, filtered) and the partial sums
// of r.z (r is filtered, so r.S P^-1 r = r.P^-1 r, the sum of squares precondition() forms).
// With START (the first pass of a substep) only z = P^-1 r, p = z and the sums.
#include "solvers/implicit_common.glsl"

#ifndef START
#define START 0
#endif

void main()
{
    if (scalars.converged != 0u)
        return;
    uint j = gl_GlobalInvocationID.x;
    if (j >= pc.partials)
        return;
    float alpha = scalars.alpha;
    float sum = 0.0;
    for (uint p = j; p < pc.count; p += pc.partials) {
        vec3 rp = r[p].xyz;
#if !START
        dv0[p].xyz += alpha * pdir[p].xyz;
        rp -= alpha * q[p].xyz;
        r[p] = vec4(rp, 0.0);
#endif
        float rz;
        vec3 zp = filtered(p, precondition(p, rp, rz));
        z[p] = vec4(zp, 0.0);
#if START
        pdir[p] = vec4(zp, 0.0);
#endif
        sum += rz;
    }
    partials[j] = sum;
}
