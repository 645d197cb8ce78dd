// The functions of edge detection (contact_edges.comp, whose phases they are; all of them in
// one workgroup in contact_edges_fused.comp). Include after contact/collide.glsl,
// contact/hash_common.glsl (the midpoints' hash) and the push block.
// Detection, edge against edge (lib/contact/collide.h): for every edge e, every edge sharing no
// end with it whose nearest point is within the contact radius of e at the start of the
// substep. Such an edge f has its midpoint within the radius plus half of each edge's length of
// e's midpoint (the longest edge measured in phase 1, which also writes the midpoints the edge
// hash is built from; its cells are that wide, contact_decide.comp), so the walk over the 27
// cells of the edge hash around e's midpoint visits every such edge, each once. In phases, as
// the faces' detection (contact_detect.comp):
//   1: (before the hashes are built) the longest edge, the midpoints and each edge's ends (for
//      the lists' loop); each edge's nearest distance and count of pairs reset; the triangles'
//      centroids for the faces' hash;
//   3 and 4: (after them) the first edge of each cell of the midpoints' hash listed (3), and
//      over those, each cell's list: the edges the walk from it steps over, for all of the
//      cell's edges (4; shared/layout.h: CVK_CELLS_*);
//   0: over every edge, the nearest distances alone, for the bounds of the edges' ends
//      (contact_bound.comp): each pair once, from e through the half of the block of cells
//      after e's (its cell's list: hash_walk_begin_half's order; in e's own cell from the lower
//      index), its distance an atomic minimum at both edges, on the float's bits, which order
//      as the non-negative floats do, so the result does not depend on thread timing — half the
//      walk of a query from each edge; where the pair's nearest points lie inside both
//      (elsewhere the pair is a vertex against an edge or a vertex, which the faces' detection
//      lists) the pair is kept in both edges' buckets of CVK_EDGE_BUCKET;
//   5: the same for the edges phase 0 put on its walk list: those whose cell's list did not
//      fit, by walking the hash, and the rest of those whose list held more to measure than
//      phase 0 keeps;
//   2: every edge's list: the nearest CVK_CONTACTS_PER_EDGE pairs of its bucket, nearest first,
//      equal distances by edge; an edge with more pairs than its bucket holds is put on the
//      work list of the LISTING pass, which walks all 27 cells around it and lists the same
//      (over a walk per edge with pairs, the buckets took the six-cloth pile's listing from 223
//      ms a frame to under 40).
#ifndef CONTACT_EDGES_GLSL
#define CONTACT_EDGES_GLSL

#include "contact/measure.glsl"


// Where the cell lists' entries start in the pool's buffer, in words: after the edges' ends.
uint pool_base()
{
    return 8u * contact_u.edge_count;
}

// The listing pass: a walk of all 27 cells around an edge that lists its nearest pairs (a
// specialisation constant; a variable of the fused dispatch, contact_edges_fused.comp).
#ifdef EDGES_FUSED
bool LISTING = false;
#else
layout(constant_id = 1) const bool LISTING = false;
#endif

const uint K = uint(CVK_CONTACTS_PER_EDGE);
const bool DEDUP = false;

uint kept[K];
float dist[K];

#include "contact/nearest.glsl"

// The pairs to list, kept as the distance pass meets them (the nearest buffer, after the
// distances): per edge a count, then per edge CVK_EDGE_BUCKET (edge, distance's bits) pairs;
// phase 2 lists from them, and an edge with more than its bucket holds is walked again by the
// LISTING pass.
uint pairs_count(uint e)
{
    return contact_u.particle_count + contact_u.edge_count + e;
}

uint pairs_at(uint e)
{
    return contact_u.particle_count + 2u * contact_u.edge_count + 2u * uint(CVK_EDGE_BUCKET) * e;
}

// The pair (e, f) at distance bits d in e's bucket.
void keep_pair(uint e, uint f, uint d)
{
    uint at = atomicAdd(nearest[pairs_count(e)], 1u);
    if (at < uint(CVK_EDGE_BUCKET)) {
        nearest[pairs_at(e) + 2u * at] = f;
        nearest[pairs_at(e) + 2u * at + 1u] = d;
    }
}

