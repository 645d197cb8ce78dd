// A collider's pose as the simulation's recorded work left it (pose 1: the end of the last
// substep), read from the contact module's poses buffer; the draw's instance index is the
// collider's index (lib/render/render_colliders.c), so a frame submitted again draws colliders where
// the simulation moved them, with no host write.
#include "shared/layout.h"

layout(std430, set = 0, binding = 10) readonly buffer Poses {
    cvk_gpu_pose poses[];
};

// q · p for a unit quaternion (x, y, z, w).
vec3 rotate(vec4 q, vec3 p)
{
    return p + 2.0 * cross(q.xyz, cross(q.xyz, p) + q.w * p);
}

vec3 posed_point(vec3 p)
{
    return poses[gl_InstanceIndex].translation1.xyz + rotate(poses[gl_InstanceIndex].rotation1, p);
}

vec3 posed_direction(vec3 d)
{
    return rotate(poses[gl_InstanceIndex].rotation1, d);
}
