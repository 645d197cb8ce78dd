// The tethers' projection of one particle (pd_tether.comp; finalize.comp's TETHERED variant),
// in displacement form, as the sweeps (pd_common.glsl): with e = x_p - x_a at the start of the
// substep and t = e + u_p - u_a, a tether too long sets u_p = u_a - e + t L / |t|, pin by pin,
// nearest first. It reads the iterate of the pinned particles only (FETCH_DST: the texel view,
// or in the fused dispatch the storage buffer), which no pass of the solve writes, and the positions at the start of the substep: the result does not depend
// on the order of invocations. A particle no tether pulls keeps its iterate bit for bit.
// Every particle has four slots: the upload points a missing tether at the particle itself with
// an unreachable length, so the loop has no data-dependent trip count or array index (llvmpipe
// runs both sides of every branch and spills indexed arrays to memory).
#ifndef SOLVERS_TETHER_GLSL
#define SOLVERS_TETHER_GLSL

// The slots any particle uses (cvk_build.tether_slots; slots fill nearest first): a scene with
// two pins reads and projects two, not four.
layout(constant_id = 2) const uint SLOTS = 4;

// Projects u onto the ball of radius limit around base (u_a - e); counts a move.
void tether_project(inout vec3 u, vec3 base, float limit, inout bool moved)
{
    vec3 t = u - base;
    float far = length(t);
    if (far > limit) {
        u = base + t * (limit / far);
        moved = true;
    }
}

// p's iterate u (at position xp at the start of the substep) held by its tethers; `moved` says
// whether any tether moved it.
vec3 tethered(uint p, vec3 xp, vec3 u, out bool moved)
{
    uvec4 anchor = imageLoad(tether_anchor, int(p));
    vec4 limit = imageLoad(tether_length, int(p));
    vec3 b0 = FETCH_DST(anchor.x) - (xp - fetch(x_read, anchor.x));
    vec3 b1 = SLOTS > 1u ? FETCH_DST(anchor.y) - (xp - fetch(x_read, anchor.y)) : b0;
    vec3 b2 = SLOTS > 2u ? FETCH_DST(anchor.z) - (xp - fetch(x_read, anchor.z)) : b0;
    vec3 b3 = SLOTS > 3u ? FETCH_DST(anchor.w) - (xp - fetch(x_read, anchor.w)) : b0;
    moved = false;
    for (uint round = 0u; round < CVK_TETHER_ROUNDS; round++) {
        bool before = moved;
        moved = false;
        tether_project(u, b0, limit.x, moved);
        if (SLOTS > 1u)
            tether_project(u, b1, limit.y, moved);
        if (SLOTS > 2u)
            tether_project(u, b2, limit.z, moved);
        if (SLOTS > 3u)
            tether_project(u, b3, limit.w, moved);
        bool again = moved;
        moved = moved || before;
        if (!again)
            break;
    }
    return u;
}

// The tether pass's work on particle p (pd_tether.comp; pd_fused.comp after its sweeps): its
// iterate, where the pass before wrote it (LOAD_DST), held by its tethers; w kept (the strain
// limit's mark, pd_strain.glsl).
#ifdef LOAD_DST
void tether_one(uint p)
{
    vec4 start = LOAD_DST(p);
    bool moved;
    vec3 u = tethered(p, fetch(x_read, p), start.xyz, moved);
    if (moved)
        STORE_DST(p, vec4(u, start.w));
}
#endif

#endif
