#version 450
#extension GL_GOOGLE_include_directive : require
// One colour of a multi-colour Gauss-Seidel sweep with SOR, in place on dst:
//   u_p <- u_p + omega ((b_p + sum_c k_c u_c) / (m_p/h^2 + sum_c k_c) - u_p)
// No two particles of one colour share a spring, so a colour updates in parallel.
// FIRST (the first sweep of an outer iteration) also computes b_p from src, the iterate at
// the start of the outer iteration, and reads neighbours of colours not yet swept from src:
// those of lower colours (index < pc.first) were already written to dst in this sweep.
// Built a second time with RESIDUAL: the first sweep of an outer iteration that a convergence
// check follows, which also writes each particle's squared residual at src (pd_common.glsl).
#include "pd_common.glsl"

layout(constant_id = 2) const bool FIRST = false;

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        vec3 acc;
        vec4 b;
        vec3 cur;
        float ksum;
        if (FIRST) {
            cur = fetch(src, p);
            b = local_step(p, cur, pc.first, acc, ksum);
        } else {
            b = texelFetch(rhs_read, int(p));
            cur = fetch(dst_read, p);
            acc = neighbour_sum(dst_read, p, cur, ksum);
        }
        dst[p] = vec4(cur + pc.omega * jacobi_move(b, cur, acc, ksum), 0.0);
    }
}
