#version 450
#extension GL_GOOGLE_include_directive : require
// One integrator rule per mode (shared/layout.h, CVK_EXPLICIT_*), per free particle, from the
// accelerations the force pass wrote. Adams-Bashforth of order 4:
//   y_n+1 = y_n + h/24 (55 F_n - 59 F_n-1 + 37 F_n-2 - 9 F_n-3),  F = (v, a)
// with forward Euler while fewer than three past values are held (seed 001 §2.3.4); each
// particle keeps its own history, so the rule needs no step count from the host.
//
// Every mode but the RK2 stage ends the substep and is watched as finalize.comp watches PD: a
// new state that is not finite, or a step longer than max_u2 allows, is not written; the first
// substep where that happens is recorded, and from then on no particle moves.
#include "solvers/explicit_common.glsl"

// (x', v') of particle p by the rule of pc.mode.
void advance(uint p, vec3 xp, vec3 vp, vec3 ap, out vec3 xn, out vec3 vn)
{
    float h = pc.h;
    if (pc.mode == CVK_EXPLICIT_RK2_COMBINE) {
        vec3 xsp = xs[p].xyz, vsp = vs[p].xyz;
        xn = 0.5 * (xp + xsp + h * vsp);
        vn = 0.5 * (vp + vsp + h * ap);
    } else if (pc.mode == CVK_EXPLICIT_VERLET) {
        vn = vp + h * ap;
        xn = xp + h * vn;
    } else if (pc.mode == CVK_EXPLICIT_AB4 && hist[CVK_EXPLICIT_HISTORY * p].w >= 3.0) {
        uint b = CVK_EXPLICIT_HISTORY * p;
        const float c = 1.0 / 24.0;
        vn = vp + h * c * (55.0 * ap - 59.0 * hist[b].xyz + 37.0 * hist[b + 1u].xyz -
                           9.0 * hist[b + 2u].xyz);
        xn = xp + h * c * (55.0 * vp - 59.0 * hist[b + 3u].xyz + 37.0 * hist[b + 4u].xyz -
                           9.0 * hist[b + 5u].xyz);
    } else {
        vn = vp + h * ap;
        xn = xp + h * vp;
    }
    vn *= pc.keep;
}

void push_history(uint p, vec3 vp, vec3 ap)
{
    uint b = CVK_EXPLICIT_HISTORY * p;
    float held = min(hist[b].w + 1.0, 3.0);
    hist[b + 2u] = hist[b + 1u];
    hist[b + 1u] = vec4(hist[b].xyz, 0.0);
    hist[b] = vec4(ap, held);
    hist[b + 5u] = hist[b + 4u];
    hist[b + 4u] = hist[b + 3u];
    hist[b + 3u] = vec4(vp, 0.0);
}

void main()
{
    if (pc.mode == CVK_EXPLICIT_RK2_STAGE) {
        for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride()) {
            xs[p] = vec4(x[p].xyz + pc.h * v[p].xyz, 0.0);
            vs[p] = vec4(v[p].xyz + pc.h * acc[p].xyz, 0.0);
        }
        return;
    }
    uint now = watch.substep;
    if (watch.diverged_at < now)
        return;
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride()) {
        vec3 xp = x[p].xyz, vp = v[p].xyz, ap = acc[p].xyz;
        vec3 xn, vn;
        advance(p, xp, vp, ap, xn, vn);
        vec3 u = xn - xp;
        bool nonfinite = any(isnan(xn)) || any(isinf(xn)) || any(isnan(vn)) || any(isinf(vn));
        bool runaway = pc.max_u2 > 0.0 && dot(u, u) > pc.max_u2;
        if (nonfinite || runaway) {
            atomicMin(watch.diverged_at, now);
            atomicMin(watch.particle, p);
            atomicOr(watch.reason, nonfinite ? CVK_WATCH_NONFINITE : CVK_WATCH_RUNAWAY);
            continue;
        }
        if (pc.mode == CVK_EXPLICIT_AB4)
            push_history(p, vp, ap);
        x[p].xyz = xn;
        v[p].xyz = vn;
    }
}
