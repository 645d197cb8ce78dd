#version 450
#extension GL_GOOGLE_include_directive : require
// One colour of a multi-colour Gauss-Seidel sweep with SOR, in place on dst:
//   u_p <- u_p + omega ((b_p + sum_c k_c u_c) / (m_p/h^2 + sum_c k_c) - u_p)
// No two particles of one colour share a spring, so a colour updates in parallel.
// FIRST (the first sweep of an outer iteration) also computes b_p from src, the iterate at
// the start of the outer iteration, and reads neighbours of colours not yet swept from src:
// those of lower colours (index < pc.first) were already written to dst in this sweep.
#include "pd_common.glsl"

layout(constant_id = 2) const bool FIRST = false;

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        vec3 acc = vec3(0.0);
        vec4 b;
        vec3 cur;
        if (FIRST) {
            cur = fetch(src, p);
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
                    acc += k[j] * (n[j] < pc.first ? fetch(dst_read, n[j]) : un);
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
                    acc += k[j] * fetch(dst_read, n[j]);
            }
            cur = pc.omega != 1.0 ? fetch(dst_read, p) : vec3(0.0);
        }
        vec3 u = (b.xyz + acc) * b.w;
        if (pc.omega != 1.0)
            u = cur + pc.omega * (u - cur);
        dst[p] = vec4(u, 0.0);
    }
}
