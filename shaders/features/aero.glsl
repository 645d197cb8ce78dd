// The air passes' set (lib/features/aero.h) and the wind at a time: the mean wind turned about the up
// axis and scaled by the gusts, deterministic functions of simulated time (cvk_gusts_desc;
// lib/features/aero.c evaluates the same on the host).
#include "shared/layout.h"

layout(std430, set = 0, binding = CVK_AERO_BINDING_FRAME) buffer Frame { cvk_gpu_frame frame; };
layout(set = 0, binding = CVK_AERO_BINDING_POSITIONS) uniform samplerBuffer x_t;
layout(set = 0, binding = CVK_AERO_BINDING_U) uniform samplerBuffer u_t;
layout(set = 0, binding = CVK_AERO_BINDING_TRIANGLES) uniform usamplerBuffer triangles_t;
layout(std430, set = 0, binding = CVK_AERO_BINDING_COEFFICIENTS) readonly buffer Coefficients {
    vec4 coefficients[];
};
layout(std430, set = 0, binding = CVK_AERO_BINDING_FORCES) writeonly buffer Forces {
    vec4 forces[];
};
layout(set = 0, binding = CVK_AERO_BINDING_INCIDENCE) uniform usamplerBuffer incidence_t;
layout(std430, set = 0, binding = CVK_AERO_BINDING_EXTERNAL) writeonly buffer Air {
    vec4 air[]; // h^2 F / m per free particle
};
layout(set = 0, binding = CVK_AERO_BINDING_FORCES_READ) uniform samplerBuffer forces_t;
CVK_DECLARE_PUSH(CVK_AERO_PUSH_FIELDS)

vec3 wind_at(float t)
{
    float tau = pc.gusts.y * t;
    float speed = 1.0 + pc.gusts.x * 0.5 * (sin(tau) + sin(1.618 * tau + 1.0));
    float turn = pc.gusts.z * sin(0.73 * tau + 2.0);
    float c = cos(turn), s = sin(turn);
    vec3 w = pc.wind.xyz;
    return speed * vec3(c * w.x + s * w.z, w.y, c * w.z - s * w.x);
}
