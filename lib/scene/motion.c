/* Keyframe interpolation: linear translation, slerp rotation, held outside the range, an
   optional loop. Kept in float arithmetic in the same order as shaders/scene/motion.glsl so the host
   and the device agree to rounding. */
#include <math.h>

#include "scene/motion.h"

cvk_pose cvk_pose_identity(void)
{
    return (cvk_pose){.rotation = {1.0f, 0.0f, 0.0f, 0.0f}, .translation = {0.0f, 0.0f, 0.0f}};
}

void cvk_quat_normalize(const float q[4], float out[4])
{
    float n = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(n > 0.0f) || !isfinite(n)) {
        out[0] = 1.0f;
        out[1] = out[2] = out[3] = 0.0f;
        return;
    }
    for (int i = 0; i < 4; i++)
        out[i] = q[i] / n;
}

void cvk_quat_rotate(const float q[4], const float p[3], float out[3])
{
    /* v' = v + 2 w (u × v) + 2 u × (u × v), u = (x, y, z) */
    const float* u = q + 1;
    float c[3] = {u[1] * p[2] - u[2] * p[1], u[2] * p[0] - u[0] * p[2], u[0] * p[1] - u[1] * p[0]};
    float cc[3] = {u[1] * c[2] - u[2] * c[1], u[2] * c[0] - u[0] * c[2], u[0] * c[1] - u[1] * c[0]};
    for (int i = 0; i < 3; i++)
        out[i] = p[i] + 2.0f * (q[0] * c[i] + cc[i]);
}

void cvk_pose_apply(const cvk_pose* pose, const float p[3], float out[3])
{
    float r[3];
    cvk_quat_rotate(pose->rotation, p, r);
    for (int i = 0; i < 3; i++)
        out[i] = r[i] + pose->translation[i];
}

void cvk_pose_apply_inverse(const cvk_pose* pose, const float p[3], float out[3])
{
    const float* q = pose->rotation;
    float conj[4] = {q[0], -q[1], -q[2], -q[3]};
    float d[3] = {p[0] - pose->translation[0], p[1] - pose->translation[1],
                  p[2] - pose->translation[2]};
    cvk_quat_rotate(conj, d, out);
}

static void slerp(const float a[4], const float b_in[4], float s, float out[4])
{
    float b[4] = {b_in[0], b_in[1], b_in[2], b_in[3]};
    float d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    if (d < 0.0f) { /* the shorter way round */
        d = -d;
        for (int i = 0; i < 4; i++)
            b[i] = -b[i];
    }
    float wa = 1.0f - s, wb = s;
    if (d < 0.9995f) {
        float angle = acosf(d);
        float sn = sinf(angle);
        wa = sinf((1.0f - s) * angle) / sn;
        wb = sinf(s * angle) / sn;
    }
    float q[4];
    for (int i = 0; i < 4; i++)
        q[i] = wa * a[i] + wb * b[i];
    cvk_quat_normalize(q, out);
}

/* The time inside the keyframes' range that `t` maps to. */
static double local_time(const cvk_motion* m, double t)
{
    double first = m->keyframes[0].time, last = m->keyframes[m->keyframe_count - 1].time;
    if (m->loop && last > first && t > last)
        return first + fmod(t - first, last - first);
    return t;
}

cvk_pose cvk_motion_pose(const cvk_motion* m, double t)
{
    cvk_pose pose = cvk_pose_identity();
    if (!m || m->keyframe_count == 0 || !m->keyframes)
        return pose;
    const cvk_keyframe* k = m->keyframes;
    uint32_t n = m->keyframe_count;
    t = local_time(m, t);
    uint32_t i = 0; /* the last keyframe at or before t */
    while (i + 1 < n && (double)k[i + 1].time <= t)
        i++;
    if (t <= (double)k[0].time || i + 1 == n) {
        const cvk_keyframe* held = t <= (double)k[0].time ? &k[0] : &k[n - 1];
        cvk_quat_normalize(held->rotation, pose.rotation);
        for (int c = 0; c < 3; c++)
            pose.translation[c] = held->translation[c];
        return pose;
    }
    float s = (float)((t - k[i].time) / ((double)k[i + 1].time - k[i].time));
    float qa[4], qb[4];
    cvk_quat_normalize(k[i].rotation, qa);
    cvk_quat_normalize(k[i + 1].rotation, qb);
    slerp(qa, qb, s, pose.rotation);
    for (int c = 0; c < 3; c++)
        pose.translation[c] = k[i].translation[c] + s * (k[i + 1].translation[c] - k[i].translation[c]);
    return pose;
}

void cvk_motion_pack(const cvk_motion* m, float* out)
{
    for (uint32_t j = 0; j < m->keyframe_count; j++) {
        const cvk_keyframe* kf = &m->keyframes[j];
        float* o = out + 8 * (size_t)j;
        float q[4];
        cvk_quat_normalize(kf->rotation, q);
        o[0] = kf->time;
        for (int c = 0; c < 3; c++) {
            o[1 + c] = kf->translation[c];
            o[4 + c] = q[1 + c];
        }
        o[7] = q[0];
    }
}
