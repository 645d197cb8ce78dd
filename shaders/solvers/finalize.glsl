// Finalize's work on particle p (finalize.comp; pd_fused.comp after the last outer iteration;
// finalize_u alone in pd_gauss_seidel.comp's last sweep where it finalizes):
// x_{n+1} = x_n + u and the rest memory, or the divergence watch's record; with tether_first
// the tethers' projection before (finalize.comp's TETHERED). u is read where the solve left it
// (LOAD_DST: u0, finalize's src and dst alike). halted and stretched: the watch as the pass
// read it before any particle (finalize.comp). Include after pd_common.glsl and, for
// finalize_one, tether.glsl.
//
// A particle that diverges is noted in the invocation's record, which finalize_watch writes to
// the watch with one set of atomics after the invocation's particles: the same watch (a minimum
// and a union, whatever the order). llvmpipe runs the atomics of a branch in the loop whether or
// not any invocation takes it (peer-hanging.json without tethers, one lavapipe thread: finalize
// 2.3-2.4 -> 1.8-1.9 ms a frame).
// The new position is stored as a whole vec4, w (the particle's own, read with xp) included: a
// store of .xyz alone cost more on llvmpipe (peer-hanging.json on one lavapipe thread, six
// alternated runs: finalize 2.63-2.75 -> 2.41-2.54 ms a frame, the same bits).
struct finalize_record {
    uint first;  // the lowest diverging particle's index (CVK_WATCH_NONE: none, or stretched)
    uint reason; // CVK_WATCH_NONFINITE | CVK_WATCH_RUNAWAY, 0 when none diverged
};

finalize_record finalize_none()
{
    return finalize_record(CVK_WATCH_NONE, 0u);
}

// x_{n+1} = xp4.xyz + u for particle p (its position and w in xp4), or the watch's record.
void finalize_u(uint p, vec4 xp4, vec3 u, bool stretched, inout finalize_record record)
{
    vec3 next = xp4.xyz + u;
    bool nonfinite = any(isnan(next)) || any(isinf(next));
    bool runaway = stretched || (pc.max_u2 > 0.0 && dot(u, u) > pc.max_u2);
    bool diverged = nonfinite || runaway;
    if (diverged) {
        if (!stretched)
            record.first = min(record.first, p);
        record.reason |= nonfinite ? CVK_WATCH_NONFINITE : CVK_WATCH_RUNAWAY;
    } else {
        x[p] = vec4(next, xp4.w);
        if (REST && pc.rest_rate > 0.0 && p < pc.stride) {
            vec3 r = rest_memory[p].xyz;
            rest_memory[p].xyz = r + pc.rest_rate * (u - LOAD_Y(p).xyz - r);
        }
    }
}

#ifdef SOLVERS_TETHER_GLSL
void finalize_one(uint p, bool halted, bool stretched, bool tether_first,
                  inout finalize_record record)
{
    vec4 xp4 = imageLoad(x_read, int(p));
    vec3 u;
    if (tether_first) {
        vec4 start = LOAD_DST(p);
        bool moved;
        u = tethered(p, xp4.xyz, start.xyz, moved);
        if (moved)
            STORE_DST(p, vec4(u, start.w));
        if (halted)
            return;
    } else {
        u = LOAD_DST(p).xyz;
    }
    finalize_u(p, xp4, u, stretched, record);
}
#endif

// The invocation's record into the watch at substep `now`: the first substep that diverged, the
// particle (where predict's stretch check did not name one) and the reasons.
void finalize_watch(finalize_record record, uint now)
{
    if (record.reason == 0u)
        return;
    atomicMin(watch.diverged_at, now);
    if (record.first != CVK_WATCH_NONE)
        atomicMin(watch.particle, record.first);
    atomicOr(watch.reason, record.reason);
}
