#version 450
#extension GL_GOOGLE_include_directive : require
// a_p = (m g + sum over p's springs of f_spring + f_damping) / m, per free particle p, from the
// positions and velocities this set reads (the state, or the RK2 stage):
//   f_spring  = -k (l - L) n                 n = (x_p - x_c) / l
//   f_damping = -kd ((v_p - v_c).n) n        along the spring (Matyka)
//             = -kd (v_p - v_c)              artificial viscosity (Desbrun)
// A pinned neighbour (c >= stride) is read from the state, whatever the set. Padding slots
// point at p itself and add nothing. With mode 1, one invocation counts the substep for the
// divergence watch (explicit_update.comp reads it after the barrier).
#include "solvers/explicit_common.glsl"

void main()
{
    if (gl_GlobalInvocationID.x == 0u && pc.mode == 1u && pc.count > 0u)
        watch.substep += 1u;
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride()) {
        vec3 xp = x_in[p].xyz;
        vec3 vp = v_in[p].xyz;
        float m = v[p].w;
        vec3 f = m * pc.gravity.xyz;
        for (uint s = 0u; s < MAX_DEGREE; s++) {
            uvec4 slot = adjacency[s * pc.stride + p];
            uint c = slot.x;
            float k = uintBitsToFloat(slot.y), rest = uintBitsToFloat(slot.z);
            bool free_c = c < pc.stride;
            vec3 d = xp - (free_c ? x_in[c].xyz : x[c].xyz);
            vec3 dvel = vp - (free_c ? v_in[c].xyz : v[c].xyz);
            float l = length(d);
            vec3 n = l > 0.0 ? d / l : vec3(0.0);
            f -= k * (l - rest) * n;
            float kd = k > 0.0 ? pc.kd : 0.0; // a torn spring (k = 0, lib/features/tear.h) damps no more
            if (pc.viscosity != 0u)
                f -= kd * dvel;
            else
                f -= kd * dot(dvel, n) * n;
        }
        acc[p] = vec4(f / m, 0.0);
    }
}
