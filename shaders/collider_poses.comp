#version 450
#extension GL_GOOGLE_include_directive : require
// The colliders' poses at the start and end of this substep, from their keyframes and the
// frame state, then the frame state advanced by one substep: the recorded work keeps its own
// time, so a command buffer submitted again and again moves the colliders on. One workgroup.
// Keyframes follow lib/motion.c: linear translation, slerp rotation, held outside the range,
// an optional loop.
layout(local_size_x = 64) in;

#include "shared/layout.h"
#define CONTACT_SET 0
#include "collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

vec4 slerp(vec4 a, vec4 b, float s)
{
    float d = dot(a, b);
    if (d < 0.0) {
        d = -d;
        b = -b;
    }
    float wa = 1.0 - s, wb = s;
    if (d < 0.9995) {
        float angle = acos(d);
        float sn = sin(angle);
        wa = sin((1.0 - s) * angle) / sn;
        wb = sin(s * angle) / sn;
    }
    return normalize(wa * a + wb * b);
}

void pose_at(cvk_gpu_collider c, float t, out vec4 rotation, out vec4 translation)
{
    rotation = vec4(0.0, 0.0, 0.0, 1.0);
    translation = vec4(0.0);
    uint n = c.keyframe_count, k0 = c.keyframe_first;
    if (n == 0u)
        return;
    float first = keyframes[2u * k0].x, last = keyframes[2u * (k0 + n - 1u)].x;
    if (c.loop != 0u && last > first && t > last)
        t = first + mod(t - first, last - first);
    uint i = 0u;
    while (i + 1u < n && keyframes[2u * (k0 + i + 1u)].x <= t)
        i++;
    if (t <= first || i + 1u == n) {
        uint k = t <= first ? k0 : k0 + n - 1u;
        rotation = normalize(keyframes[2u * k + 1u]);
        translation = vec4(keyframes[2u * k].yzw, 0.0);
        return;
    }
    vec4 ka = keyframes[2u * (k0 + i)], kb = keyframes[2u * (k0 + i + 1u)];
    float s = (t - ka.x) / (kb.x - ka.x);
    rotation = slerp(normalize(keyframes[2u * (k0 + i) + 1u]),
                     normalize(keyframes[2u * (k0 + i + 1u) + 1u]), s);
    translation = vec4(ka.yzw + s * (kb.yzw - ka.yzw), 0.0);
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