// Edge e's list: its pairs, nearest first, up to its first empty slot, where its readers stop
// (cloth_push.glsl, contact_bound.glsl). On lavapipe each storage store in a loop is a loop
// over the lanes, run as often as the longest lane's list: an edge without pairs stores one
// word instead of K (phase 2 against phase 0 in the same runs, the 40 x 40 contact drape:
// 0.130 -> 0.114; the same bits).
void store_list(uint e)
{
    for (uint k = 0u; k < K; k++) {
        edge_contacts[e * K + k] = kept[k];
        if (kept[k] == CVK_NO_CONTACT)
            break;
    }
}

// Whether edges (a, b) and (c, d) share an end: adjacent (or one edge), never a pair.
bool shares_end(uvec2 ab, uvec2 cd)
{
    return cd.x == ab.x || cd.x == ab.y || cd.y == ab.x || cd.y == ab.y;
}

// Edge f = (c, d) at xc, xd, of e = (a, b)'s instance: its distance to e if it shares no end
// with e (else INFINITY), and whether the nearest points lie inside both.
float ends_distance(uvec2 ab, vec3 xa, vec3 xb, uvec2 cd, vec3 xc, vec3 xd, out bool both)
{
    both = false;
    if (shares_end(ab, cd))
        return INFINITY;
    float s, t;
    vec3 c1, c2;
    closest_segments(xa, xb, xc, xd, s, t, c1, c2);
    both = s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0;
    return length(c1 - c2);
}

// Edge f, its midpoint near e = (a, b)'s: its distance to e if f shares no end with e and is
// of e's instance (else INFINITY), and whether the nearest points lie inside both.
float edge_distance(uvec2 ab, vec3 xa, vec3 xb, uint f, out bool both)
{
    both = false;
    uvec2 cd = contact_edge(f);
    if (contact_instance(cd.x) != contact_instance(ab.x))
        return INFINITY; // another instance: copies never touch one another
    return ends_distance(ab, xa, xb, cd, contact_x(cd.x), contact_x(cd.y), both);
}

// A pair within the radius met by the distance pass: f's nearest distance, and both buckets
// where the nearest points lie inside both edges.
void keep_near(uint e, uint f, float d, bool both)
{
    uint bits = floatBitsToUint(d);
    atomicMin(nearest[contact_u.particle_count + f], bits);
    if (both) {
        keep_pair(e, f, bits);
        keep_pair(f, e, bits);
    }
}

// The edges the distance pass's walk meets that may be within the radius (may_touch), kept
// and measured after it: on lavapipe a loop's body runs at every step for every lane (under a
// mask where a lane has nothing to do), so the segments' nearest points, the atomics and the
// buckets' writes run in a loop over the edges kept, not at every entry of the walk. An edge
// with more to measure walks again for the rest: more edges pass the boxes than the radius, and
// with room for 32 the pile walked again so often that its edge detection took 88 ms a frame
// instead of 52.
const uint NEAR = 64u;
uint near_f[NEAR];

// Whether the walk's entry is a pair to test: in the distance pass's half walk each pair is
// met once (in e's own cell from the lower index).
bool candidate(hash_walk w, uint e, vec3 m, uvec4 entry, bool here, float reach2)
{
    return here && (LISTING || w.n != HASH_HOME || entry.w > e) &&
           within_reach(m, uintBitsToFloat(entry.xyz), reach2);
}

// Edge f met by e's walk or list at distance d (both: the nearest points inside both edges):
// its pair with e if within the radius (the listing pass).
void meet(uint f, float d, bool both, inout float nearest_e)
{
    if (!(d < contact_u.radius))
        return;
    nearest_e = min(nearest_e, d);
    if (both)
        INSERT(d, f);
}

// e's box (its ends' lower and upper corners) and how near another edge's box must come for
// the pair to be measured: the radius with room for the rounding of the two measures.
struct edge_box {
    vec3 low, high;
    float near2;
};

edge_box box_of(vec3 xa, vec3 xb)
{
    edge_box b;
    b.low = min(xa, xb);
    b.high = max(xa, xb);
    vec3 far = max(abs(b.low), abs(b.high));
    float near = contact_u.radius * 1.001 + 1.0e-6 * (1.0 + max(far.x, max(far.y, far.z)));
    b.near2 = near * near;
    return b;
}

