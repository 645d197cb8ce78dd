#version 450
#extension GL_GOOGLE_include_directive : require
// x_{n+1} = x_n + u: the one place absolute positions are rounded. u stays in src as the
// velocity (times h) for the next prediction. The rest memory of a free particle (index below
// pc.stride) follows the correction this solve made to its prediction:
// r += rest_rate (u - y - r) (lib/solvers/solve_pd.h).
//
// The divergence watch costs a few arithmetic operations per particle here, with no pass of its
// own: a new position that is not finite, or a step longer than pc.max_u2 allows (a speed no
// cloth reaches, lib/sim/sim.h), is not written, nor is any once predict found a spring stretched
// past its bound; the first substep where that happens is recorded, and from then on no
// particle moves.
//
// TETHERED (spec id 6): the tethers' projection first, where it would be the pass just before
// this one (no contact or grab after it, no attached particle, which this pass would move while
// others read it): u is read from dst_read, which in this pass's set is src, tethered
// (solvers/tether.glsl) and written back in place when a tether moved it, as pd_tether.comp
// would have: one pass over the particles fewer a substep, the same bits.
#include "solvers/pd_common.glsl"
#include "solvers/tether.glsl"
#include "solvers/finalize.glsl"

layout(constant_id = 6) const bool TETHERED = false;

void main()
{
    uint now = watch.substep;
    bool halted = watch.diverged_at < now;
    if (halted && !TETHERED)
        return;
    bool stretched = watch.stretched != 0u;
    finalize_record record = finalize_none();
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride())
        finalize_one(pc.first + i, halted, stretched, TETHERED, record);
    finalize_watch(record, now);
}
