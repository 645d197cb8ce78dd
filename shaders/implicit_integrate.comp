#version 450
#extension GL_GOOGLE_include_directive : require
// v = (v + dv) (1 - damping), x += h v, from the iterate that holds the solution (damping
// only across the normal of a particle held on a collider).
//
// With colliders, the release of a held particle (one-sided contact): the unfiltered system's
// residual along its normal, n.(b - A dv), is the push the surface would have to pull with to
// keep it there. Where it is positive the particle leaves now, with the velocity along n one
// block-Jacobi step gives it, n.(b - A dv) / n.A_pp n; the next substep's contact pass then
// sees it moving away and leaves it free.
#include "implicit_common.glsl"

vec3 solution(bool second, uint p)
{
    return second ? dv1[p].xyz : dv0[p].xyz;
}

// (b - A dv)_p = b_p - m dv_p - sum H (dv_p - dv_c), dv_c = 0 for a pinned neighbour.
vec3 residual(bool second, uint p, vec3 dv, float m)
{
    vec3 res = b[p].xyz - m * dv;
    for (uint s = 0u; s < MAX_DEGREE; s++) {
        uint e = s * pc.stride + p;
        vec3 d = dv - slot_free(e) * solution(second, slot_neighbour(e, p));
        res -= sym_mul(offdiag[2u * e], offdiag[2u * e + 1u], d);
    }
    return res;
}

void main()
{
    bool second = scalars.result != 0u;
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride()) {
        vec3 dv = solution(second, p);
        vec3 vel = v[p].xyz + dv;
        if (FILTER) {
            vec3 n = contact_filter[p].xyz;
            float pull = dot(n, residual(second, p, dv, v[p].w));
            float stiffness = dot(n, sym_mul(diag[4u * p], diag[4u * p + 1u], n));
            if (pull > 0.0) {
                vel += (pull / stiffness) * n;
                contact_filter[p].w = 2.0; // released (for tests: cvk_implicit_read_held)
            }
            // Damping leaves the prescribed component along n alone (it ends on the surface).
            vel = pc.keep * vel + (1.0 - pc.keep) * dot(vel, n) * n;
        } else {
            vel *= pc.keep;
        }
        v[p].xyz = vel;
        x[p].xyz += pc.h * vel;
    }
}
