#version 450
#extension GL_GOOGLE_include_directive : require
// Detection, vertex against faces (lib/contact/collide.h): for every particle p, every triangle
// not around p whose nearest point is within the contact radius of p at the start of the
// substep (x_n). A triangle that near has a corner within the reach (the radius plus the
// farthest a point of a triangle is from its nearest corner, from the longest edge measured
// by contact_edges.comp; the hash's cells are wider, contact_decide.comp), and the walk over
// the 27 hash cells around p visits every such corner (of p's instance: the scene's copies
// never touch one another, and a corner of another is passed over); the triangles
// around each are tested once, through their lowest-index corner within reach. Each pair found:
//   - p's nearest distance and each corner's (an atomic minimum on the float's bits, which
//     order as the non-negative floats do, so the result does not depend on thread timing)
//     take its distance: the bounds come from them (contact_bound.comp);
//   - p's list keeps the feature the nearest point lies on — the face, an edge or a corner, so a
//     point beside an edge shared by two faces is listed once — nearest first, equal distances by
//     feature, the CVK_CONTACTS_PER_PARTICLE nearest.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
#define HASH_SET 1
#include "contact/hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

const uint K = uint(CVK_CONTACTS_PER_PARTICLE);
const bool DEDUP = true;

uint kept[K];
float dist[K];

#include "contact/nearest.glsl"

// The feature of triangle t that its point nearest p lies on, from the barycentric weights.
uint feature_of(uint t, uvec4 tri, vec3 w)
{
    bool in0 = w.x > 0.0, in1 = w.y > 0.0, in2 = w.z > 0.0;
    uint inside = uint(in0) + uint(in1) + uint(in2);
    if (inside == 3u)
        return t << 2u | CVK_FEATURE_FACE;
    if (inside == 1u)
        return (in0 ? tri.x : (in1 ? tri.y : tri.z)) << 2u | CVK_FEATURE_VERTEX;
    // edge k runs from corner k to corner k + 1: the one whose opposite weight is 0
    uvec4 edges = contact_triangle_edges(t);
    uint e = !in2 ? edges.x : (!in0 ? edges.y : edges.z);
    return e << 2u | CVK_FEATURE_EDGE;
}

// The triangles around corner q within the radius of p (q within reach of p).
float triangles_at(uint p, vec3 xp, uint q, vec3 xq, float reach2, float nearest_p)
{
    uint base = contact_u.particle_count + 1u;
    for (uint o = contact_incident(q); o < contact_incident(q + 1u); o++) {
        uint t = contact_incident(base + o);
        uvec4 tri = contact_triangle(t);
        if (tri.x == p || tri.y == p || tri.z == p)
            continue; // around p: adjacent, never in contact
        uint u = tri.x == q ? tri.y : tri.x;
        uint v = tri.z == q ? tri.y : tri.z;
        vec3 xu = contact_x(u), xv = contact_x(v);
        if ((u < q && within_reach(xp, xu, reach2)) || (v < q && within_reach(xp, xv, reach2)))
            continue; // tested through a lower corner
        vec3 a = tri.x == q ? xq : xu;
        vec3 b = tri.y == q ? xq : (tri.x == q ? xu : xv);
        vec3 c = tri.z == q ? xq : xv;
        // Every point of the triangle is within its longest distance from the centroid of it:
        // a triangle whose centroid is farther than that plus the radius is not near.
        vec3 g = (a + b + c) * (1.0 / 3.0);
        float spread2 = max(max(dot(a - g, a - g), dot(b - g, b - g)), dot(c - g, c - g));
        vec3 pg = xp - g;
        float near = contact_u.radius + sqrt(spread2);
        if (dot(pg, pg) >= near * near)
            continue;
        vec3 w;
        float d = length(xp - closest_on_triangle(xp, a, b, c, w));
        if (!(d < contact_u.radius))
            continue;
        nearest_p = min(nearest_p, d);
        uint bits = floatBitsToUint(d);
        atomicMin(nearest[tri.x], bits);
        atomicMin(nearest[tri.y], bits);
        atomicMin(nearest[tri.z], bits);
        INSERT(d, feature_of(t, tri, w));
    }
    return nearest_p;
}

// Corners found within reach, tested a batch at a time: on SIMD hardware a loop body runs
// whenever one lane needs it, so the triangles are tested in a loop over the corners a lane
// found, not inside the walk over every hash entry (about 4 entries of 5 are not within reach).
const uint BATCH = 16u;
uint found[BATCH];

float test_batch(uint p, vec3 xp, uint count, float reach2, float nearest_p)
{
    for (uint i = 0u; i < count; i++) {
        uint q = found[i];
        nearest_p = triangles_at(p, xp, q, contact_x(q), reach2, nearest_p);
    }
    return nearest_p;
}

void detect(uint p)
{
    vec3 xp = contact_x(p);
    clear_nearest();
    // A triangle within the radius has a corner within the radius plus its longest edge / √3
    // (the farthest a point of it is from its nearest corner).
    float reach = contact_u.radius + uintBitsToFloat(frame.longest) * 0.57735027;
    float reach2 = reach * reach;
    float nearest_p = INFINITY;
    uint instance = contact_instance(p); // copies never touch one another
    hash_walk w = hash_walk_begin(xp, instance); // the slots of p's instance's corners
    uvec4 entry;
    bool here;
    uint count = 0u;
    while (hash_walk_step(w, entry, here)) {
        if (here && within_reach(xp, uintBitsToFloat(entry.xyz), reach2) &&
            contact_instance(entry.w) == instance) {
            found[count] = entry.w;
            count++;
        }
        if (count == BATCH) {
            nearest_p = test_batch(p, xp, count, reach2, nearest_p);
            count = 0u;
        }
    }
    nearest_p = test_batch(p, xp, count, reach2, nearest_p);
    if (nearest_p < INFINITY)
        atomicMin(nearest[p], floatBitsToUint(nearest_p));
    for (uint k = 0u; k < K; k++) {
        contacts[p * K + k] = kept[k];
        if (kept[k] == CVK_NO_CONTACT)
            continue;
        // The pair on the feature's side: listed under each of its corners (in the order of
        // the atomics; contact_bound.comp sorts each list).
        uvec3 v;
        uint count = feature_corners(kept[k], v);
        for (uint j = 0u; j < count; j++) {
            uint q = j == 0u ? v.x : (j == 1u ? v.y : v.z);
            uint at = atomicAdd(sides[q], 1u);
            if (at < uint(CVK_SIDES_PER_PARTICLE)) {
                uint base = contact_u.particle_count + 2u * (q * uint(CVK_SIDES_PER_PARTICLE) + at);
                sides[base] = p;
                sides[base + 1u] = kept[k];
            }
        }
    }
}

void main()
{
    if (pc.count == 0u)
        return;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
        detect(pc.first + i);
}
