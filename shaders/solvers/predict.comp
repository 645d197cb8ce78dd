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
#define PREDICT_WIND_ID 3
#include "solvers/predict.glsl"

void main()
{
    if (gl_GlobalInvocationID.x == 0u && pc.count > 0u)
        watch.substep += 1u;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        dst[p] = predict_one(p, fetch(src, p));
    }
    flush_stretched();
}
