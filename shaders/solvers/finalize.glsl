// Finalize's work on particle p (finalize.comp; pd_fused.comp after the last outer iteration):
// x_{n+1} = x_n + u and the rest memory, or the divergence watch's record; with tether_first
// the tethers' projection before (finalize.comp's TETHERED). u is read where the solve left it
// (LOAD_DST: u0, finalize's src and dst alike). now, halted and stretched: the watch as the pass
// read it before any particle (finalize.comp). Include after pd_common.glsl and tether.glsl.
void finalize_one(uint p, uint now, bool halted, bool stretched, bool tether_first)
{
    vec3 xp = fetch(x_read, p);
    vec3 u;
    if (tether_first) {
        vec4 start = LOAD_DST(p);
        bool moved;
        u = tethered(p, xp, start.xyz, moved);
        if (moved)
            STORE_DST(p, vec4(u, start.w));
        if (halted)
            return;
    } else {
        u = LOAD_DST(p).xyz;
    }
    vec3 next = xp + u;
    bool nonfinite = any(isnan(next)) || any(isinf(next));
    bool runaway = stretched || (pc.max_u2 > 0.0 && dot(u, u) > pc.max_u2);
    if (nonfinite || runaway) {
        atomicMin(watch.diverged_at, now);
        if (!stretched)
            atomicMin(watch.particle, p);
        atomicOr(watch.reason, nonfinite ? CVK_WATCH_NONFINITE : CVK_WATCH_RUNAWAY);
    } else {
        x[p].xyz = next;
        if (pc.rest_rate > 0.0 && p < pc.stride) {
            vec3 r = rest_memory[p].xyz;
            rest_memory[p].xyz = r + pc.rest_rate * (u - LOAD_Y(p).xyz - r);
        }
    }
}
