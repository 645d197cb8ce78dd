// The functions of the faces' detection (contact_detect.comp; contact_faces_fused.comp after the
// decision and the faces' hash build, where the plan fuses). Include after contact/collide.glsl,
// contact/hash_common.glsl (the centroids' hash) and the push block.
// Detection, vertex against faces (lib/contact/collide.h): for every particle p, every triangle
// not around p whose nearest point is within the contact radius of p at the start of the
// substep (x_n). Every point of a triangle lies within its corners' reach of its centroid (the
// farthest a corner is from it), so a triangle that near has its centroid within the radius
// plus the largest reach of p (both measured by contact_edges.comp phase 1, which writes the
// centroids the faces' hash is built from; its cells are that wide, contact_decide.comp), and
// the walk over the 27 hash cells around p visits it, once (of p's instance: the scene's
// copies never touch one another, and a triangle of another is passed over). Each pair found:
//   - p's nearest distance and each corner's (an atomic minimum on the float's bits, which
//     order as the non-negative floats do, so the result does not depend on thread timing)
//     take its distance: the bounds come from them (contact_bound.comp);
//   - p's list keeps the feature the nearest point lies on — the face, an edge or a corner, so a
//     point beside an edge shared by two faces is listed once — nearest first, equal distances by
//     feature, the CVK_CONTACTS_PER_PARTICLE nearest.
#ifndef CONTACT_DETECT_GLSL
#define CONTACT_DETECT_GLSL

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

// Triangle t, its centroid within reach of p: its distance from p where it is not around p
// and of p's instance (else INFINITY), and the feature its point nearest p lies on.
float triangle_distance(uint p, vec3 xp, uint t, uint instance, out uint feature)
{
    feature = CVK_NO_CONTACT;
    uvec4 tri = contact_triangle(t);
    if (tri.x == p || tri.y == p || tri.z == p)
        return INFINITY; // around p: adjacent, never in contact
    if (contact_instance(tri.x) != instance)
        return INFINITY; // another instance's, in a slot p's shares
    vec3 a = contact_x(tri.x), b = contact_x(tri.y), c = contact_x(tri.z);
    // Every point of the triangle is within its corners' reach of its centroid: a triangle
    // whose centroid is farther than that plus the radius is not near.
    vec3 g = triangle_centroid(a, b, c);
    vec3 pg = xp - g;
    float near = contact_u.radius + corner_reach(a, b, c, g);
    if (dot(pg, pg) >= near * near)
        return INFINITY;
    vec3 w;
    float d = length(xp - closest_on_triangle(xp, a, b, c, w));
    feature = feature_of(t, tri, w);
    return d;
}

// Pair (p, t) within the radius at distance d, p's nearest point on `feature`: each corner's
// nearest distance, and p's list.
void keep_hit(uint t, uint feature, float d)
{
    uvec4 tri = contact_triangle(t);
    uint bits = floatBitsToUint(d);
    atomicMin(nearest[tri.x], bits);
    atomicMin(nearest[tri.y], bits);
    atomicMin(nearest[tri.z], bits);
    INSERT(d, feature);
}

// Triangles found within reach, tested a batch at a time, and the pairs within the radius kept
// after the walk. On lavapipe a loop's body, and every loop nested in it, runs at each of its
// steps for every lane, under a mask where a lane has nothing to do: so the walk only gathers
// a batch of triangles, and the tests run in a loop after it (not called from inside the walk
// when a batch fills: that ran the tests' loop once at every entry), and the atomics and the
// list in a loop over the pairs after all the tests. Against the tests inside the walk, the
// flat 40 x 40 drape's one detection took 2.3 ms instead of 5.0 and the six-cloth pile's faces
// at every substep (frames 41 and 42) 87 ms a frame instead of 218. A particle with more pairs
// than HITS walks again for the rest. A pair's triangle alone is kept, its distance and
// feature measured again after the tests (the same function, the same bits): a store at a
// variable index of a private array is a loop over the lanes on lavapipe (contact_edges.glsl).
const uint BATCH = 32u; // at most 32: test_batch marks its pairs as bits of a word
uint found[BATCH];
const uint HITS = 32u;
uint hit_t[HITS];
uint hits; // reset by each detect: an invocation may detect for several particles

