#version 450
#extension GL_GOOGLE_include_directive : require
// The system of one substep, per free particle p, from its springs (slot by slot):
//   f_p   = m g + sum -k (l - L) n - kd ((v_p - v_c).n) n          n = (x_p - x_c) / l
//   K     = k (n n^T + max(0, 1 - L/l) (I - n n^T))   (-dF_p/dx_p; without the clamp the
//           factor 1 - L/l of a compressed spring is negative and A can lose definiteness)
//   H     = h kd n n^T + h^2 K;  A_pp = m I + sum H,  A_pc = -H (c free)
//   b_p   = h f_p - h^2 sum K (v_p - v_c)
// and the start of the solve: dv = 0, r = S b (CG; S the contact filter, implicit_common.glsl),
// the factors of A_pp (block Jacobi; of S A_pp S + m n n^T for a particle held on a collider).
#include "solvers/implicit_common.glsl"

void add_outer(inout vec4 s0, inout vec4 s1, vec3 n, float a, float t)
{
    // a n n^T + t (I - n n^T)
    float d = a - t;
    s0 += vec4(d * n.x * n.x + t, d * n.y * n.y + t, d * n.z * n.z + t, d * n.x * n.y);
    s1 += vec4(d * n.x * n.z, d * n.y * n.z, 0.0, 0.0);
}

void main()
{
    if (gl_GlobalInvocationID.x == 0u && pc.count > 0u) {
        scalars.converged = 0u;
        scalars.iterations = 0u;
        scalars.result = 0u;
        // This dispatch covers the particles as every particle pass does.
        scalars.reduce_groups = pc.partials / gl_WorkGroupSize.x;
        scalars.particle_groups = gl_NumWorkGroups.x;
        scalars.single_groups = 1u;
        scalars.reduce_y = scalars.reduce_z = 1u;
        scalars.particle_y = scalars.particle_z = 1u;
        scalars.single_y = scalars.single_z = 1u;
    }
    float h = pc.h;
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride()) {
        vec3 xp = x[p].xyz;
        vec4 vp4 = v[p];
        vec3 vp = vp4.xyz;
        float m = vp4.w;
        vec3 f = m * pc.gravity.xyz;
        vec3 kv = vec3(0.0);
        vec4 a0 = vec4(m, m, m, 0.0), a1 = vec4(0.0);
        for (uint s = 0u; s < MAX_DEGREE; s++) {
            uint e = s * pc.stride + p;
            uvec4 slot = adjacency[e];
            float k = uintBitsToFloat(slot.y), rest = uintBitsToFloat(slot.z);
            vec3 d = xp - x[slot.x].xyz;
            float l = length(d);
            vec3 n = l > 0.0 ? d / l : vec3(0.0);
            float t = l > 0.0 ? 1.0 - rest / l : 0.0;
            if (pc.clamp != 0u)
                t = max(t, 0.0);
            vec3 dvel = vp - v[slot.x].xyz;
            float kd = k > 0.0 ? pc.kd : 0.0; // a torn spring (k = 0, lib/features/tear.h) damps no more
            f -= (k * (l - rest) + kd * dot(dvel, n)) * n;
            vec4 k0 = vec4(0.0), k1 = vec4(0.0);
            add_outer(k0, k1, n, k, k * t);
            kv += sym_mul(k0, k1, dvel);
            vec4 h0 = h * h * k0, h1 = h * h * k1;
            add_outer(h0, h1, n, h * kd, 0.0);
            a0 += h0;
            a1 += h1;
            offdiag[2u * e] = h0;
            offdiag[2u * e + 1u] = h1;
        }
        diag[4u * p] = a0;
        diag[4u * p + 1u] = a1;
        vec3 rhs = h * f - h * h * kv;
        b[p] = vec4(rhs, 0.0);
        if (FILTER) {
            // A held particle's preconditioner: S A_pp S + m n n^T = A_pp - n a^T - a n^T +
            // (n.a + m) n n^T with a = A_pp n (unchanged when n = 0, a free particle).
            vec3 n = contact_filter[p].xyz;
            vec3 an = sym_mul(a0, a1, n);
            float c = dot(n, an) + m;
            a0 -= vec4(2.0 * n * an - c * n * n, n.x * an.y + an.x * n.y - c * n.x * n.y);
            a1 -= vec4(n.x * an.z + an.x * n.z - c * n.x * n.z,
                       n.y * an.z + an.y * n.z - c * n.y * n.z, 0.0, 0.0);
            rhs = filtered(p, rhs);
        }
        // L D L^T of the block, pivots clamped at m (see precondition()).
        float d0 = max(a0.x, m);
        float l10 = a0.w / d0, l20 = a1.x / d0;
        float d1 = max(a0.y - l10 * l10 * d0, m);
        float l21 = (a1.y - l20 * l10 * d0) / d1;
        float d2 = max(a0.z - l20 * l20 * d0 - l21 * l21 * d1, m);
        diag[4u * p + 2u] = vec4(l10, l20, l21, 0.0);
        diag[4u * p + 3u] = vec4(1.0 / d0, 1.0 / d1, 1.0 / d2, 0.0);
        r[p] = vec4(rhs, 0.0);
        dv0[p] = vec4(0.0);
    }
}
