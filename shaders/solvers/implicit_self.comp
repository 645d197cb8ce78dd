#version 450
#extension GL_GOOGLE_include_directive : require
// Self-contact of the implicit family (lib/contact/collide.h), after the integration, which
// left x where the substep started and each free particle's displacement, within its bound,
// in r and z (implicit_integrate.comp, SELF):
//   - LISTED (spec id 4): the free particles in some pair the last detection listed (the work
//     list contact_bound.comp writes, dispatched through its indirect command), as pd's cloth
//     contact pass: the displacement in r pushed off the other cloth features
//     (contact/cloth_push.glsl, the other side read from r, never from z, which this pass
//     writes), within the bound, into z;
//   - then every free particle: x += z, and where the push changed the displacement, v = z / h
//     (a push becomes velocity, as in pd);
//   - ATTACHED (spec id 5, after the attachments' place pass): every attached particle kept
//     within its bound, as pd's contact pass keeps it (pc.stride is the free count, pc.count
//     the particle count here; a pinned one never leaves its bound): one the attachment would
//     take past it lags, and the next substep detects.
// Pinned and attached particles have no displacement of their own in r: theirs is h v (0 for
// a pinned one; the attachment's for an attached one, implicit_integrate's attach pass).
#define IMPLICIT_CONTACT 1 // the contact set (set 1): pairs, bounds, work lists
#include "solvers/implicit_common.glsl"

layout(constant_id = 4) const bool LISTED = false;
layout(constant_id = 5) const bool ATTACHED = false;

vec3 start_x(uint q)
{
    return x[q].xyz;
}

vec3 iterate_x(uint q)
{
    return x[q].xyz + (q < pc.count ? r[q].xyz : pc.h * v[q].xyz);
}

#include "contact/cloth_push.glsl"

void main()
{
    vec3 shift = bound_shift();
    if (ATTACHED) {
        for (uint p = pc.stride + gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride())
            x[p].xyz = within_bound(p, x[p].xyz, shift);
        return;
    }
    if (LISTED) {
        if (pc.count == 0u)
            return; // the warm-up dispatch changes nothing
        uint count = lists[CVK_LIST_LISTED_COUNT], start = list_start(CVK_LIST_LISTED_GROUPS);
        for (uint i = gl_GlobalInvocationID.x; i < count; i += invocation_stride()) {
            uint p = lists[start + i];
            vec3 x0 = x[p].xyz, xp = x0 + r[p].xyz;
            z[p] = vec4(within_bound(p, xp + cloth_push(p, x0, xp), shift) - x0, 0.0);
        }
        return;
    }
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += invocation_stride()) {
        vec3 u = z[p].xyz;
        if (any(notEqual(u, r[p].xyz)))
            v[p].xyz = u / pc.h;
        x[p].xyz += u;
    }
}
