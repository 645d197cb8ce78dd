#version 450
#extension GL_GOOGLE_include_directive : require
// The air's force on each triangle at the start of the substep (lib/features/aero.h, cvk_aero_desc):
// the air's velocity relative to the triangle v (the wind minus the mean of its corners'
// velocities u / h), its unit normal n and area A give
//   F = A (d |v.n| v_n + f |v| v_t + l (v.n) |v_t| lift),  v_n = (v.n) n,  v_t = v - v_n,
// with d, l, f the cloth's coefficients times rho / 2 and lift the unit vector across v in the
// plane of v and n (NvCloth's: (v x n) x v); (v.n) |v_t| is cos(theta) sin(theta) |v|^2.
// A third of F is written per triangle; aero_gather sums it per particle, no atomics.
layout(local_size_x_id = 0) in;

#include "features/aero.glsl"

void main()
{
    if (pc.count == 0u)
        return;
    uint step = pc.counted != 0u ? frame.step - 1u : frame.step;
    vec3 wind = wind_at(float(step) * pc.dt);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += stride) {
        uvec4 t = texelFetch(triangles_t, int(i));
        vec3 a = texelFetch(x_t, int(t.x)).xyz, b = texelFetch(x_t, int(t.y)).xyz,
             c = texelFetch(x_t, int(t.z)).xyz;
        vec3 velocity = (texelFetch(u_t, int(t.x)).xyz + texelFetch(u_t, int(t.y)).xyz +
                         texelFetch(u_t, int(t.z)).xyz) / (3.0 * pc.dt);
        vec3 v = wind - velocity;
        vec3 normal = cross(b - a, c - a);
        float twice_area = length(normal);
        vec3 f = vec3(0.0);
        if (twice_area > 0.0) {
            vec3 n = normal / twice_area;
            float vn = dot(v, n);
            vec3 vt = v - vn * n;
            vec4 k = coefficients[t.w];
            f = k.x * abs(vn) * vn * n + k.z * length(v) * vt;
            vec3 across = cross(cross(v, n), v);
            float across_length = length(across);
            if (across_length > 0.0)
                f += k.y * vn * length(vt) * (across / across_length);
            f *= twice_area / 6.0; // a third of A F
        }
        forces[i] = vec4(f, 0.0);
    }
}
