#version 450
#extension GL_GOOGLE_include_directive : require
// Attachments (lib/features/attach.h): every attached particle moves over this substep as its keyframed
// motion says, to target = pose(t + dt) · start. The time comes from the frame state; without
// a collider pass (which counts the substep first) the first attach pass of the substep counts
// it. One workgroup.
//
// Projective dynamics: the displacement u = target − x_n, written into both of the solver's
// displacement iterates (pinned particles are never swept, so the solve reads it as given) and
// added to the position by finalize.
//
// Implicit Euler (-DIMPLICIT=1, U0 and U1 both the velocities): before the assembly the
// velocity pass prescribes v = (target − x_n) / dt. An attached particle is pinned for the
// solver (S = 0: never an unknown), and the assembly reads its velocity in the springs to it,
// so b_p already carries the constrained Δv through the off-diagonal block (Baraff & Witkin's
// z; seed 000 §4.5). After the integration the place pass puts x at the target itself.
layout(local_size_x = 64) in;

#include "shared/layout.h"

layout(std430, set = 0, binding = CVK_ATTACH_BINDING_FRAME) buffer Frame { cvk_gpu_frame frame; };
layout(std430, set = 0, binding = CVK_ATTACH_BINDING_KEYFRAMES) readonly buffer Keyframes {
    vec4 keyframes[];
};
layout(std430, set = 0, binding = CVK_ATTACH_BINDING_ATTACHMENTS) readonly buffer Attachments {
    cvk_gpu_attachment attachments[];
};
layout(std430, set = 0, binding = CVK_ATTACH_BINDING_ATTACHED) readonly buffer Attached {
    cvk_gpu_attached attached[];
};
#ifdef IMPLICIT
layout(std430, set = 0, binding = CVK_ATTACH_BINDING_POSITIONS) buffer Positions { vec4 x[]; };
layout(std430, set = 0, binding = CVK_ATTACH_BINDING_U0) buffer Velocities { vec4 v[]; };
#else
layout(std430, set = 0, binding = CVK_ATTACH_BINDING_POSITIONS) readonly buffer Positions {
    vec4 x[];
};
layout(std430, set = 0, binding = CVK_ATTACH_BINDING_U0) writeonly buffer U0 { vec4 u0[]; };
layout(std430, set = 0, binding = CVK_ATTACH_BINDING_U1) writeonly buffer U1 { vec4 u1[]; };
#endif
CVK_DECLARE_PUSH(CVK_ATTACH_PUSH_FIELDS)

#include "scene/motion.glsl"

void main()
{
    if (pc.count == 0u)
        return; // the warm-up dispatch: time must not move
    uint step = pc.advance != 0u ? frame.step : frame.step - 1u; // this substep's index
    float t1 = float(step + 1u) * pc.dt;
    for (uint i = gl_LocalInvocationID.x; i < pc.count; i += gl_WorkGroupSize.x) {
        cvk_gpu_attached a = attached[i];
        cvk_gpu_attachment m = attachments[a.attachment];
        vec4 rotation, translation;
        motion_pose(m.keyframe_first, m.keyframe_count, m.loop != 0u, t1, rotation, translation);
        vec3 target = quat_rotate(rotation, a.start.xyz) + translation.xyz;
#ifdef IMPLICIT
        if (pc.place != 0u)
            x[a.particle].xyz = target;
        else
            v[a.particle].xyz = (target - x[a.particle].xyz) / pc.dt;
#else
        vec4 u = vec4(target - x[a.particle].xyz, 0.0);
        u0[a.particle] = u;
        u1[a.particle] = u;
#endif
    }
    if (pc.advance != 0u) {
        memoryBarrierBuffer();
        barrier();
        if (gl_LocalInvocationID.x == 0u)
            frame.step = step + 1u;
    }
}
