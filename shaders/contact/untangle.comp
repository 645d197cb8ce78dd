#version 450
#extension GL_GOOGLE_include_directive : require
// The untangling step of a search (lib/contact/collide.h, "Untangling"): which particles lie in a
// region of their cloth that has passed through another surface, found from the positions
// alone (global intersection analysis, Baraff, Witkin and Kass 2003), so the search can hold
// them back towards the side they came from instead of keeping them where they are.
//
// Where two surfaces intersect, the intersection curve cuts the edges of each that cross a
// face of the other. The cloth's particles joined by edges that are not cut fall into
// regions; a cloth with no intersection is one region, and a region smaller than the cloth's
// largest, enclosed by cut edges, is the part that went through (the small one: a fold's tip
// pushed through a layer, a corner through a stack). Such a region's particles are on the
// wrong side of the faces that cut it, and their pairs with those faces are listed with the
// other side (CVK_UNTANGLE_PAIR); the contact pass brings them back a little each substep
// (collide.glsl, collide_triangle), and later searches keep that side while the pair lasts
// (contact_detect.comp).
//
// Phases (push.phase), each only at a substep that searches, after the search:
// 0 (the particles with candidates): each own edge tested against the particle's candidate
//   triangles; a cut marks the edge at both its ends, with the cutting triangle's cloth;
// 1 (one invocation): the indirect command of the phases below, none when no edge is cut;
// 2, 3, 4 (every particle): one round of labels: the lowest label's label (pointer jumping)
//   among the particle and its neighbours across edges that are not cut; 2 the first, from
//   the particles' own indices, into the second array; 3 from the second into the first, 4
//   back (the rounds alternate, the last writing the first array);
// 5 (every particle): each region's size and cutters; a region with a neighbour of another
//   label across an uncut edge has not converged in the rounds recorded and counts as large;
// 6 (every region's lowest particle): the largest converged region of each cloth;
// 7 (the particles with candidates): the pairs of a particle in an enclosed region (a
//   converged region at most a quarter of its cloth's largest, CVK_UNTANGLE_SMALLER) with
//   the faces over it of the cloths that cut the region, marked and given the side the
//   particle is not on;
// 8 (every particle): the accumulated arrays cleared for the next search.
// Every phase is a function of the one before (labels are double-buffered, the counts are
// atomic sums), so the result does not depend on thread timing or dispatch shape.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

const uint K = uint(CVK_CONTACTS_PER_PARTICLE);

uint at(uint array, uint p)
{
    return uint(CVK_LIST_HEADER) + (2u + array) * contact_u.particle_count + p;
}

uint cloth_at(uint which, uint c) // 0: the largest converged region, 1: one did not converge
{
    uint n = contact_u.particle_count;
    uint arrays_end = uint(CVK_LIST_HEADER) + (2u + uint(CVK_UNTANGLE_ARRAYS)) * n;
    return arrays_end + which * contact_u.cloth_count + c;
}

uint cloth_of(uint p) { return uint(contact_rest(p).w); }

// Whether segment (p, q) crosses the inside of triangle (a, b, c): its ends strictly on
// either side of the plane, the crossing point strictly inside the three edges.
bool cuts(vec3 p, vec3 q, vec3 a, vec3 b, vec3 c)
{
    vec3 n = cross(b - a, c - a);
    float dp = dot(p - a, n), dq = dot(q - a, n);
    if (!((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)))
        return false;
    vec3 x = p + (dp / (dp - dq)) * (q - p);
    return dot(cross(b - a, x - a), n) > 0.0 && dot(cross(c - b, x - b), n) > 0.0 &&
           dot(cross(a - c, x - c), n) > 0.0;
}

void mark(uint p, uint slot, uint cloth_bit)
{
    if (slot < 32u)
        atomicOr(lists[at(CVK_UNTANGLE_CUT_LOW, p)], 1u << slot);
    else
        atomicOr(lists[at(CVK_UNTANGLE_CUT_HIGH, p)], 1u << (slot - 32u));
    atomicOr(lists[at(CVK_UNTANGLE_CUTTERS, p)], cloth_bit);
}