// Whether edge (xc, xd), which shares no end with e, may be within the radius of it: its box
// within the radius of e's box. The boxes' distance is at most the edges', so no pair within
// the radius is missed, and one more to measure costs only time. The distance pass tests this
// at every entry and measures only what passes, in a loop of its own: on lavapipe the branches
// of the segments' nearest points all run for every lane at every entry, while a loop runs as
// often as its longest lane (performance.md: the 40 x 40 contact drape's edge detection 2.40 ->
// 2.23 times its faces' in the same runs, the six-cloth pile's 55-57 -> 48 ms a frame in its
// first 60 frames; the same bits).
bool may_touch(edge_box b, vec3 xc, vec3 xd)
{
    vec3 gap = max(max(min(xc, xd) - b.high, b.low - max(xc, xd)), vec3(0.0));
    return dot(gap, gap) <= b.near2;
}

// Edge f, which may touch e: kept to measure after the loop, where there is room.
void keep_to_measure(uint f, inout uint found)
{
    if (found < NEAR)
        near_f[found] = f;
    found++;
}

// Where edge e's cell list starts in the pool, and its length (CVK_CELL_OVERFLOW: none).
uvec2 cell_list(uint e)
{
    uint at = CVK_CELLS_HEADER + contact_u.edge_count + 2u * e;
    return uvec2(cells[at], cells[at + 1u]);
}

// Whether a list's edge f (`home`: the walk met it in e's own cell) with its ends c and d
// (their positions' bits and indices) may touch e = (a, b), its midpoint m: the pair is to test
// (each pair once: in e's own cell from the lower index), f's midpoint is within reach, f
// shares no end with e and its box is near e's.
bool list_may_touch(uint e, uvec2 ab, edge_box b, vec3 m, float reach2, uint f, bool home,
                    uvec4 c, uvec4 d)
{
    vec3 xc = uintBitsToFloat(c.xyz), xd = uintBitsToFloat(d.xyz);
    return (!home || f > e) && within_reach(m, 0.5 * (xc + xd), reach2) &&
           !shares_end(ab, uvec2(c.w, d.w)) && may_touch(b, xc, xd);
}

// Whether the walk's edge f (a candidate entry of the hash) may touch e = (a, b): of e's
// instance, sharing no end with it, its box near e's.
bool walk_may_touch(uvec2 ab, edge_box b, uint f)
{
    uvec2 cd = contact_edge(f);
    return contact_instance(cd.x) == contact_instance(ab.x) && !shares_end(ab, cd) &&
           may_touch(b, contact_x(cd.x), contact_x(cd.y));
}

// Edge f, kept to measure by e = (a, b): the pair within the radius kept (keep_near) and e's
// nearest distance.
void measure_kept(uint e, uvec2 ab, vec3 xa, vec3 xb, uint f, inout float nearest_e)
{
    uvec4 c = imageLoad(edge_ends_t, int(2u * f)), d = imageLoad(edge_ends_t, int(2u * f + 1u));
    bool both;
    float dist = ends_distance(ab, xa, xb, uvec2(c.w, d.w), uintBitsToFloat(c.xyz),
                               uintBitsToFloat(d.xyz), both);
    if (dist < contact_u.radius) {
        nearest_e = min(nearest_e, dist);
        keep_near(e, f, dist, both);
    }
}

// Edge e's ends, midpoint and reach, what each pass over the edges starts from.
struct edge_query {
    uvec2 ab;
    vec3 xa, xb, m;
    float reach2;
    uint instance; // the slots of e's instance's edges
};

edge_query query_of(uint e)
{
    edge_query q;
    q.ab = contact_edge(e);
    q.xa = contact_x(q.ab.x);
    q.xb = contact_x(q.ab.y);
    q.m = 0.5 * (q.xa + q.xb);
    float reach = contact_u.radius + 0.5 * (distance(q.xa, q.xb) + uintBitsToFloat(frame.longest));
    q.reach2 = reach * reach;
    q.instance = contact_instance(q.ab.x);
    return q;
}

