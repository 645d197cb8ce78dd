#version 450
#extension GL_GOOGLE_include_directive : require
// The colliders' poses at the start and end of this substep, from their keyframes and the
// frame state, then the frame state advanced by one substep: the recorded work keeps its own
// time, so a command buffer submitted again and again moves the colliders on. One workgroup.
// Keyframes follow lib/scene/motion.c (shaders/scene/motion.glsl).
layout(local_size_x = 64) in;

#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

void pose_at(cvk_gpu_collider c, float t, out vec4 rotation, out vec4 translation)
{
    motion_pose(c.keyframe_first, c.keyframe_count, c.loop != 0u, t, rotation, translation);
}

void main()
{
    if (pc.count == 0u)
        return; // the warm-up dispatch: time must not move
    uint step = frame.step;
    float t0 = float(step) * contact.dt, t1 = float(step + 1u) * contact.dt;
    for (uint k = gl_LocalInvocationID.x; k < pc.count; k += gl_WorkGroupSize.x) {
        cvk_gpu_collider c = shapes[k];
        cvk_gpu_pose pose;
        pose_at(c, t0, pose.rotation0, pose.translation0);
        pose_at(c, t1, pose.rotation1, pose.translation1);
        poses[k] = pose;
    }
    memoryBarrierBuffer();
    barrier();
    if (gl_LocalInvocationID.x == 0u)
        frame.step = step + 1u;
}
