#version 450
#extension GL_GOOGLE_include_directive : require
// Detection, edge against edge (lib/contact/collide.h): for every edge e, every edge sharing no
// end with it whose nearest point is within the contact radius of e at the start of the
// substep. Such an edge f has an end within the radius plus half of each edge's length of e's
// midpoint (the longest edge measured in phase 1; the hash's cells are that wide,
// contact_decide.comp), so the walk over the 27 cells around the midpoint visits every such end, and the edges at each are
// tested once, through their lower end within reach. e's nearest distance is kept for the
// bounds of its ends (contact_bound.comp: f finds e too, so no atomics are needed), and its
// list keeps the nearest CVK_CONTACTS_PER_EDGE whose nearest points lie inside both edges
// (where they do not, the pair is a vertex against an edge or a vertex, which the faces'
// detection lists: contact_detect.comp), nearest first, equal distances by edge.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
#define HASH_SET 1
#include "contact/hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

const uint K = uint(CVK_CONTACTS_PER_EDGE);
const bool DEDUP = false;

uint kept[K];
float dist[K];

#include "contact/nearest.glsl"

// The edges at end q (q within reach of e's midpoint m) within the radius of e = (a, b).
float edges_at(uint e, uvec2 ab, vec3 xa, vec3 xb, vec3 m, uint q, vec3 xq, float reach2,
               float nearest_e)
{
    uint base = contact_u.particle_count + 1u;
    for (uint o = particle_edge(q); o < particle_edge(q + 1u); o++) {
        uint f = particle_edge(base + o);
        uvec2 cd = contact_edge(f);
        if (cd.x == ab.x || cd.x == ab.y || cd.y == ab.x || cd.y == ab.y)
            continue; // sharing an end: adjacent
        uint r = cd.x == q ? cd.y : cd.x; // the other end
        vec3 xr = contact_x(r);
        if (r < q && within_reach(m, xr, reach2))
            continue; // tested through its lower end
        // Every point of an edge is within half its length of its midpoint.
        if (distance(m, 0.5 * (xq + xr)) >= contact_u.radius + 0.5 * (distance(xa, xb) + distance(xq, xr)))
            continue;
        float s, t;
        vec3 c1, c2;
        closest_segments(xa, xb, xq, xr, s, t, c1, c2);
        float d = length(c1 - c2);
        if (!(d < contact_u.radius))
            continue;
        nearest_e = min(nearest_e, d);
        if (s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0)
            INSERT(d, f);
    }
    return nearest_e;
}

void detect(uint e)
{
    uvec2 ab = contact_edge(e);
    vec3 xa = contact_x(ab.x), xb = contact_x(ab.y);
    vec3 m = 0.5 * (xa + xb);
    clear_nearest();
    float reach = contact_u.radius + 0.5 * (distance(xa, xb) + uintBitsToFloat(frame.longest));
    float reach2 = reach * reach;
    float nearest_e = INFINITY;
    ivec3 home = hash_cell(m);
    for (uint n = 0u; n < 27u; n++) {
        ivec3 cell = hash_neighbour_cell(home, n);
        uvec2 range = hash_range(cell);
        for (uint i = range.x; i < range.y; i++) {
            uvec4 entry = hash_entry_point(i);
            vec3 xq = uintBitsToFloat(entry.xyz);
            if (hash_cell(xq) == cell && within_reach(m, xq, reach2))
                nearest_e = edges_at(e, ab, xa, xb, m, entry.w, xq, reach2, nearest_e);
        }
    }
    nearest[contact_u.particle_count + e] = floatBitsToUint(nearest_e);
    for (uint k = 0u; k < K; k++)
        edge_contacts[e * K + k] = kept[k];
}

// Phase 1, before detection: the longest edge now, which bounds how near a corner of a near
// feature is (an atomic maximum on the float's bits, which order as non-negative floats do).
void measure_longest()
{
    float longest = 0.0;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uvec2 ab = contact_edge(pc.first + i);
        longest = max(longest, distance(contact_x(ab.x), contact_x(ab.y)));
    }
    atomicMax(frame.longest, floatBitsToUint(longest));
}

void main()
{
    if (pc.count == 0u)
        return;
    if (pc.phase == 1u) {
        measure_longest();
        return;
    }
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
        detect(pc.first + i);
}
