/* Keyframed rigid motion on the host (the device evaluates the same rules in
   shaders/scene/motion.glsl): a pose is a unit quaternion and a translation, x' = t + q x q*. */
#ifndef CVK_MOTION_H
#define CVK_MOTION_H

#include "clothvk.h"

typedef struct cvk_pose {
    float rotation[4];    /* [w, x, y, z], unit */
    float translation[3]; /* m */
} cvk_pose;

/* The identity pose. */
cvk_pose cvk_pose_identity(void);

/* The pose of `motion` at time `t` (s): see cvk_motion in clothvk.h. */
cvk_pose cvk_motion_pose(const cvk_motion* motion, double t);

/* q · p (p a point or direction), and the pose applied to a point / its inverse. */
void cvk_quat_rotate(const float q[4], const float p[3], float out[3]);
void cvk_pose_apply(const cvk_pose* pose, const float p[3], float out[3]);
void cvk_pose_apply_inverse(const cvk_pose* pose, const float p[3], float out[3]);

/* The keyframes as the device reads them (shaders/scene/motion.glsl): 8 floats per keyframe, time,
   translation, then the normalised rotation as (x, y, z, w). */
void cvk_motion_pack(const cvk_motion* motion, float* out);

/* Normalised copy of q; [1, 0, 0, 0] when q is zero. */
void cvk_quat_normalize(const float q[4], float out[4]);

#endif