bool is_cut(uint p, uint slot)
{
    uint word = lists[at(slot < 32u ? CVK_UNTANGLE_CUT_LOW : CVK_UNTANGLE_CUT_HIGH, p)];
    return (word & (1u << (slot & 31u))) != 0u;
}

// Phase 0: p's own edges against p's candidate triangles.
void find_cuts(uint p)
{
    vec3 xp = contact_x(p);
    uint slots = own_slots(p);
    for (uint k = 0u; k < K; k++) {
        uint e = contact_entry(p * K + k);
        if (e == CVK_NO_CONTACT)
            break;
        if ((e & CVK_EDGE_PAIR) != 0u)
            continue;
        uvec4 tri = contact_triangle((e & ~CVK_UNTANGLE_PAIR) >> 1u);
        if (p == tri.x || p == tri.y || p == tri.z) // a small collision.exclusion lets these in
            continue;
        vec3 a = contact_x(tri.x), b = contact_x(tri.y), c = contact_x(tri.z);
        uint cloth_bit = 1u << (cloth_of(tri.x) & 31u);
        for (uint i = 0u; i < slots; i++) {
            uint r;
            bool border;
            if (!own_edge(p, i, r, border) || r == tri.x || r == tri.y || r == tri.z ||
                !cuts(xp, contact_x(r), a, b, c))
                continue;
            mark(p, i, cloth_bit);
            for (uint j = 0u, rs = own_slots(r); j < rs; j++) { // the same edge from r
                uint back;
                if (own_edge(r, j, back, border) && back == p)
                    mark(r, j, cloth_bit);
            }
            lists[CVK_LIST_UNTANGLE_CUTS] = 1u; // a flag: every writer writes the same
        }
    }
}

// In round `from` (2: the particles' own indices; 3: the second array; 4: the first), the
// label of q's label: a particle of q's region (labels never cross a cut edge).
uint jumped(uint q, uint from)
{
    if (from == 2u)
        return q;
    uint array = from == 3u ? CVK_UNTANGLE_LABEL_NEXT : CVK_UNTANGLE_LABEL;
    return lists[at(array, lists[at(array, q)])];
}

// Phase 5: whether p's label agrees with its neighbours' across uncut edges and is a root.
bool settled(uint p)
{
    uint l = lists[at(CVK_UNTANGLE_LABEL, p)];
    bool same = lists[at(CVK_UNTANGLE_LABEL, l)] == l;
    for (uint i = 0u, slots = own_slots(p); i < slots; i++) {
        uint r;
        bool border;
        if (own_edge(p, i, r, border) && !is_cut(p, i))
            same = same && lists[at(CVK_UNTANGLE_LABEL, r)] == l;
    }
    return same;
}

void per_particle(uint p)
{
    uint phase = pc.phase;
    if (phase >= 2u && phase <= 4u) {
        uint lowest = jumped(p, phase);
        for (uint i = 0u, slots = own_slots(p); i < slots; i++) {
            uint r;
            bool border;
            if (own_edge(p, i, r, border) && !is_cut(p, i))
                lowest = min(lowest, jumped(r, phase));
        }
        lists[at(phase == 3u ? CVK_UNTANGLE_LABEL : CVK_UNTANGLE_LABEL_NEXT, p)] = lowest;
    } else if (phase == 5u) {
        uint l = lists[at(CVK_UNTANGLE_LABEL, p)];
        atomicAdd(lists[at(CVK_UNTANGLE_SIZE, l)], 1u);
        atomicOr(lists[at(CVK_UNTANGLE_REGION_CUTTERS, l)], lists[at(CVK_UNTANGLE_CUTTERS, p)]);
        if (!settled(p)) {
            atomicOr(lists[at(CVK_UNTANGLE_SIZE, l)], CVK_UNTANGLE_SPLIT);
            atomicOr(lists[cloth_at(1u, cloth_of(p))], 1u);
        }
    } else if (phase == 6u) {
        uint size = lists[at(CVK_UNTANGLE_SIZE, p)];
        if (lists[at(CVK_UNTANGLE_LABEL, p)] == p && (size & CVK_UNTANGLE_SPLIT) == 0u)
            atomicMax(lists[cloth_at(0u, cloth_of(p))], size);
    } else if (phase == 8u) { // the labels are written whole by the rounds before any read
        lists[at(CVK_UNTANGLE_CUT_LOW, p)] = 0u;
        lists[at(CVK_UNTANGLE_CUT_HIGH, p)] = 0u;
        lists[at(CVK_UNTANGLE_CUTTERS, p)] = 0u;
        lists[at(CVK_UNTANGLE_SIZE, p)] = 0u;
        lists[at(CVK_UNTANGLE_REGION_CUTTERS, p)] = 0u;
        if (p < contact_u.cloth_count) {
            lists[cloth_at(0u, p)] = 0u;
            lists[cloth_at(1u, p)] = 0u;
        }
    }
}

