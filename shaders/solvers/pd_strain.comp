#version 450
#extension GL_GOOGLE_include_directive : require
// Strain limiting (solver.strain_limit, pd_strain.glsl), one colour per dispatch after the last
// sweep of every outer iteration, before tethers and contact. The limit, 1 + strain_limit,
// comes in the push constants' omega, and the longest move in cheb (m; 0: any — the rounds
// after contact keep moves under half the thickness, so a particle contact left a thickness
// off a collider stays outside it: pd_passes.c).
#include "solvers/pd_common.glsl"
#include "solvers/pd_strain.glsl"

void main()
{
    vec3 shift = sweep_shift();
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride())
        strain_one(pc.first + i, pc.omega, pc.cheb, shift);
}
