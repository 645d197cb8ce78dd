#version 450
#extension GL_GOOGLE_include_directive : require
// One Jacobi sweep from src into dst, with relaxation omega and, when pc.cheb != 1, the
// Chebyshev semi-iterative step of Wang 2015:
//   x^ = (b + sum_c k_c x_c) / diag,   z = x + omega (x^ - x),
//   x_next = cheb (z - x_older) + x_older, where x_older (the iterate before src) is in dst.
// FIRST computes b from src, the positions at the start of the outer iteration.
#include "pd_common.glsl"

layout(constant_id = 2) const bool FIRST = false;

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        vec3 cur = fetch_position(src, p);
        vec3 acc = vec3(0.0);
        vec4 b;
        if (FIRST) {
            vec4 yp = texelFetch(y_read, int(p));
            vec3 sum = yp.w * yp.xyz;
            float diag = yp.w;
            for (uint s = 0; s < MAX_DEGREE; s++) {
                uint e = s * pc.stride + p;
                uvec2 a = texelFetch(adjacency, int(e)).xy;
                float k = uintBitsToFloat(a.y);
                vec3 tn = fetch_position(src, a.x);
                sum += projected(cur, tn, texelFetch(adjacency_kl, int(e)).x);
                diag += k;
                acc += k * tn;
            }
            b = vec4(sum, 1.0 / diag);
            rhs[p] = b;
        } else {
            b = texelFetch(rhs_read, int(p));
            for (uint s = 0; s < MAX_DEGREE; s++) {
                uvec2 a = texelFetch(adjacency, int(s * pc.stride + p)).xy;
                acc += uintBitsToFloat(a.y) * fetch_position(src, a.x);
            }
        }
        vec3 x = (b.xyz + acc) * b.w;
        x = cur + pc.omega * (x - cur);
        if (pc.cheb != 1.0) {
            vec3 older = fetch_position(dst_read, p);
            x = pc.cheb * (x - older) + older;
        }
        dst[p].xyz = x;
    }
}
