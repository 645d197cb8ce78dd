// Keyframed rigid motion on the device: the rules of lib/scene/motion.c (linear translation, slerp
// rotation, held outside the range, an optional loop), for colliders and attachments alike.
// The includer declares `vec4 keyframes[]` first: 2 per keyframe, (time, translation) and the
// rotation (x, y, z, w), as lib/scene/motion.c packs them (cvk_motion_pack).
#ifndef CVK_MOTION_GLSL
#define CVK_MOTION_GLSL

// ---- quaternions (x, y, z, w) ----------------------------------------------------------------

vec3 quat_rotate(vec4 q, vec3 v)
{
    vec3 c = cross(q.xyz, v);
    return v + 2.0 * (q.w * c + cross(q.xyz, c));
}

vec3 quat_rotate_inverse(vec4 q, vec3 v)
{
    return quat_rotate(vec4(-q.xyz, q.w), v);
}

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

// The pose at time t (s) of the motion whose n keyframes start at keyframe k0.
void motion_pose(uint k0, uint n, bool loop, float t, out vec4 rotation, out vec4 translation)
{
    rotation = vec4(0.0, 0.0, 0.0, 1.0);
    translation = vec4(0.0);
    if (n == 0u)
        return;
    float first = keyframes[2u * k0].x, last = keyframes[2u * (k0 + n - 1u)].x;
    if (loop && last > first && t > last)
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

#endif
