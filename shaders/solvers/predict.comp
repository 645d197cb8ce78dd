#version 450
#extension GL_GOOGLE_include_directive : require
// Verlet prediction in displacement form: the last substep's displacement u (in src) carries
// the velocity, so the predicted displacement is y = u (1 - damping) + h^2 g (+ h^2 F / m of
// the air, WIND), the inertial target of the solve. The first iterate is y plus the rest
// memory (the low-passed correction the solves made to their predictions, lib/solvers/solve_pd.h):
// at rest that is the equilibrium itself, which a truncated solve keeps; without it the solve
// would rest where its sweeps leave h^2 g partly uncorrected. Pinned particles are never
// dispatched.
//
// For the divergence watch, one invocation counts the substep (finalize reads the count after
// the barriers between them), and every particle's first spring (slot 0) is measured in the
// positions the substep starts from, which no pass writes while this one runs: one past
// RUNAWAY_STRETCH times its rest length raises the flag finalize acts on. One spring a particle
// is enough (a solve that blows up stretches every spring around where it starts) and costs
// four fetches where the first four would cost seven.
#include "solvers/pd_common.glsl"

// The air's h^2 F / m (lib/features/aero.h), when the scene has a "wind" block.
layout(constant_id = 3) const bool WIND = false;
layout(set = 0, binding = CVK_PD_BINDING_EXTERNAL, rgba32f) uniform readonly imageBuffer air;

const float RUNAWAY_STRETCH = 10.0; // lib/sim/sim.h, CVK_DIVERGED_STRETCH

bool overstretched(uint p, vec3 xp)
{
    uint c = quad_neighbours(0u, p).x;
    float k = quad_k(0u, p).x;
    float limit = RUNAWAY_STRETCH * imageLoad(adjacency_rest, int(p)).x;
    vec3 d = fetch(x_read, c) - xp;
    return k > 0.0 && dot(d, d) > limit * limit;
}

void main()
{
    if (gl_GlobalInvocationID.x == 0u && pc.count > 0u)
        watch.substep += 1u;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        vec3 yp = fetch(src, p) * pc.keep + pc.gravity_h2.xyz;
        if (WIND)
            yp += fetch(air, p);
        vec4 xp = imageLoad(x_read, int(p));
        y[p] = vec4(yp, xp.w);
        vec3 first = pc.rest_rate > 0.0 ? yp + rest_memory[p].xyz : yp;
        dst[p] = vec4(first, 0.0);
        if (pc.max_u2 > 0.0 && overstretched(p, xp.xyz)) {
            watch.stretched = 1u;
            atomicMin(watch.particle, p);
        }
    }
}
