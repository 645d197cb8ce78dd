#version 450
#extension GL_GOOGLE_include_directive : require
// One Jacobi sweep from src into dst, with relaxation omega and, when pc.cheb != 1, the
// Chebyshev semi-iterative step of Wang 2015:
//   u^ = (b + sum_c k_c u_c) / diag,   z = u + omega (u^ - u),
//   u_next = cheb (z - u_older) + u_older, where u_older (the iterate before src) is in dst.
// FIRST computes b from src, the iterate at the start of the outer iteration. Built a second
// time with RESIDUAL: a checking first sweep also writes the squared residual at src.
#include "solvers/pd_common.glsl"

layout(constant_id = 2) const bool FIRST = false;

void main()
{
    vec3 shift = sweep_shift();
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        vec3 cur = fetch(src, p);
        vec3 acc;
        vec4 b;
        float ksum;
        if (FIRST) {
            b = local_step(p, cur, 0u, acc, ksum);
        } else {
            b = imageLoad(rhs_read, int(p));
            acc = neighbour_sum(src, p, cur, ksum);
        }
        vec3 u = cur + pc.omega * jacobi_move(b, cur, acc, ksum);
        if (pc.cheb != 1.0) {
            vec3 older = fetch(dst_read, p);
            u = pc.cheb * (u - older) + older;
        }
        dst[p] = vec4(bounded(p, u, shift), 0.0);
    }
}
