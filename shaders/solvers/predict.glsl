// The prediction of one particle (predict.comp; pd_fused.comp before its first outer
// iteration): y = u (1 - damping) + h^2 g (+ h^2 F / m of the air, WIND) from `last`, the
// last substep's displacement of p, and the first iterate y + rest memory, which it returns;
// a first spring stretched past its bound is noted for flush_stretched (pd_common.glsl).
// Include after pd_common.glsl, with PREDICT_WIND_ID the constant id of WIND.
#ifndef SOLVERS_PREDICT_GLSL
#define SOLVERS_PREDICT_GLSL

// The air's h^2 F / m (lib/features/aero.h), when the scene has a "wind" block.
layout(constant_id = PREDICT_WIND_ID) const bool WIND = false;
layout(set = 0, binding = CVK_PD_BINDING_EXTERNAL, rgba32f) uniform readonly imageBuffer air;

vec4 predict_one(uint p, vec3 last)
{
    vec3 yp = predicted(last);
    if (WIND)
        yp += fetch(air, p);
    vec4 xp = imageLoad(x_read, int(p));
    y[p] = vec4(yp, xp.w);
    vec3 first = REST && pc.rest_rate > 0.0 ? yp + rest_memory[p].xyz : yp;
    watch_first_spring(p, quad_k(0u, p).x, imageLoad(adjacency_rest, int(p)).x,
                       xp.xyz - fetch(x_read, quad_neighbours(0u, p).x));
    return vec4(first, 0.0);
}

#endif
