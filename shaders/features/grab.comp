#version 450
#extension GL_GOOGLE_include_directive : require
// The grabbed particle (lib/features/grab.h): it moves in a straight line from where the frame found it
// to the host's target, evenly over the frame's substeps, so its displacement this substep is
// what is left of the way divided by the substeps left, u = (target - x_n) / (S - s). The
// solver must hold it there, infinitely heavy: the prediction's w, m/h^2, becomes pc.weight
// (2^100), next to which every spring's k is lost in rounding, so each sweep gives back u to
// within 1e-27 m; u also goes into both iterates (the first iterate, and, run again before
// finalize in a scene with tethers or contact, which do not weigh particles, the solved
// displacement). Its u stays the velocity (times h) the particle keeps when released. One
// invocation per particle held: the grabbed one and, with cvk_sim_grab_within, the members
// around it, each at its own offset from the target (a hand rather than a fingertip).
//
// The substep s within the frame comes from the divergence watch, which predict counted before
// this pass and which restarts only between frames (lib/sim/sim_watch.c).
#include "shared/layout.h"

layout(local_size_x = CVK_GRAB_MAX) in;

layout(std430, set = 0, binding = CVK_GRAB_BINDING_GRAB) readonly buffer Grab {
    cvk_gpu_grab grab;
    vec4 members[CVK_GRAB_MAX];
};
layout(std430, set = 0, binding = CVK_GRAB_BINDING_WATCH) readonly buffer Watch {
    cvk_gpu_watch watch;
};
layout(std430, set = 0, binding = CVK_GRAB_BINDING_POSITIONS) readonly buffer Positions {
    vec4 x[];
};
layout(std430, set = 0, binding = CVK_GRAB_BINDING_Y) writeonly buffer Inertial { vec4 y[]; };
layout(std430, set = 0, binding = CVK_GRAB_BINDING_U0) writeonly buffer U0 { vec4 u0[]; };
layout(std430, set = 0, binding = CVK_GRAB_BINDING_U1) writeonly buffer U1 { vec4 u1[]; };
CVK_DECLARE_PUSH(CVK_GRAB_PUSH_FIELDS)

void main()
{
    uint i = gl_LocalInvocationID.x;
    if (pc.substeps == 0u || grab.held == 0u || i >= grab.count)
        return; // the warm-up dispatch, nothing grabbed, or a member slot not in use
    vec4 m = members[i];
    uint p = floatBitsToUint(m.w);
    uint done = (watch.substep - 1u) % pc.substeps; // substeps of this frame before this one
    vec3 u = (grab.target.xyz + m.xyz - x[p].xyz) / float(pc.substeps - done);
    y[p] = vec4(u, pc.weight);
    u0[p] = vec4(u, 0.0);
    u1[p] = vec4(u, 0.0);
}