// The listing pass: e's nearest pairs, from a walk of all 27 cells around it.
void detect_listing(uint e)
{
    edge_query q = query_of(e);
    clear_nearest();
    float nearest_e = INFINITY;
    uvec4 entry;
    bool here;
    hash_walk w = hash_walk_begin(q.m, q.instance, q.reach2);
    while (hash_walk_step(w, q.m, q.reach2, entry, here)) {
        if (candidate(w, e, q.m, entry, here, q.reach2)) {
            bool both;
            float dist = edge_distance(q.ab, q.xa, q.xb, entry.w, both);
            meet(entry.w, dist, both, nearest_e);
        }
    }
    store_list(e);
}

// An edge for the walking pass (phase 5), on the list after the cells' (shared/layout.h).
void walk_append(uint e)
{
    uint at = atomicAdd(cells[CVK_CELLS_WALK + 3u], 1u);
    cells[CVK_CELLS_HEADER + 3u * contact_u.edge_count + at] = e;
    atomicMax(cells[CVK_CELLS_WALK], min(at / pc.per_group + 1u, 65535u));
}

// The distance pass (phase 0) for edge e: it loops over the list of e's cell, the walk's
// entries in its order (the home cell's marked), and measures the edges kept. An edge whose
// list did not fit goes to the walking pass instead, and one with more to measure than this
// pass keeps goes there for the rest: on lavapipe a walk in this pass ran its body under an
// empty mask for every SIMD vector where no edge needed it (the 40 x 40 contact drape's and
// the six-cloth pile's edge detection 0.95-0.96 of before against their faces'; the same
// bits).
void detect(uint e)
{
    edge_query q = query_of(e);
    edge_box box = box_of(q.xa, q.xb);
    float nearest_e = INFINITY;
    uint found = 0u;
    uvec2 list = cell_list(e);
    bool walk = list.y == CVK_CELL_OVERFLOW;
    // A list holds e's instance's edges only (gather_cells), and their ends come from one
    // array at detection (measure_longest): three loads an entry instead of seven. Two entries
    // a step, both entries' loads before either's test: a CPU device runs an invocation's reads
    // one after another, and the second entry's gathers overlap the first's (the flat 40 x 40
    // drape's edge detection 4.4 -> 4.1 ms a detection, the six-cloth pile's 14.2 -> 12.3 in
    // its first 20 frames; four entries a step, each loaded just before its test, gained
    // nothing).
    for (uint k = 0u; !walk && k < list.y; k += 2u) {
        bool second = k + 1u < list.y;
        uint listed0 = CELL_POOL(pool_base() + list.x + k);
        uint listed1 = CELL_POOL(pool_base() + list.x + (second ? k + 1u : k));
        uint f0 = listed0 & ~CVK_CELL_HOME, f1 = listed1 & ~CVK_CELL_HOME;
        uvec4 c0 = imageLoad(edge_ends_t, int(2u * f0)), d0 = imageLoad(edge_ends_t, int(2u * f0 + 1u));
        uvec4 c1 = imageLoad(edge_ends_t, int(2u * f1)), d1 = imageLoad(edge_ends_t, int(2u * f1 + 1u));
        if (list_may_touch(e, q.ab, box, q.m, q.reach2, f0, listed0 >= CVK_CELL_HOME, c0, d0))
            keep_to_measure(f0, found);
        if (second && list_may_touch(e, q.ab, box, q.m, q.reach2, f1, listed1 >= CVK_CELL_HOME, c1, d1))
            keep_to_measure(f1, found);
    }
    if (walk || found > NEAR)
        walk_append(e);
    for (uint i = 0u; i < min(found, NEAR); i++)
        measure_kept(e, q.ab, q.xa, q.xb, near_f[i], nearest_e);
    if (nearest_e < INFINITY)
        atomicMin(nearest[contact_u.particle_count + e], floatBitsToUint(nearest_e));
}

