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
const bool COLLIDERS = COLLIDER_TYPES != 0u;

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
    uvec2 range = collider_range(p);
    for (uint k = range.x; k < range.y; k++) {
        if (collider_shape(k).type != CVK_COLLIDER_FUNNEL_ID)
            continue;
        // In the funnel's frame every point of a midpoint's path is within max(|m0 - x0|,
        // |m1 - x1|) of p's path, and p's path within |l1 - l0| of l0: an edge whose bound
        // keeps it beyond r is not traced (a trace costs up to 32 of the funnel's distances).
        vec3 l0, l1;
        local_path(collider_pose(k), x0, u, l0, l1);
        float slack = shape_distance(collider_shape(k), l0) - length(l1 - l0) - r;
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

// Whether p's path from x0 to x0 + u keeps a quarter of the thickness (and half its start's
// distance) off every funnel: a place within the bound on the side of the surface the particle
// started on, which a funnel's push may be brought back to.
bool shells_clear(uint p, vec3 x0, vec3 u)
{
    uvec2 range = collider_range(p);
    for (uint k = range.x; k < range.y; k++) {
        cvk_gpu_collider c = collider_shape(k);
        if (c.type != CVK_COLLIDER_FUNNEL_ID)
            continue;
        vec3 l0, l1;
        local_path(collider_pose(k), x0, u, l0, l1);
        float r = min(0.25 * contact_u.thickness, 0.5 * shape_distance(c, l0));
        vec3 hit, n;
        if (!(r > 0.0) || trace_segment(c, l0, l1, r, hit, n))
            return false;
    }
    return true;
}

// Where corner q is in the iterate before (src): triangle corners and edge ends are read from
// it, never from the buffer being written, so the result does not depend on the order of
// invocations.
vec3 iterate_x(uint q)
{
    return fetch(x_read, q) + fetch(src, q);
}

// One vertex–feature pair (the vertex vx at xv, the feature `entry`): how far the vertex
// moves along the normal (out: n, the feature's corners' weights w and the pair's share
// s = (thickness - d) / (1 + |w|^2), the projection of the distance constraint with equal
// masses: the vertex moves s, the nearest point of the feature back by s |w|^2, so the pair
// ends the thickness apart). False when the pair is not within the thickness.
bool feature_pair(vec3 xv, uint entry, out uvec3 v, out uint count, out vec3 n, out vec3 w,
                  out float s, out vec3 near)
{
    count = feature_corners(entry, v);
    vec3 a = iterate_x(v.x), b = count > 1u ? iterate_x(v.y) : a;
    vec3 c = count > 2u ? iterate_x(v.z) : b;
    near = feature_closest(xv, count, a, b, c, w);
    vec3 gap = xv - near;
    float d = length(gap);
    if (!(d < contact_u.thickness) || d == 0.0)
        return false;
    n = gap / d;
    s = (contact_u.thickness - d) / (1.0 + dot(w, w));
    return true;
}

// Coulomb friction on a move along n of `depth`: the tangential part of the slide (the
// particle's motion over the substep relative to the surface's) taken away while within
// mu_s times the depth, mu_k times it otherwise.
vec3 friction(vec3 slide, vec3 n, float depth)
{
    vec3 tangent = slide - dot(slide, n) * n;
    float t = length(tangent);
    float stop = t <= contact_u.static_friction * depth ? 1.0
               : min(1.0, contact_u.friction * depth / max(t, 1e-30));
    return -stop * tangent;
}

// Cloth contact of p at xp (lib/contact/collide.h): its share of every vertex–feature pair it
// is in — as the vertex (its list) and as a corner of the feature (its side list) — and of
// every edge–edge pair of its edges (shared by the four ends as the nearest points divide the
// edges), with friction against the other side's motion.
vec3 cloth_push(uint p, vec3 x0, vec3 xp)
{
    const uint K = uint(CVK_CONTACTS_PER_PARTICLE), KE = uint(CVK_CONTACTS_PER_EDGE);
    const uint KS = uint(CVK_SIDES_PER_PARTICLE);
    float thickness = contact_u.thickness;
    vec3 push = vec3(0.0);
    uvec3 v;
    uint count;
    vec3 n, w, near;
    float s;
    for (uint k = 0u; k < K; k++) {
        uint entry = contact_entry(p * K + k);
        if (entry == CVK_NO_CONTACT)
            break;
        if (!feature_pair(xp, entry, v, count, n, w, s, near))
            continue;
        vec3 a0 = fetch(x_read, v.x), b0 = count > 1u ? fetch(x_read, v.y) : a0;
        vec3 c0 = count > 2u ? fetch(x_read, v.z) : b0;
        vec3 near0 = w.x * a0 + w.y * b0 + w.z * c0;
        push += s * n + friction((xp - x0) - (near - near0), n, s);
    }
    for (uint k = 0u; k < KS; k++) {
        uvec2 pair = side_pair(p, k);
        if (pair.x == CVK_NO_CONTACT)
            break;
        vec3 xv = iterate_x(pair.x);
        if (!feature_pair(xv, pair.y, v, count, n, w, s, near))
            continue;
        float wp = v.x == p ? w.x : (v.y == p ? w.y : w.z);
        vec3 v0 = fetch(x_read, pair.x);
        push += -s * wp * n + wp * friction((xp - x0) - (xv - v0), -n, s * wp);
    }
    uint base = contact_u.particle_count + 1u;
    for (uint o = particle_edge(p); o < particle_edge(p + 1u); o++) {
        uint e = particle_edge(base + o);
        if (edge_entry(e * KE) == CVK_NO_CONTACT)
            continue; // the common case: nothing near the edge
        uvec2 ends = contact_edge(e);
        uint q = ends.x == p ? ends.y : ends.x;
        vec3 xq = iterate_x(q);
        for (uint k = 0u; k < KE; k++) {
            uint f = edge_entry(e * KE + k);
            if (f == CVK_NO_CONTACT)
                break;
            uvec2 cd = contact_edge(f);
            float se, te;
            vec3 c1, c2;
            closest_segments(xp, xq, iterate_x(cd.x), iterate_x(cd.y), se, te, c1, c2);
            float d = length(c1 - c2);
            if (!(d < thickness) || d == 0.0 || se <= 0.0 || se >= 1.0 || te <= 0.0 || te >= 1.0)
                continue;
            // The projection of the distance constraint with equal masses: each end moves by
            // its weight times (thickness - d) / the sum of the four weights squared.
            float sum = (1.0 - se) * (1.0 - se) + se * se + (1.0 - te) * (1.0 - te) + te * te;
            push += (1.0 - se) * (thickness - d) / (sum * d) * (c1 - c2);
        }
    }
    // At most half a thickness of push in one pass, however many features push: a particle
    // crowded by several layers would be thrown by their summed corrections.
    float most = 0.5 * thickness, len = length(push);
    return len > most ? push * (most / len) : push;
}

// The cloth contact pass (LISTED in pd_contact.comp): p's displacement u pushed off the
// features of its pairs, within its bound.
vec3 pd_cloth_contact(uint p, vec3 u)
{
    vec3 x0 = fetch(x_read, p);
    vec3 xp = x0 + u;
    return within_bound(p, xp + cloth_push(p, x0, xp)) - x0;
}

// The pass over every particle, after the cloth contact pass: p's displacement u within its
// bound (with self-contact) and out of the colliders.
vec3 pd_contact(uint p, vec3 u)
{
    vec3 x0 = fetch(x_read, p);
    if (SELF)
        u = within_bound(p, x0 + u) - x0;
    vec3 pushed = u;
    if (HAS_TYPE(CVK_COLLIDER_FUNNEL_ID))
        pushed = edges_off_shells(p, x0, pushed);
    if (COLLIDERS)
        pushed = collide_colliders(p, x0, pushed);
    // A collider's push must not take a particle past its bound (lib/contact/collide.h): the
    // pushed place is brought back within it where that leaves the particle outside every
    // solid collider's surface (within the thickness of it at most: the bound is under the
    // thickness) and on its side of every funnel. Where it would not — a collider that moved
    // onto where detection saw the particle — the collider wins, and the particle, past its
    // bound, makes the next substep detect.
    if (SELF && COLLIDERS && any(notEqual(pushed, u))) {
        vec3 back = within_bound(p, x0 + pushed);
        bool outside = nearest_solid(p, back, false) >= 0.0;
        if (HAS_TYPE(CVK_COLLIDER_FUNNEL_ID))
            outside = outside && shells_clear(p, x0, back - x0);
        pushed = outside ? back - x0 : pushed;
    }
    return pushed;
}
