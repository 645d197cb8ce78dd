#version 450
#extension GL_GOOGLE_include_directive : require
// Contact after the last sweep of every outer iteration, in place on the iterate that sweep
// wrote (dst), in two passes (pd_contact.glsl):
//   - LISTED (spec id 2): the free particles in some pair the last detection listed (the work
//     list contact_bound.comp writes, dispatched through its indirect command): u <- the
//     displacement that keeps the particle off the other cloth features, within its bound. Only
//     these particles are dispatched: lavapipe runs every statement of a shader under a mask,
//     a loop's body at least once, so a test of "in a pair?" inside a pass over all particles
//     saves nothing there (7.6 of 14.8 ms a frame of the 40 × 40 drape with no pair listed);
//   - then every particle: kept within its bound (tethers do not hold it) and out of the
//     colliders.
// The next outer iteration's local step starts from the result, and the last one leaves the
// substep's displacement free of penetration (contact_one, pd_contact.glsl). The fused sweeps
// (pd_fused.comp) run the same two passes after their sweeps.
// The first is built on its own (CLOTH_CONTACT defined), without the colliders' code: lavapipe
// inlines and compiles the code of a branch a specialisation constant switches off before it
// drops it, and with it this pass's pipeline took as long to make as the second's (1.1 s each
// for the 40 x 40 contact drape, most of the simulation's creation).
#include "solvers/pd_common.glsl"
#include "solvers/pd_contact.glsl"

#ifdef CLOTH_CONTACT
const bool LISTED = true;
#else
layout(constant_id = 2) const bool LISTED = false;
#endif

void main()
{
    vec3 shift = SELF ? bound_shift() : vec3(0.0);
    if (LISTED) {
        if (pc.count == 0u)
            return; // the warm-up dispatch changes nothing
        uint count = lists[CVK_LIST_LISTED_COUNT], start = list_start(CVK_LIST_LISTED_GROUPS);
        for (uint i = gl_GlobalInvocationID.x; i < count; i += invocation_stride())
            contact_one(lists[start + i], true, shift);
        return;
    }
#ifndef CLOTH_CONTACT
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        contact_one(pc.first + i, false, shift);
    }
#endif
}