// Phase 7: the cloths (bit c % 32) whose faces enclose p's region, where that region
// converged and is at most 1 / CVK_UNTANGLE_SMALLER of its cloth's largest (a region that did
// not converge counts as large, and so does every region of a cloth where one did not).
uint enclosing(uint p)
{
    uint l = lists[at(CVK_UNTANGLE_LABEL, p)];
    uint size = lists[at(CVK_UNTANGLE_SIZE, l)];
    uint cloth = cloth_of(p);
    uint largest = lists[cloth_at(1u, cloth)] != 0u ? 0xffffffffu : lists[cloth_at(0u, cloth)];
    bool enclosed = (size & CVK_UNTANGLE_SPLIT) == 0u &&
                    size <= largest / uint(CVK_UNTANGLE_SMALLER);
    return enclosed ? lists[at(CVK_UNTANGLE_REGION_CUTTERS, l)] : 0u;
}

void mark_pairs(uint p)
{
    uint through = enclosing(p);
    if (through == 0u)
        return;
    vec3 xp = contact_x(p);
    for (uint k = 0u; k < K; k++) {
        uint e = contact_entry(p * K + k);
        if (e == CVK_NO_CONTACT)
            break;
        if ((e & CVK_EDGE_PAIR) != 0u)
            continue;
        uint t = (e & ~CVK_UNTANGLE_PAIR) >> 1u;
        uvec4 tri = contact_triangle(t);
        if ((through & (1u << (cloth_of(tri.x) & 31u))) == 0u)
            continue;
        vec3 a = contact_x(tri.x), b = contact_x(tri.y), c = contact_x(tri.z);
        vec3 w;
        vec3 closest = closest_on_triangle(xp, a, b, c, w);
        if (!(w.x > 0.0 && w.y > 0.0 && w.z > 0.0))
            continue; // beside the face: the side it starts each substep on (collide_triangle)
        uint other = 1u - triangle_side(xp, closest, a, b, c);
        contacts[p * K + k] = (t << 1u) | CVK_UNTANGLE_PAIR | other;
    }
}

void main()
{
    if (pc.count == 0u)
        return;
    if (pc.phase == 1u) { // none at a substep that does not search
        if (gl_GlobalInvocationID.x != 0u)
            return;
        uint groups = (contact_u.particle_count + pc.per_group - 1u) / pc.per_group;
        bool cut = frame.search != 0u && lists[CVK_LIST_UNTANGLE_CUTS] > 0u;
        lists[CVK_LIST_UNTANGLE_GROUPS] = cut ? min(groups, 65535u) : 0u;
        lists[CVK_LIST_UNTANGLE_GROUPS + 1] = 1u;
        lists[CVK_LIST_UNTANGLE_GROUPS + 2] = 1u;
        lists[CVK_LIST_UNTANGLE_CUTS] = 0u;
        return;
    }
    if (frame.search == 0u)
        return;
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (pc.phase == 0u || pc.phase == 7u) {
        uint listed = lists[CVK_LIST_CONTACT_COUNT];
        uint base = contact_list_base();
        bool cut = pc.phase == 7u && lists[CVK_LIST_UNTANGLE_GROUPS] > 0u;
        for (uint i = gl_GlobalInvocationID.x; i < listed; i += stride) {
            if (pc.phase == 0u)
                find_cuts(lists[base + i]);
            else if (cut)
                mark_pairs(lists[base + i]);
        }
        return;
    }

    for (uint p = gl_GlobalInvocationID.x; p < contact_u.particle_count; p += stride)
        per_particle(p);
}
