#version 450
#extension GL_GOOGLE_include_directive : require
// The decision to detect, over the particles (lib/contact/collide.h), in two phases around
// contact_decide.comp's:
// 0: each particle's displacement since detection extrapolated over the substep by its last
//    substep's (e = x_n - seen + (x_n - x_before)) and its last substep's (v), bounded per axis
//    (atomic min and max on order-preserving bits: the result does not depend on thread
//    timing);
// 1: whether some particle's e is farther than `redetect` of its bound from the shift the
//    substep would have without detecting (e's centre; contact_decide.comp phase 0), or that
//    shift would centre its bound too near a collider; x_n kept as the next substep's
//    x_before.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#define CONTACT_TYPES_ID 1
#include "contact/collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

const float BIG = 3.0e38;

// Whether x is nearer than `gap` to some collider (or inside it) at the start or the end of the
// substep: a particle whose bound (of radius b) is centred nearer than the thickness - b could
// be pushed out of its bound by the collider (pd_contact.glsl), so the substep detects instead
// (and takes no shift).
bool inside_collider(vec3 x, float gap)
{
    bool inside = false;
    for (uint k = 0u; k < contact_u.collider_count; k++) {
        if (HAS_TYPE(CVK_COLLIDER_FUNNEL_ID) && shapes_u[k].type == CVK_COLLIDER_FUNNEL_ID)
            continue; // a funnel's push wins anyway (pd_contact.glsl)
        cvk_gpu_pose pose = poses_u[k];
        vec3 l0 = quat_rotate_inverse(pose.rotation0, x - pose.translation0.xyz);
        vec3 l1 = quat_rotate_inverse(pose.rotation1, x - pose.translation1.xyz);
        inside = inside || min(shape_distance(shapes_u[k], l0), shape_distance(shapes_u[k], l1)) < gap;
    }
    return inside;
}

// Whether x is within the thickness, the radius and `travel` of some collider at the start or
// the end of the substep: a collider may stop it while the others move on, so a detection
// takes no shift (contact_decide.comp). Funnels are left out of both tests: a funnel's push
// is not held to the bound (pd_contact.glsl), and these rules would only slow the cloth
// pouring through one.
bool near_collider(vec3 x, float travel)
{
    float reach = contact_u.thickness + contact_u.radius + travel;
    bool near = false;
    for (uint k = 0u; k < contact_u.collider_count; k++) {
        if (HAS_TYPE(CVK_COLLIDER_FUNNEL_ID) && shapes_u[k].type == CVK_COLLIDER_FUNNEL_ID)
            continue;
        cvk_gpu_pose pose = poses_u[k];
        vec3 l0 = quat_rotate_inverse(pose.rotation0, x - pose.translation0.xyz);
        vec3 l1 = quat_rotate_inverse(pose.rotation1, x - pose.translation1.xyz);
        float d = min(shape_distance(shapes_u[k], l0), shape_distance(shapes_u[k], l1));
        near = near || !(d >= reach);
    }
    return near;
}

void bound_axes(vec3 low, vec3 high, vec3 vlow, vec3 vhigh)
{
    if (low.x > high.x)
        return;
    atomicMin(motion_bounds.e_low_x, ordered(low.x));
    atomicMin(motion_bounds.e_low_y, ordered(low.y));
    atomicMin(motion_bounds.e_low_z, ordered(low.z));
    atomicMax(motion_bounds.e_high_x, ordered(high.x));
    atomicMax(motion_bounds.e_high_y, ordered(high.y));
    atomicMax(motion_bounds.e_high_z, ordered(high.z));
    atomicMin(motion_bounds.v_low_x, ordered(vlow.x));
    atomicMin(motion_bounds.v_low_y, ordered(vlow.y));
    atomicMin(motion_bounds.v_low_z, ordered(vlow.z));
    atomicMax(motion_bounds.v_high_x, ordered(vhigh.x));
    atomicMax(motion_bounds.v_high_y, ordered(vhigh.y));
    atomicMax(motion_bounds.v_high_z, ordered(vhigh.z));
}

void main()
{
    if (pc.count == 0u)
        return;
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (pc.phase == 1u) {
        vec3 next = vec3(motion_bounds.next_x, motion_bounds.next_y, motion_bounds.next_z);
        bool exceed = false;
        for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += stride) {
            uint p = pc.first + i;
            vec4 seen = texelFetch(searched_t, int(p));
            vec3 x = contact_x(p);
            vec3 e = 2.0 * x - previous[p].xyz - seen.xyz - next;
            previous[p] = vec4(x, 0.0); // the next substep's x_before
            exceed = exceed || !(length(e) <= contact_u.redetect * abs(seen.w)) ||
                     inside_collider(seen.xyz + next, contact_u.thickness - abs(seen.w));
        }
        if (exceed)
            atomicOr(motion_bounds.exceed, 1u);
        return;
    }
    vec3 low = vec3(BIG), high = vec3(-BIG), vlow = vec3(BIG), vhigh = vec3(-BIG);
    bool near = false;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += stride) {
        uint p = pc.first + i;
        vec3 x = contact_x(p);
        vec3 v = x - previous[p].xyz;
        near = near || near_collider(x, 2.0 * length(v));
        vec3 e = x - texelFetch(searched_t, int(p)).xyz + v;
        bool finite = all(lessThanEqual(abs(e), vec3(BIG))) && all(lessThanEqual(abs(v), vec3(BIG)));
        low = min(low, finite ? e : vec3(-BIG));
        high = max(high, finite ? e : vec3(BIG));
        vlow = min(vlow, finite ? v : vec3(-BIG));
        vhigh = max(vhigh, finite ? v : vec3(BIG));
    }
    bound_axes(low, high, vlow, vhigh);
    if (near)
        atomicOr(motion_bounds.near, 1u);
}
