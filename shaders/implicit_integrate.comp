#version 450
#extension GL_GOOGLE_include_directive : require
// v = (v + dv) (1 - damping), x += h v, from the iterate that holds the solution.
#include "implicit_common.glsl"

void main()
{
    bool second = scalars.result != 0u;
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride()) {
        vec3 dv = second ? dv1[p].xyz : dv0[p].xyz;
        vec3 vel = (v[p].xyz + dv) * pc.keep;
        v[p].xyz = vel;
        x[p].xyz += pc.h * vel;
    }
}