// The walking pass (phase 5) for edge e of the distance pass's walk list. Where e's list did
// not fit: the same pairs from a walk of the half block of cells after e's, the edges kept
// measured after it, and where there are more than it keeps, the same walk again, the edges
// past those measured as they are met (a lane with no more ends this loop at its first step).
// Where the list held more than phase 0 kept (which measured those): the list again, the
// edges past those measured as they are met.
void detect_walk(uint e)
{
    edge_query q = query_of(e);
    edge_box box = box_of(q.xa, q.xb);
    float nearest_e = INFINITY;
    uvec2 list = cell_list(e);
    bool walk = list.y == CVK_CELL_OVERFLOW;
    uint found = walk ? 0u : NEAR + 1u;
    uvec4 entry;
    bool here;
    hash_walk w = hash_walk_begin_half(q.m, q.instance);
    while (walk && hash_walk_step(w, q.m, q.reach2, entry, here)) {
        if (candidate(w, e, q.m, entry, here, q.reach2) && walk_may_touch(q.ab, box, entry.w))
            keep_to_measure(entry.w, found);
    }
    for (uint i = 0u; walk && i < min(found, NEAR); i++)
        measure_kept(e, q.ab, q.xa, q.xb, near_f[i], nearest_e);
    w = hash_walk_begin_half(q.m, q.instance);
    uint met = 0u;
    for (; walk && found > NEAR && hash_walk_step(w, q.m, q.reach2, entry, here);) {
        if (candidate(w, e, q.m, entry, here, q.reach2) && walk_may_touch(q.ab, box, entry.w) &&
            met++ >= NEAR)
            measure_kept(e, q.ab, q.xa, q.xb, entry.w, nearest_e);
    }
    for (uint k = 0u; !walk && k < list.y; k++) {
        uint listed = CELL_POOL(pool_base() + list.x + k), f = listed & ~CVK_CELL_HOME;
        uvec4 c = imageLoad(edge_ends_t, int(2u * f)), d = imageLoad(edge_ends_t, int(2u * f + 1u));
        if (list_may_touch(e, q.ab, box, q.m, q.reach2, f, listed >= CVK_CELL_HOME, c, d) &&
            met++ >= NEAR)
            measure_kept(e, q.ab, q.xa, q.xb, f, nearest_e);
    }
    if (nearest_e < INFINITY)
        atomicMin(nearest[contact_u.particle_count + e], floatBitsToUint(nearest_e));
}

// The walking pass over its list (phase 5).
void walk_listed()
{
    uint count = cells[CVK_CELLS_WALK + 3u], start = CVK_CELLS_HEADER + 3u * contact_u.edge_count;
    for (uint i = gl_GlobalInvocationID.x; i < count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
        detect_walk(cells[start + i]);
}

// The instance of the edge at entry (its first end's): the salt of its slot.
uint edge_instance(uint f)
{
    return contact_instance(contact_edge(f).x);
}

// Whether the hash's entry (a midpoint and its edge) is of that cell and instance: a slot holds
// every cell and instance that hash to it.
bool in_cell(uvec4 entry, ivec3 cell, uint instance)
{
    return hash_cell(uintBitsToFloat(entry.xyz)) == cell && edge_instance(entry.w) == instance;
}

// The first edge, in the slot's order, of edge e's cell and instance: the one that gathers the
// cell's list (which one does not change the list's entries, only where in the pool it lies
// and their order, which no reader depends on: detect measures every entry that may touch).
uint first_of_cell(uint e, ivec3 cell, uint instance)
{
    uvec2 range = hash_range(cell, instance);
    for (uint k = range.x; k < range.y; k++) {
        uvec4 entry = hash_entry_point(k);
        if (in_cell(entry, cell, instance))
            return entry.w;
    }
    return e;
}

// Phase 3, after the midpoints' hash: the first edge of each cell on the list of phase 4.
void find_cells()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint e = pc.first + i, instance = edge_instance(e);
        if (first_of_cell(e, hash_cell(hash_point(e)), instance) != e)
            continue;
        uint at = atomicAdd(cells[CVK_CELLS_COUNT], 1u);
        cells[CVK_CELLS_HEADER + at] = e;
        atomicMax(cells[0], min(at / pc.per_group + 1u, 65535u));
    }
}

