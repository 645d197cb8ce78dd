#version 450
#extension GL_GOOGLE_include_directive : require
// Contact after the last sweep of every outer iteration, in place on the iterate that sweep
// wrote (dst): u <- the displacement that keeps the particle out of colliders and off other
// cloths (pd_contact.glsl). The next outer iteration's local step starts from it, and the last
// one leaves the substep's displacement free of penetration. w marks a particle this pass
// moved: the next outer iteration's first sweep does not over-relax it (pd_gauss_seidel.comp);
// every other pass writes w = 0.
#include "solvers/pd_common.glsl"
#include "solvers/pd_contact.glsl"

// p's displacement kept out of contact, w marking whether that moved it.
void contact_one(uint p)
{
    vec3 u = fetch(dst_read, p);
    vec3 moved = pd_contact(p, u);
    dst[p] = vec4(moved, any(notEqual(moved, u)) ? 1.0 : 0.0);
}

void main()
{
    if (LISTED) {
        // Only the particles with candidates (no colliders: nothing else to do), listed by the
        // search (contact/contact_compact.comp).
        uint listed = pc.count == 0u ? 0u : lists[CVK_LIST_CONTACT_COUNT];
        for (uint i = gl_GlobalInvocationID.x; i < listed; i += invocation_stride()) {
            contact_one(lists[contact_list_base() + i]);
        }
        return;
    }
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        contact_one(pc.first + i);
    }
}
