#version 450
#extension GL_GOOGLE_include_directive : require
// Tethers after the last sweep of every outer iteration, in place on the iterate that sweep
// wrote (dst), before contact: a free particle farther from one of its pins than that tether's
// length (lib/topology/build.h) is moved onto the sphere of that radius around the pin, pin by pin,
// nearest first. Each particle moves only itself and reads only pinned particles, which no
// pass of the solve writes: the result does not depend on the order of invocations.
#include "solvers/pd_common.glsl"

// The slots any particle uses (cvk_build.tether_slots; slots fill nearest first): a scene with
// two pins reads and projects two, not four.
layout(constant_id = 2) const uint SLOTS = 4;


// In displacement form, as the sweeps (pd_common.glsl): with e = x_p - x_a at the start of the
// substep and t = e + u_p - u_a, a tether too long sets u_p = u_a - e + t L / |t|. A particle
// no tether pulls keeps its iterate bit for bit. Every particle has four slots: the upload
// points a missing tether at the particle itself with an unreachable length, so the loop has
// no data-dependent trip count or array index (llvmpipe runs both sides of every branch and
// spills indexed arrays to memory).

// Projects u onto the ball of radius limit around base (u_a - e); counts a move.
void project(inout vec3 u, vec3 base, float limit, inout bool moved)
{
    vec3 t = u - base;
    float far = length(t);
    if (far > limit) {
        u = base + t * (limit / far);
        moved = true;
    }
}

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        uvec4 anchor = imageLoad(tether_anchor, int(p));
        vec4 limit = imageLoad(tether_length, int(p));
        vec3 xp = fetch(x_read, p);
        vec4 start = imageLoad(dst_read, int(p));
        vec3 u = start.xyz;
        vec3 b0 = fetch(dst_read, anchor.x) - (xp - fetch(x_read, anchor.x));
        vec3 b1 = SLOTS > 1u ? fetch(dst_read, anchor.y) - (xp - fetch(x_read, anchor.y)) : b0;
        vec3 b2 = SLOTS > 2u ? fetch(dst_read, anchor.z) - (xp - fetch(x_read, anchor.z)) : b0;
        vec3 b3 = SLOTS > 3u ? fetch(dst_read, anchor.w) - (xp - fetch(x_read, anchor.w)) : b0;
        bool moved = false;
        for (uint round = 0u; round < CVK_TETHER_ROUNDS; round++) {
            bool before = moved;
            moved = false;
            project(u, b0, limit.x, moved);
            if (SLOTS > 1u)
                project(u, b1, limit.y, moved);
            if (SLOTS > 2u)
                project(u, b2, limit.z, moved);
            if (SLOTS > 3u)
                project(u, b3, limit.w, moved);
            bool again = moved;
            moved = moved || before;
            if (!again)
                break;
        }
        if (moved) // w kept: the strain limit's mark (pd_strain.comp)
            dst[p] = vec4(u, start.w);
    }
}
