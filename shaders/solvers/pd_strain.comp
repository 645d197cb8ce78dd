#version 450
#extension GL_GOOGLE_include_directive : require
// Strain limiting (solver.strain_limit), one colour per dispatch after the last sweep of every
// outer iteration, in place on the iterate that sweep wrote (dst), before tethers and contact:
// a particle whose springs are longer than (1 + limit) times their rest lengths moves to
// shorten them — by the mean of the moves that would bring each such spring back to the limit
// (to its neighbour's current place: a particle of another colour, which this dispatch does not
// write, so the result does not depend on the order of invocations), then within its bound.
// The limit, 1 + strain_limit, comes in the push constants' omega, and the longest move in
// cheb (m; 0: any — the rounds after contact keep moves under half the thickness, so a
// particle contact left a thickness off a collider stays outside it: pd_passes.c). A particle
// no spring of which is past the limit keeps its iterate bit for bit.
#include "solvers/pd_common.glsl"

void main()
{
    float limit = pc.omega;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        vec4 cur = imageLoad(dst_read, int(p));
        vec3 xp = fetch(x_read, p) + cur.xyz;
        vec3 move = vec3(0.0);
        float over = 0.0;
        for (uint q = 0; q < QUADS; q++) {
            uvec4 n = quad_neighbours(q, p);
            vec4 k = quad_k(q, p);
            vec4 rest = imageLoad(adjacency_rest, int(q * pc.stride + p));
            for (uint j = 0; j < 4u; j++) {
                vec3 t = xp - (fetch(x_read, n[j]) + fetch(dst_read, n[j]));
                float len2 = dot(t, t), most = limit * rest[j];
                // Padding slots (k 0, p itself) and springs within the limit take no part.
                bool past = k[j] > 0.0 && len2 > most * most;
                float len = sqrt(len2);
                move += past ? t * ((most - len) / len) : vec3(0.0);
                over += past ? 1.0 : 0.0;
            }
        }
        // w 1: the next outer iteration's first sweep does not over-relax a particle moved
        // here (as after contact, pd_gauss_seidel.comp): it would throw it past the solve.
        move /= max(over, 1.0);
        float len = length(move);
        if (pc.cheb > 0.0 && len > pc.cheb)
            move *= pc.cheb / len;
        if (over > 0.0)
            dst[p] = vec4(bounded(p, cur.xyz + move), 1.0);
    }
}
