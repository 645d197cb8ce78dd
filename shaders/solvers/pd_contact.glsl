// Contact between the projective-dynamics iterations: a particle's displacement is kept a
// thickness off the cloth features listed at the last detection, within its bound, and out of
// every collider (contact/collide.glsl, lib/contact/collide.h). The other side's particles are
// read from src (the iterate before), never from the buffer being written, so the result does
// not depend on the order of invocations.
// Specialised: collider types the scene lacks (COLLIDER_TYPES, id 3) and self-contact
// (SELF, id 4) compile to nothing — on lavapipe both sides of a branch run.
#define CONTACT_TYPES_ID 3
#include "contact/collide.glsl"

layout(constant_id = 4) const bool SELF = false;
const bool COLLIDERS = COLLIDER_TYPE_BITS != 0u;

// The funnels' edge test, and the path test a funnel's push brought back within the bound must
// pass, are left out of the builds for scenes without a funnel (NO_FUNNELS) and of the pass
// over the listed particles (CLOTH_CONTACT), which has no colliders: a branch a specialisation
// constant switches off is still inlined and compiled by lavapipe before it is dropped, and
// these inline every collider type's distance and normal several times over (the 40 x 40
// contact drape's pass over every particle took 1.5-1.9 s to make with them, 0.8 without).
#if !defined(CLOTH_CONTACT) && !defined(NO_FUNNELS)
#define FUNNEL_EDGES 1
#endif
#ifdef FUNNEL_EDGES
// A funnel is a surface with two sides, and a particle's contact alone lets an edge cut
// through it: a particle carried below the rim and round it to the outside stays outside
// while its neighbours are inside, the edges between them through the wall, and the cloth
// pulls it up the outer wall, stretching those edges without bound (funnel.json stopped at
// frame 55 with an edge ten times its rest length). So the midpoints of the particle's
// triangle edges are kept half a thickness off the funnels too, on the side each started the
// substep on, and the particle moves by the largest of their corrections (its neighbour moves
// by the same from its side, so the midpoint moves by all of it). The neighbours' displacement
// is the iterate before (src), as for the triangles above. shell_push: funnel k's push on the
// midpoints of p's edges, where larger than `most`.
vec3 shell_push(uint k, uint p, vec3 x0, vec3 u, vec3 most)
{
    uint base = contact_u.particle_count + 1u;
    float r = 0.5 * contact_u.thickness;
    // In the funnel's frame every point of a midpoint's path is within max(|m0 - x0|,
    // |m1 - x1|) of p's path, and p's path within |l1 - l0| of l0: an edge whose bound
    // keeps it beyond r is not traced (a trace costs up to 32 of the funnel's distances).
    vec3 l0, l1;
    local_path(collider_pose(k), x0, u, l0, l1);
    float slack = shape_distance(typed_shape(k, CVK_COLLIDER_FUNNEL_ID), l0) - length(l1 - l0) - r;
    uint o_begin = contact_incident(p), o_end = contact_incident(p + 1u);
    for (uint o = o_begin; o < o_end; o++) {
        uvec4 t = contact_triangle(contact_incident(base + o));
        // The edge to the next corner in the triangle's winding: each edge of p once, as
        // the triangles on either side wind it the other way; and the edge to the corner
        // before where no triangle has it the other way round (a border: the table's w
        // marks it, lib/contact/collide.c).
        uint k0 = t.x == p ? 0u : (t.y == p ? 1u : 2u);
        uint next = t[(k0 + 1u) % 3u], prev = t[(k0 + 2u) % 3u];
        bool border = (t.w & (1u << ((k0 + 2u) % 3u))) != 0u;
        for (uint j = 0u; j < (border ? 2u : 1u); j++) {
            uint q = j == 0u ? next : prev;
            vec3 half0 = 0.5 * (fetch(x_read, q) - x0);
            vec3 half1 = half0 + 0.5 * (FETCH_SRC(q) - u);
            if (max(length(half0), length(half1)) < slack)
                continue;
            vec3 um = u + half1 - half0; // the midpoint's displacement
            vec3 push = collide_shape(k, CVK_COLLIDER_FUNNEL_ID, x0 + half0, um, r) - um;
            if (dot(push, push) > dot(most, most))
                most = push;
        }
    }
    return most;
}

vec3 edges_off_shells(uint p, vec3 x0, vec3 u)
{
    vec3 most = vec3(0.0);
#define SHELL_PUSH(k) most = shell_push(k, p, x0, u, most);
    FOR_EACH_FUNNEL(p, SHELL_PUSH)
#undef SHELL_PUSH
    return u + most;
}

