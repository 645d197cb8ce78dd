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
//
// Friction of a particle that stays held (Coulomb, after the solve, as an impulse on the
// particle alone): the surface pushed with the impulse -n.(b - A dv) over the substep, so the
// tangential velocity relative to the surface is stopped while it is within mu_s times that
// push over m, and shortened by mu_k times it otherwise (the collider's coefficients).
//
// SELF (spec id 3, self-contact): x is not moved here. The substep's displacement h v, kept
// within the particle's bound (lib/contact/collide.h; where that would put it inside a solid
// collider, the collider wins and the next substep detects, as in pd's contact pass), goes to
// r and z (free after the solve), where implicit_self.comp pushes the listed particles off
// the cloth features and moves x; v is the kept displacement over h where the bound cut it.
#define IMPLICIT_CONTACT 1 // the colliders' friction and poses (set 1)
#include "solvers/implicit_common.glsl"

layout(constant_id = 3) const bool SELF = false;

// The tangential velocity relative to collider k's surface at x, less Coulomb friction for a
// normal impulse `push` on mass m.
vec3 friction(uint k, vec3 xp, vec3 vel, vec3 n, float push, float m)
{
    cvk_gpu_collider c = collider_shape(k);
    cvk_gpu_pose pose = collider_pose(k);
    vec3 l = quat_rotate_inverse(pose.rotation0, xp - pose.translation0.xyz);
    vec3 surface = (quat_rotate(pose.rotation1, l) + pose.translation1.xyz - xp) / pc.h;
    vec3 rel = vel - surface;
    vec3 tangential = rel - dot(rel, n) * n;
    float t = length(tangential);
    if (t * m <= c.static_friction * push)
        return vel - tangential;
    return vel - tangential * min(1.0, c.friction * push / (m * t));
}

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
    vec3 shift = SELF ? bound_shift() : vec3(0.0);
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride()) {
        vec3 dv = solution(second, p);
        vec3 vel = v[p].xyz + dv;
        if (FILTER) {
            vec4 f = contact_filter[p];
            vec3 n = f.xyz;
            float m = v[p].w;
            float pull = dot(n, residual(second, p, dv, m));
            float stiffness = dot(n, sym_mul(diag[4u * p], diag[4u * p + 1u], n));
            if (pull > 0.0) {
                vel += (pull / stiffness) * n;
                contact_filter[p].w = -f.w; // released (for tests: cvk_implicit_read_held)
            } else if (f.w > 0.0) {
                vel = friction(uint(f.w) - 1u, x[p].xyz, vel, n, -pull, m);
            }
            // Damping leaves the prescribed component along n alone (it ends on the surface).
            vel = pc.keep * vel + (1.0 - pc.keep) * dot(vel, n) * n;
        } else {
            vel *= pc.keep;
        }
        if (SELF) {
            vec3 x0 = x[p].xyz, u = pc.h * vel;
            vec3 kept = within_bound(p, x0 + u, shift);
            if (!FILTER || nearest_solid(p, kept, false) >= 0.0) {
                vel = any(notEqual(kept, x0 + u)) ? (kept - x0) / pc.h : vel;
                u = kept - x0;
            }
            r[p] = vec4(u, 0.0);
            z[p] = vec4(u, 0.0);
            v[p].xyz = vel;
            continue;
        }
        v[p].xyz = vel;
        x[p].xyz += pc.h * vel;
    }
}
