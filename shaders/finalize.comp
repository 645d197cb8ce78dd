#version 450
#extension GL_GOOGLE_include_directive : require
// x_{n+1} = x_n + u: the one place absolute positions are rounded. u stays in src as the
// velocity (times h) for the next prediction.
#include "pd_common.glsl"

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        x[p].xyz = fetch(x_read, p) + fetch(src, p);
    }
}
