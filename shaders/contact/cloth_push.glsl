// Cloth contact (lib/contact/collide.h), the share of a particle in its listed pairs, for any
// family: the includer defines where a particle q was at the start of the substep,
// vec3 start_x(uint q), and where it is in the iterate before the pass, vec3 iterate_x(uint q)
// (never the buffer being written, so the result does not depend on the order of invocations),
// and includes contact/collide.glsl first.
#ifndef CONTACT_CLOTH_PUSH_GLSL
#define CONTACT_CLOTH_PUSH_GLSL

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
    float pushing = 0.0; // the pairs that push p
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
        vec3 a0 = start_x(v.x), b0 = count > 1u ? start_x(v.y) : a0;
        vec3 c0 = count > 2u ? start_x(v.z) : b0;
        vec3 near0 = w.x * a0 + w.y * b0 + w.z * c0;
        push += s * n + friction((xp - x0) - (near - near0), n, s);
        pushing += 1.0;
    }
    for (uint k = 0u; k < KS; k++) {
        uvec2 pair = side_pair(p, k);
        if (pair.x == CVK_NO_CONTACT)
            break;
        vec3 xv = iterate_x(pair.x);
        if (!feature_pair(xv, pair.y, v, count, n, w, s, near))
            continue;
        float wp = v.x == p ? w.x : (v.y == p ? w.y : w.z);
        vec3 v0 = start_x(pair.x);
        push += -s * wp * n + wp * friction((xp - x0) - (xv - v0), -n, s * wp);
        pushing += 1.0;
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
            pushing += 1.0;
        }
    }
    // The mean of the pairs' pushes, not their sum (Macklin et al. 2014's constraint
    // averaging): every pair is projected from the same iterate, so where several push one
    // particle — a layer in a stack, pushed up by the one below as the vertex and down by the
    // one above as a corner — their sum overshoots, and the overshoot becomes speed. Summed,
    // the six-cloth pile still threw particles at 5 m/s after six seconds and detected at 80 %
    // of its substeps; averaged, at 3 m/s and 45 % (docs/figures/contact-ogc/rest.csv).
    push /= max(pushing, 1.0);
    // At most half a thickness of push in one pass, however many features push: a particle
    // crowded by several layers would be thrown by their corrections.
    float most = 0.5 * thickness, len = length(push);
    return len > most ? push * (most / len) : push;
}
#endif
