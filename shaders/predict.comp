#version 450
#extension GL_GOOGLE_include_directive : require
// Verlet prediction in displacement form: the last substep's displacement u (in src) carries
// the velocity, so the predicted displacement is y = u (1 - damping) + h^2 g; it is also the
// first iterate. Pinned particles are never dispatched.
#include "pd_common.glsl"

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        vec3 yp = fetch(src, p) * pc.keep + pc.gravity_h2.xyz;
        y[p] = vec4(yp, texelFetch(x_read, int(p)).w);
        dst[p] = vec4(yp, 0.0);
    }
}
