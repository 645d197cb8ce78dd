#version 450
#extension GL_GOOGLE_include_directive : require
// Contact constraints of the implicit solve, per free particle at the start of the substep
// (the colliders posed at t and t + h by contact/collider_poses.comp). A particle is held on the
// collider whose surface it would reach first: its gap g = distance - thickness, its velocity
// relative to the surface along the outward normal n is u (its motion at its present velocity
// over the substep in the collider's moving frame, as collide_colliders measures it), and it
// is held when g + h u, where it would end the substep, is below HOLD_SLACK thicknesses. Held:
//   - inside (g < 0), x moves out along n onto the surface (Baraff & Witkin's position
//     alteration, seed 000 section 4.5): no velocity is made from the correction;
//   - its velocity along n becomes the one that ends the substep on the surface, u = -g / h
//     (the surface's own for a particle on it);
//   - its filter is n (S = I - n n^T): the solve leaves that component alone, and w is 1 + the
//     collider's index (its friction and motion, implicit_integrate.comp).
// Every other particle's filter is 0. Release and friction: implicit_integrate.comp.
#define IMPLICIT_CONTACT 1
#include "solvers/implicit_common.glsl"

// A held particle rests within rounding of g = 0, so g + h u wanders either side of it; this
// much slack keeps it held until the release gives it a real velocity away.
const float HOLD_SLACK = 0.01;

void main()
{
    float h = pc.h;
    float thickness = contact_u.thickness;
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride()) {
        vec3 xp = x[p].xyz;
        vec3 vp = v[p].xyz;
        float best = HOLD_SLACK * thickness, gap = 0.0, speed = 0.0;
        vec3 normal = vec3(0.0);
        uint which = 0u; // 1 + the collider it is held on
        uvec2 range = collider_range(p);
        for (uint k = range.x; k < range.y; k++) {
            cvk_gpu_collider c = collider_shape(k);
            cvk_gpu_pose pose = collider_pose(k);
            // Where the particle is in the collider's frame now and, at its present
            // velocity, at the end of the substep (as collide_colliders measures motion).
            vec3 l0, l1;
            local_path(pose, xp, h * vp, l0, l1);
            float g = shape_distance(c, l0) - thickness;
            // Distances are 1-Lipschitz: a particle farther than its move cannot end within
            // the slack, and its normal (six field samples on a mesh) is not needed.
            if (g - length(l1 - l0) >= best)
                continue;
            vec3 n = shape_normal(c, l0);
            float ends = g + dot(n, l1 - l0);
            if (ends < best) {
                best = ends;
                gap = g;
                speed = dot(n, l1 - l0) / h;
                normal = quat_rotate(pose.rotation0, n);
                which = k + 1u;
            }
        }
        bool held = dot(normal, normal) > 0.0;
        if (held) {
            xp -= min(gap, 0.0) * normal;
            vp += (-max(gap, 0.0) / h - speed) * normal;
            x[p].xyz = xp;
            v[p].xyz = vp;
        }
        contact_filter[p] = vec4(normal, float(which));
    }
}
