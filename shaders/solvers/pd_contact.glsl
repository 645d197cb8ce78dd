// Contact between the projective-dynamics iterations: a particle's displacement is kept off
// the other cloths' triangles found for it this substep and out of every collider
// (contact/collide.glsl). Triangle corners are read from src (the iterate before), never from the
// buffer being written, so the result does not depend on the order of invocations.
// Specialised: collider types the scene lacks (COLLIDER_TYPES, id 3) and self-contact
// (SELF, id 4) compile to nothing — on lavapipe both sides of a branch run.
#define CONTACT_TYPES_ID 3
#include "contact/collide.glsl"

layout(constant_id = 4) const bool SELF = false;
// collision.edges: the lists hold edge pairs too (shared/layout.h, CVK_EDGE_PAIR).
layout(constant_id = 5) const bool EDGES = false;
const bool COLLIDERS = COLLIDER_TYPES != 0u;
// Self-contact alone: the pass visits only the particles the last search listed with
// candidates (lib/contact/collide.h, "Patches"); with colliders it visits every particle.
const bool LISTED = SELF && !COLLIDERS;

// A funnel is a surface with two sides, and a particle's contact alone lets an edge cut
// through it: a particle carried below the rim and round it to the outside stays outside
// while its neighbours are inside, the edges between them through the wall, and the cloth
// pulls it up the outer wall, stretching those edges without bound (funnel.json stopped at
// frame 55 with an edge ten times its rest length). So the midpoints of the particle's
// triangle edges are kept half a thickness off the funnels too, on the side each started the
// substep on, and the particle moves by the largest of their corrections (its neighbour moves
// by the same from its side, so the midpoint moves by all of it). The neighbours' displacement
// is the iterate before (src), as for the triangles above.
vec3 edges_off_shells(uint p, vec3 x0, vec3 u)
{
    uint base = contact_u.particle_count + 1u;
    float r = 0.5 * contact_u.thickness;
    vec3 most = vec3(0.0);
    for (uint k = 0u; k < contact_u.collider_count; k++) {
        if (shapes_u[k].type != CVK_COLLIDER_FUNNEL_ID)
            continue;
        // In the funnel's frame every point of a midpoint's path is within max(|m0 - x0|,
        // |m1 - x1|) of p's path, and p's path within |l1 - l0| of l0: an edge whose bound
        // keeps it beyond r is not traced (a trace costs up to 32 of the funnel's distances).
        cvk_gpu_pose pose = poses_u[k];
        vec3 l0 = quat_rotate_inverse(pose.rotation0, x0 - pose.translation0.xyz);
        vec3 l1 = quat_rotate_inverse(pose.rotation1, x0 + u - pose.translation1.xyz);
        float slack = shape_distance(shapes_u[k], l0) - length(l1 - l0) - r;
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
                vec3 half1 = half0 + 0.5 * (fetch(src, q) - u);
                if (max(length(half0), length(half1)) < slack)
                    continue;
                vec3 um = u + half1 - half0; // the midpoint's displacement
                vec3 push = collide_shape(k, x0 + half0, um, r) - um;
                if (dot(push, push) > dot(most, most))
                    most = push;
            }
        }
    }
    return u + most;
}

// p's move for the edge pair e of its list (collide_edge); the other ends from the iterate
// before (src), as a triangle's corners.
vec3 edge_pair(uint p, vec3 x0, vec3 xp, uint e)
{
    uint r;
    bool border;
    own_edge(p, (e & ~CVK_EDGE_PAIR) >> CVK_EDGE_OWN_SHIFT, r, border);
    uint f = (e >> 1u) & ((1u << (CVK_EDGE_OWN_SHIFT - 1)) - 1u);
    uvec4 tri = contact_triangle(f / 3u);
    uint a = corner_of(tri, f % 3u), b = corner_of(tri, (f % 3u + 1u) % 3u);
    vec3 r0 = fetch(x_read, r), a0 = fetch(x_read, a), b0 = fetch(x_read, b);
    return collide_edge(x0, xp, r0, r0 + fetch(src, r), a0, b0, a0 + fetch(src, a),
                        b0 + fetch(src, b), e & 1u);
}

vec3 pd_contact(uint p, vec3 u)
{
    vec3 x0 = fetch(x_read, p);
    if (SELF) {
        vec3 xp = x0 + u;
        // Farthest first (the list is nearest first), so the nearest triangle has the last
        // word: a particle that crossed a face is also beside its neighbours' edges, which
        // push it away from them, further through, and taken after the face they undid its
        // correction (a patch dragged 7 mm through a cloth and let go stayed through).
        uint n = 0u;
        while (n < uint(CVK_CONTACTS_PER_PARTICLE) &&
               contact_entry(p * uint(CVK_CONTACTS_PER_PARTICLE) + n) != CVK_NO_CONTACT)
            n++;
        for (uint k = n; k-- > 0u;) {
            uint e = contact_entry(p * uint(CVK_CONTACTS_PER_PARTICLE) + k);
            if (EDGES && (e & CVK_EDGE_PAIR) != 0u) {
                xp = edge_pair(p, x0, xp, e);
                continue;
            }
            uvec4 t = contact_triangle((e & ~CVK_UNTANGLE_PAIR) >> 1u);
            vec3 a0 = fetch(x_read, t.x), b0 = fetch(x_read, t.y), c0 = fetch(x_read, t.z);
            xp = collide_triangle(x0, xp, a0, b0, c0, a0 + fetch(src, t.x), b0 + fetch(src, t.y),
                                  c0 + fetch(src, t.z), e & (CVK_UNTANGLE_PAIR | 1u));
        }
        // At most half a thickness of push in one pass, however many triangles push: a
        // particle crowded by several layers was otherwise thrown by their summed corrections.
        vec3 push = xp - (x0 + u);
        float length_push = length(push);
        float most = 0.5 * contact_u.thickness;
        u += length_push > most ? push * (most / length_push) : push;
    }
    if (HAS_TYPE(CVK_COLLIDER_FUNNEL_ID))
        u = edges_off_shells(p, x0, u);
    if (COLLIDERS)
        u = collide_colliders(x0, u);
    return u;
}
