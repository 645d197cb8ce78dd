#version 450
#extension GL_GOOGLE_include_directive : require
// CG: p = z + beta p.
#include "solvers/implicit_common.glsl"

void main()
{
    if (scalars.converged != 0u)
        return;
    float beta = scalars.beta;
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride())
        pdir[p] = vec4(z[p].xyz + beta * pdir[p].xyz, 0.0);
}