// How near a cell of the midpoints' hash a midpoint must be to go on the cell's list: the longest
// reach (the radius and the longest edge, detect's), so every midpoint within reach of an edge
// whose midpoint is in the cell is within it of the cell's box (hash_cell_near, which also
// widens the box against rounding). A cell's list holds only these: of the 13 cells after the
// home cell, the corners of the block lie partly out of reach (the six-cloth pile's first 40
// frames: edge detection 129-135 -> 119-120 ms a frame, the same bits; the flat 40 x 40
// drape's unchanged).
float cell_reach2()
{
    float reach = contact_u.radius + uintBitsToFloat(frame.longest);
    return reach * reach;
}

// Whether the walk's entry goes on a cell's list: in the visited cell, within reach of the
// cell's box, and of the cell's instance (a slot holds every instance that hashes to it).
bool listable(uvec4 entry, bool here, ivec3 cell, float reach2, uint instance)
{
    return here && hash_cell_near(cell, uintBitsToFloat(entry.xyz), reach2) &&
           edge_instance(entry.w) == instance;
}

// Phase 4, over those: each cell's list, the entries of the half block a walk from it steps
// over that can be within reach of the cell (in the walk's order, the home cell's marked), for
// every edge of the cell; where the pool is full, the cell's edges walk.
void gather_cells()
{
    uint count = cells[CVK_CELLS_COUNT];
    for (uint i = gl_GlobalInvocationID.x; i < count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint e = cells[CVK_CELLS_HEADER + i], instance = edge_instance(e);
        vec3 m = hash_point(e);
        ivec3 cell = hash_cell(m);
        float reach2 = cell_reach2();
        uvec4 entry;
        bool here;
        // Room for every entry of the slots the walk visits, taken before it, so that one walk
        // writes the list (entries of other cells or out of reach leave some room unused).
        uint room = 0u;
        for (uint n = HASH_HOME; n < 27u; n++) {
            uvec2 slot = hash_range(hash_neighbour_cell(cell, n), instance);
            room += slot.y - slot.x;
        }
        uint start = atomicAdd(cells[CVK_CELLS_POOL_USED], room);
        // room <= 14 edge counts (a slot holds each edge once at most), under the pool's size
        bool fits = start <= uint(CVK_CELL_POOL_PER_EDGE) * contact_u.edge_count - room;
        uint length = 0u;
        // A loop over the cells with a loop over each cell's entries in it: one loop whose
        // every step either moved to the next cell or took an entry ran both at every step on
        // lavapipe (as the faces' walk did: performance.md).
        hash_walk w = hash_walk_begin_half(m, instance);
        for (; fits && w.n < 27u; hash_walk_next_cell(w, m, -1.0)) {
            uint home = w.n == HASH_HOME ? CVK_CELL_HOME : 0u;
            while (w.range.x < w.range.y) {
                entry = hash_walk_entry(w, here);
                if (listable(entry, here, cell, reach2, instance)) {
                    uint at = pool_base() + start + length++;
                    CELL_POOL_WORD(at) = entry.w | home;
                }
            }
        }
        uvec2 range = hash_range(cell, instance);
        for (uint j = range.x; j < range.y; j++) {
            uvec4 member = hash_entry_point(j);
            if (!in_cell(member, cell, instance))
                continue;
            uint at = CVK_CELLS_HEADER + contact_u.edge_count + 2u * member.w;
            cells[at] = start;
            cells[at + 1u] = fits ? length : CVK_CELL_OVERFLOW;
        }
    }
}

// Phase 2, after the distances: every edge's list, its nearest K from its bucket (the same
// list as the LISTING walk keeps: each pair is met once, and the nearest K, equal distances by
// edge, do not depend on the order the atomics filled the bucket in); an edge whose bucket ran
// over put on the LISTING pass's work list.
void list_near()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint e = pc.first + i;
        uint count = NEAREST(pairs_count(e));
        clear_nearest();
        for (uint j = 0u; count <= uint(CVK_EDGE_BUCKET) && j < count; j++)
            INSERT(uintBitsToFloat(NEAREST(pairs_at(e) + 2u * j + 1u)), NEAREST(pairs_at(e) + 2u * j));
        store_list(e);
        if (count > uint(CVK_EDGE_BUCKET))
            list_append(CVK_LIST_EDGE_PAIRS_GROUPS, e, pc.per_group);
    }
}

#endif