// Whether p's path from x0 to x0 + u keeps a quarter of the thickness (and half its start's
// distance) off funnel k: a place within the bound on the side of the surface the particle
// started on, which a funnel's push may be brought back to.
bool shell_clear(uint k, vec3 x0, vec3 u)
{
    cvk_gpu_collider c = typed_shape(k, CVK_COLLIDER_FUNNEL_ID);
    vec3 l0, l1;
    local_path(collider_pose(k), x0, u, l0, l1);
    float r = min(0.25 * contact_u.thickness, 0.5 * shape_distance(c, l0));
    vec3 hit, n;
    return r > 0.0 && !trace_segment(c, l0, l1, r, hit, n);
}

bool shells_clear(uint p, vec3 x0, vec3 u)
{
    bool clear = true;
#define SHELL_CLEAR(k) clear = clear && shell_clear(k, x0, u);
    FOR_EACH_FUNNEL(p, SHELL_CLEAR)
#undef SHELL_CLEAR
    return clear;
}

#endif

// Where corner q is in the iterate before (src): triangle corners and edge ends are read from
// it, never from the buffer being written, so the result does not depend on the order of
// invocations.
vec3 iterate_x(uint q)
{
    return fetch(x_read, q) + FETCH_SRC(q);
}

vec3 start_x(uint q)
{
    return fetch(x_read, q);
}

#include "contact/cloth_push.glsl"

// The cloth contact pass (LISTED in pd_contact.comp): p's displacement u pushed off the
// features of its pairs, within its bound.
vec3 pd_cloth_contact(uint p, vec3 u, vec3 shift)
{
    vec3 x0 = fetch(x_read, p);
    vec3 xp = x0 + u;
    return within_bound(p, xp + cloth_push(p, x0, xp), shift) - x0;
}

#ifndef CLOTH_CONTACT
// The pass over every particle, after the cloth contact pass: p's displacement u within its
// bound (with self-contact) and out of the colliders.
vec3 pd_contact(uint p, vec3 u, vec3 shift)
{
    vec3 x0 = fetch(x_read, p);
    if (SELF)
        u = within_bound(p, x0 + u, shift) - x0;
    vec3 pushed = u;
#ifdef FUNNEL_EDGES
    if (HAS_TYPE(CVK_COLLIDER_FUNNEL_ID))
        pushed = edges_off_shells(p, x0, pushed);
#endif
    if (COLLIDERS)
        pushed = collide_colliders(p, x0, pushed);
    // A collider's push must not take a particle past its bound (lib/contact/collide.h): the
    // pushed place is brought back within it where that leaves the particle outside every
    // solid collider's surface (within the thickness of it at most: the bound is under the
    // thickness) and on its side of every funnel. Where it would not — a collider that moved
    // onto where detection saw the particle — the collider wins, and the particle, past its
    // bound, makes the next substep detect.
    if (SELF && COLLIDERS && any(notEqual(pushed, u))) {
        vec3 back = within_bound(p, x0 + pushed, shift);
        bool outside = nearest_solid(p, back, false) >= 0.0;
#ifdef FUNNEL_EDGES
        if (HAS_TYPE(CVK_COLLIDER_FUNNEL_ID))
            outside = outside && shells_clear(p, x0, back - x0);
#endif
        pushed = outside ? back - x0 : pushed;
    }
    return pushed;
}
#endif

// The contact passes' work on particle p (pd_contact.comp; pd_fused.comp after its sweeps):
// listed, the pass over the particles in pairs; else the pass over every particle. p's
// displacement is read where the pass before wrote it (LOAD_DST) and kept out of contact, w
// marking whether this or the strain limit before it (pd_strain.glsl) moved it: the next outer
// iteration's first sweep does not over-relax such a particle (pd_gauss_seidel.comp); the
// sweeps write w = 0.
void contact_one(uint p, bool listed, vec3 shift)
{
    vec4 start = LOAD_DST(p);
    vec3 u = start.xyz;
    if (p >= contact_u.free_count) { // attached (self-contact only): kept within the bound
        vec3 x0 = fetch(x_read, p);
        STORE_DST(p, vec4(within_bound(p, x0 + u, shift) - x0, 0.0));
        return;
    }
#ifdef CLOTH_CONTACT
    vec3 moved = pd_cloth_contact(p, u, shift);
#else
    vec3 moved = listed ? pd_cloth_contact(p, u, shift) : pd_contact(p, u, shift);
#endif
    STORE_DST(p, vec4(moved, any(notEqual(moved, u)) || start.w != 0.0 ? 1.0 : 0.0));
}
