#version 450
#extension GL_GOOGLE_include_directive : require
// Verlet prediction: y = x + (x - x_prev)(1 - damping) + h^2 g; x_prev <- x; the first
// iterate is y. Pinned particles are never dispatched.
#include "pd_common.glsl"

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        vec3 x = fetch_position(src, p);
        vec4 old = texelFetch(prev_read, int(p));
        vec3 yp = x + (x - old.xyz) * pc.keep + pc.gravity_h2.xyz;
        prev[p] = vec4(x, old.w);
        y[p] = vec4(yp, old.w);
        dst[p] = vec4(yp, 0.0);
    }
}
