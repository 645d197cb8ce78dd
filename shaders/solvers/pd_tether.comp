#version 450
#extension GL_GOOGLE_include_directive : require
// Tethers after the last sweep of every outer iteration, in place on the iterate that sweep
// wrote (dst), before contact: a free particle farther from one of its pins than that tether's
// length (lib/topology/build.h) is moved onto the sphere of that radius around the pin
// (solvers/tether.glsl). Where nothing comes between the last tethers and finalize,
// finalize.comp projects them itself (its TETHERED variant) and this pass is not recorded then.
#include "solvers/pd_common.glsl"
#include "solvers/tether.glsl"

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride())
        tether_one(pc.first + i);
}