// The tests mark the batch's pairs as bits of a word (BATCH is 32), and a loop over the marks
// after them keeps the pairs: the store into hit_t, a loop over the lanes, ran under a mask at
// every test (the 40 x 40 contact drape's faces against its edges' distances in the same runs
// 0.65 -> 0.63, against its solve 0.93 -> 0.86; the six-cloth pile's within the noise; the
// same bits).
float test_batch(uint p, vec3 xp, uint count, uint instance, float nearest_p)
{
    uint marks = 0u;
    for (uint i = 0u; i < count; i++) {
        uint feature;
        float d = triangle_distance(p, xp, found[i], instance, feature);
        bool pair = d < contact_u.radius;
        marks |= pair ? 1u << i : 0u;
        nearest_p = pair ? min(nearest_p, d) : nearest_p;
    }
    for (; marks != 0u; marks &= marks - 1u) {
        if (hits < HITS)
            hit_t[hits] = found[findLSB(marks)];
        hits++;
    }
    return nearest_p;
}

// The walk's next batch of triangles within reach of xp (their indices in found), cell by
// cell: a loop over the cells and in it a loop over a cell's entries, rather than
// hash_walk_step's one loop over both, where every step ran the move to the next cell (its
// box, its slot's range) and the entry's loads, one of them under a mask (the faces against
// the edges' distances in the same runs: the six-cloth pile's 0.60 -> 0.52, the 40 x 40
// contact drape's 0.64 -> 0.61; the same bits). The cells are stepped over and their entries
// met in hash_walk_step's order.
uint gather_batch(inout hash_walk w, vec3 xp, float reach2)
{
    uint count = 0u;
    while (w.n < 27u && count < BATCH) {
        while (w.range.x < w.range.y && count < BATCH) {
            bool here;
            uvec4 entry = hash_walk_entry(w, here);
            if (here && within_reach(xp, uintBitsToFloat(entry.xyz), reach2)) {
                found[count] = entry.w;
                count++;
            }
        }
        if (w.range.x == w.range.y)
            hash_walk_next_cell(w, xp, reach2);
    }
    return count;
}

void detect(uint p)
{
    vec3 xp = contact_x(p);
    clear_nearest();
    hits = 0u;
    // The cells are as wide as the reach: the radius plus the farthest a corner is from its
    // centroid (contact_decide.comp).
    float reach = HASH_PARAMS.cell_size;
    float reach2 = reach * reach;
    float nearest_p = INFINITY;
    uint instance = contact_instance(p); // copies never touch one another
    // The slots of p's instance's triangles, the cells out of reach of p stepped over.
    hash_walk w = hash_walk_begin(xp, instance, reach2);
    uvec4 entry;
    bool here;
    for (bool more = true; more;) {
        uint count = gather_batch(w, xp, reach2);
        more = w.n < 27u;
        nearest_p = test_batch(p, xp, count, instance, nearest_p);
    }
    for (uint i = 0u; i < min(hits, HITS); i++) {
        uint feature;
        float d = triangle_distance(p, xp, hit_t[i], instance, feature);
        keep_hit(hit_t[i], feature, d);
    }
    // More pairs than the list holds (a crowd of layers): the same walk again, the pairs past
    // the list's kept as they are met (a lane with no more ends this loop at its first step).
    w = hash_walk_begin(xp, instance, reach2);
    for (uint met = 0u; hits > HITS && hash_walk_step(w, xp, reach2, entry, here);) {
        if (!here || !within_reach(xp, uintBitsToFloat(entry.xyz), reach2))
            continue;
        uint feature;
        float d = triangle_distance(p, xp, entry.w, instance, feature);
        if (d < contact_u.radius && met++ >= HITS)
            keep_hit(entry.w, feature, d);
    }
    if (nearest_p < INFINITY)
        atomicMin(nearest[p], floatBitsToUint(nearest_p));
    // p's list up to its first empty slot, where its readers stop (cloth_push.glsl,
    // contact_bound.glsl), and each pair on its feature's corners' side lists. The loop ends
    // there: on lavapipe its body, the side lists' atomics and stores, ran under a mask at
    // every slot of every list (the 40 x 40 contact drape's faces against its edges'
    // distances in the same runs 0.68 -> 0.64, the six-cloth pile's 0.62 -> 0.61; the same
    // bits).
    for (uint k = 0u; k < K; k++) {
        contacts[p * K + k] = kept[k];
        if (kept[k] == CVK_NO_CONTACT)
            break;
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

#endif
