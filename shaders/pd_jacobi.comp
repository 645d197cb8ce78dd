#version 450
#extension GL_GOOGLE_include_directive : require
// One Jacobi sweep from src into dst, with relaxation omega and, when pc.cheb != 1, the
// Chebyshev semi-iterative step of Wang 2015:
//   u^ = (b + sum_c k_c u_c) / diag,   z = u + omega (u^ - u),
//   u_next = cheb (z - u_older) + u_older, where u_older (the iterate before src) is in dst.
// FIRST computes b from src, the iterate at the start of the outer iteration.
#include "pd_common.glsl"

layout(constant_id = 2) const bool FIRST = false;

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        vec3 cur = fetch(src, p);
        vec3 acc = vec3(0.0);
        vec4 b;
        if (FIRST) {
            vec3 xp = fetch(x_read, p);
            vec4 yp = texelFetch(y_read, int(p));
            vec3 sum = yp.w * yp.xyz;
            float diag = yp.w;
            for (uint q = 0; q < QUADS; q++) {
                uvec4 n = quad_neighbours(q, p);
                vec4 k = quad_k(q, p);
                vec4 kl = texelFetch(adjacency_kl, int(q * pc.stride + p));
                for (uint j = 0; j < 4u; j++) {
                    vec3 un = fetch(src, n[j]);
                    vec3 edge = xp - fetch(x_read, n[j]);
                    sum += spring_rhs(edge, edge + cur - un, k[j], kl[j]);
                    diag += k[j];
                    acc += k[j] * un;
                }
            }
            b = vec4(sum, 1.0 / diag);
            rhs[p] = b;
        } else {
            b = texelFetch(rhs_read, int(p));
            for (uint q = 0; q < QUADS; q++) {
                uvec4 n = quad_neighbours(q, p);
                vec4 k = quad_k(q, p);
                for (uint j = 0; j < 4u; j++)
                    acc += k[j] * fetch(src, n[j]);
            }
        }
        vec3 u = (b.xyz + acc) * b.w;
        u = cur + pc.omega * (u - cur);
        if (pc.cheb != 1.0) {
            vec3 older = fetch(dst_read, p);
            u = pc.cheb * (u - older) + older;
        }
        dst[p] = vec4(u, 0.0);
    }
}
