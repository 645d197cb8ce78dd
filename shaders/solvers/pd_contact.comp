#version 450
#extension GL_GOOGLE_include_directive : require
// Contact after the last sweep of every outer iteration, in place on the iterate that sweep
// wrote (dst): u <- the displacement that keeps the particle out of colliders and off other
// cloths, within its bound (pd_contact.glsl). The next outer iteration's local step starts from it, and the last
// one leaves the substep's displacement free of penetration. w marks a particle this pass
// moved, or the strain limit before it did (pd_strain.comp): the next outer iteration's first
// sweep does not over-relax it (pd_gauss_seidel.comp); the sweeps write w = 0.
#include "solvers/pd_common.glsl"
#include "solvers/pd_contact.glsl"

// p's displacement kept out of contact, w marking whether that moved it.
void contact_one(uint p)
{
    vec4 start = imageLoad(dst_read, int(p));
    vec3 u = start.xyz;
    if (p >= contact_u.free_count) { // attached (self-contact only): kept within the bound
        vec3 x0 = fetch(x_read, p);
        dst[p] = vec4(within_bound(p, x0 + u) - x0, 0.0);
        return;
    }
    vec3 moved = pd_contact(p, u);
    dst[p] = vec4(moved, any(notEqual(moved, u)) || start.w != 0.0 ? 1.0 : 0.0);
}

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        contact_one(pc.first + i);
    }
}
