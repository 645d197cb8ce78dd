#version 450
#extension GL_GOOGLE_include_directive : require
// Particle–triangle candidates, at a search (lib/contact/collide.h): for each free particle, the
// triangles of any cloth within the detection radius at the start of the substep (x_n),
// skipping triangles of its own cloth that were near it at rest. A triangle within the radius
// has a corner within the radius plus 1.5 × the longest edge / √3 (the farthest any point of a
// triangle is from its nearest corner, with the cloth stretched by up to 50 %;
// lib/contact/collide_passes.c),
// the hash's cell size: the walk over the 27 cells around the particle visits every such
// corner, and the triangles around each corner that is neither too far nor near at rest are
// tested, each once, through the lowest-index corner within reach. Where the cloth is not
// folded every corner within reach is near at rest, and no triangle is tested at all. The
// nearest CVK_CONTACTS_PER_PARTICLE are kept, with the side of the triangle the particle
// belongs on: where it is over the face, the side the last list held for the pair, if it held
// it (so a particle that crossed the face since is brought back, solvers/pd_contact.glsl; with the
// untangling step's mark, untangle.comp), else the side it is on; equally near ones by
// triangle index, so the list depends neither on thread timing nor on the order of the walk.
//
// LANES invocations share a particle (lib/sim/sim.c: one on a CPU device, several on a GPU, where
// one invocation's walk is a long chain of dependent reads and a few thousand of them leave
// the device idle): each walks every LANES-th entry of the cells with its own nearest list,
// and the first merges the others' lists into its own. A triangle is tested once whichever
// lane holds its corner, and the lists are ordered by (distance, item), so the merged list is
// the one a single invocation finds.
layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint LANES = 1u;
// collision.edges: edge pairs too (below).
layout(constant_id = 2) const bool EDGES = false;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
#define HASH_SET 1
#include "contact/hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

const uint K = uint(CVK_CONTACTS_PER_PARTICLE);
const float INFINITY = 3.0e38; // beyond any distance kept

// Within reach of xp: the walk's test and the dedup's, one expression (precise: no
// contraction, so both give the same answer for the same corner).
bool within_reach(vec3 xp, vec3 x, float reach2)
{
    precise vec3 d = x - xp;
    precise float d2 = dot(d, d);
    return d2 < reach2;
}

// Of one cloth and near at rest (lib/contact/collide.c, cvk_collide_rest_near) for one corner.
bool corner_rest_near(vec4 rp, vec4 rq, float e2)
{
    vec3 d = rq.xyz - rp.xyz;
    return rq.w == rp.w && dot(d, d) < e2;
}

// Whether entry q of `cell` is a corner the search goes on from: in that cell (not another
// sharing its slot, which is visited through its own), within reach, and not near p at rest
// (then all its triangles are: the common case inside one cloth).
bool near_corner(vec3 xp, vec4 rp, ivec3 cell, uint q, vec3 xq, float reach2, float e2)
{
    return hash_cell(xq) == cell && within_reach(xp, xq, reach2) &&
           !corner_rest_near(rp, contact_rest(q), e2);
}

// Whether the kept candidate (dist_k, kept_k) comes after (d, item) in the list.
bool after(float dist_k, uint kept_k, float d, uint item)
{
    return dist_k > d || (dist_k == d && kept_k > item);
}

// collision.edges: the nearest KE edge pairs, kept apart from the triangles and written after
// them (as many of the K places as they fill; the triangles keep the others).
// The lanes' lists, for the first lane of each particle to merge (a uint and a float per
// candidate, 128 bytes per invocation, 160 with edge pairs after the triangles: lib/sim/sim.c
// keeps one lane where the device's shared memory does not hold them).
const uint KE = EDGES ? uint(CVK_EDGE_CONTACTS_PER_PARTICLE) : 1u;
const uint SLOTS = K + (EDGES ? KE : 0u);
const uint SHARED_LISTS = (LANES > 1u ? gl_WorkGroupSize.x : 1u) * SLOTS;
shared uint lane_kept[SHARED_LISTS];
shared float lane_dist[SHARED_LISTS];

// (d, item) into the nearest K, if it is among them (ties, as at a corner shared by several
// triangles: the lower triangle first, so the list does not depend on the order of the walk).
// Every index is a constant once the loop unrolls: a variable index into a private array is a
// per-lane memory loop on lavapipe (the search took 1.4x as long with the usual insertion
// loop).
// (A macro, not a function: lavapipe copied the arrays of a function's inout parameters at
// every call, which made the search 1.6x as long.)
#define INSERT(kept, dist, D, ITEM) INSERT_N(kept, dist, K, D, ITEM)
#define INSERT_N(kept, dist, N, D, ITEM)                                                 \
    {                                                                                   \
        float new_d = (D);                                                              \
        uint new_item = (ITEM);                                                         \
        for (uint s = (N) - 1u; s > 0u; s--) {                                          \
            bool shift = after(dist[s - 1u], kept[s - 1u], new_d, new_item);            \
            bool here = !shift && after(dist[s], kept[s], new_d, new_item);             \
            kept[s] = shift ? kept[s - 1u] : (here ? new_item : kept[s]);               \
            dist[s] = shift ? dist[s - 1u] : (here ? new_d : dist[s]);                  \
        }                                                                               \
        bool front = after(dist[0], kept[0], new_d, new_item);                          \
        kept[0] = front ? new_item : kept[0];                                           \
        dist[0] = front ? new_d : dist[0];                                              \
    }

// The first lane's N places from `at` in its slots (own) with the other lanes' merged in; a
// macro for the reason INSERT is one.
#define MERGE_LANES(kept, dist, N, at)                                                   \
    for (uint k = 0u; k < (N); k++) {                                                   \
        kept[k] = lane_kept[own + (at) + k];                                            \
        dist[k] = lane_dist[own + (at) + k];                                            \
    }                                                                                   \
    for (uint j = 1u; j < LANES; j++) {                                                 \
        uint other = own + j * SLOTS + (at);                                            \
        for (uint k = 0u; k < (N) && lane_kept[other + k] != CVK_NO_CONTACT; k++)       \
            INSERT_N(kept, dist, N, lane_dist[other + k], lane_kept[other + k])         \
    }

// What every step of a particle's walk reads of the particle, fixed for the walk.
struct Walker {
    uint p;
    vec3 x;          // x_n
    vec4 rest;       // rest position, w: its cloth
    float reach2;    // the reach squared (the hash's cell size: radius + 1.5 × longest edge / √3)
    float e2;        // the exclusion squared (triangles' corners near p at rest)
    float ee2;       // the edge exclusion squared (edge pairs)
    uint slots;      // collision.edges: p's own edges to test (0 without)
    float own_reach; // collision.edges: the radius plus p's longest edge
    bool border;     // collision.edges: one of p's own edges is a border
};

// The lists of the walk in hand: the last search's list of p (last), the nearest triangles so
// far (kept, dist) and, with collision.edges, edge pairs (ekept, edist). At module scope so
// the walk's steps below share them without passing arrays (see INSERT: lavapipe copied a
// function's inout arrays at every call).
uint last[K];
uint kept[K];
float dist[K];
uint ekept[KE];
float edist[KE];

// p's list written (its triangles, then its edge pairs: as many triangles as leave room for
// the edge pairs), and p listed for the contact passes if it has a candidate.
void write_list(uint p)
{
    uint edges = 0u, triangles = 0u;
    for (uint k = 0u; k < KE; k++)
        edges += EDGES && ekept[k] != CVK_NO_CONTACT ? 1u : 0u;
    for (uint k = 0u; k < K; k++)
        triangles += kept[k] != CVK_NO_CONTACT ? 1u : 0u;
    uint start = min(triangles, K - edges); // where the edge pairs go
    for (uint k = 0u; k < K; k++) {
        uint e = CVK_NO_CONTACT;
        for (uint m = 0u; m < KE; m++) // every index a constant (see INSERT)
            e = k - start == m ? ekept[m] : e;
        contacts[p * K + k] = k < start ? kept[k] : (k - start < edges ? e : CVK_NO_CONTACT);
    }
    if (kept[0] != CVK_NO_CONTACT || edges > 0u) // the contact passes visit it (contact_compact.comp)
        lists[contact_list_base() + atomicAdd(lists[CVK_LIST_CONTACT_COUNT], 1u)] = p;
}

// The first and the last of the 27 cells around home (in hash_neighbour_cell's order) that
// hold, in this lane's entries, a corner to go on from; first_cell > last_cell when none does.
void cells_to_search(Walker walker, ivec3 home, uint lane, out uint first_cell, out uint last_cell)
{
    first_cell = 27u;
    last_cell = 0u;
    for (uint n = 0u; n < 27u; n++) {
        ivec3 cell = hash_neighbour_cell(home, n);
        uvec2 range = hash_range(cell);
        for (uint e = range.x + lane; e < range.y; e += LANES) {
            uvec4 entry = hash_entry_point(e); // the point's index and where it is
            if (near_corner(walker.x, walker.rest, cell, entry.w, uintBitsToFloat(entry.xyz),
                            walker.reach2, walker.e2)) {
                first_cell = min(first_cell, n);
                last_cell = n;
            }
        }
    }
}

// The lists at the start of p's walk: the last search's list of p (cleared to none when p's
// patch went quiet or the positions were written: a pair found again over the face keeps the
// side it had), and nothing kept yet.
void start_lists(uint p)
{
    bool live = true;
    for (uint k = 0u; k < K; k++) {
        uint e = contact_entry(p * K + k);
        live = live && e != CVK_NO_CONTACT;
        last[k] = live ? e : CVK_NO_CONTACT;
    }
    for (uint k = 0u; k < K; k++) {
        kept[k] = CVK_NO_CONTACT;
        dist[k] = INFINITY;
    }
    for (uint k = 0u; k < KE; k++) {
        ekept[k] = CVK_NO_CONTACT;
        edist[k] = INFINITY;
    }
}

// The longest of p's first `slots` own edges (0 with none), and whether one is a border.
float longest_own_edge(uint p, vec3 xp, uint slots, out bool border)
{
    float longest = 0.0;
    border = false;
    for (uint i = 0u; i < slots; i++) {
        uint r;
        bool on_border;
        if (own_edge(p, i, r, on_border)) {
            longest = max(longest, distance(xp, contact_x(r)));
            border = border || on_border;
        }
    }
    return longest;
}

// The triangles around corner q (none unless q is near: near_corner; o_end is the end of its
// incident triangles) within the radius of p, into p's nearest with the side p belongs on.
void triangles_at(Walker walker, uint q, vec3 xq, bool near, uint o_end)
{
    vec3 xp = walker.x;
    vec4 rp = walker.rest;
    uint base = contact_u.particle_count + 1u; // where the incident triangles' ids start
    for (uint o = near ? contact_incident(q) : 0u; o < o_end; o++) {
        uint t = contact_incident(base + o);
        uvec4 tri = contact_triangle(t);
        // The other two corners (q is one of the three).
        uint u = tri.x == q ? tri.y : tri.x;
        uint v = tri.z == q ? tri.y : tri.z;
        vec3 xu = contact_x(u), xv = contact_x(v);
        // Tested once, through its lowest-index corner within reach.
        if ((u < q && within_reach(xp, xu, walker.reach2)) ||
            (v < q && within_reach(xp, xv, walker.reach2)))
            continue;
        if (corner_rest_near(rp, contact_rest(u), walker.e2) ||
            corner_rest_near(rp, contact_rest(v), walker.e2))
            continue;
        vec3 a = tri.x == q ? xq : xu;
        vec3 b = tri.y == q ? xq : (tri.x == q ? xu : xv);
        vec3 c = tri.z == q ? xq : xv;
        vec3 w;
        vec3 closest = closest_on_triangle(xp, a, b, c, w);
        float d = length(xp - closest);
        if (d >= contact_u.detect_radius)
            continue;
        uint side = triangle_side(xp, closest, a, b, c);
        uint item = t << 1u;
        if (w.x > 0.0 && w.y > 0.0 && w.z > 0.0) {
            for (uint k = 0u; k < K; k++) {
                bool same = ((last[k] & ~CVK_UNTANGLE_PAIR) >> 1u) == t;
                side = same ? (last[k] & 1u) : side;
                item |= same ? (last[k] & CVK_UNTANGLE_PAIR) : 0u;
            }
        }
        INSERT(kept, dist, d, item | side)
    }
}

// Edge pairs (collision.edges): each edge at q (once: from its triangle that runs it from the
// lower index to the higher, or its border triangle; tested through its end with the lower
// index within reach) against each of p's own edges, one of the two a border (beyond a border
// no face holds the other cloth's particles off; two interior edges, two creases crossing, are
// left to the particle–triangle pairs around them), no end of either near an end of the other
// at rest (within the edge exclusion, wider than the triangles': lib/contact/collide.c). Found where
// an end of the edge is within the reach of p (lib/contact/collide_passes.c: edges crossing at right
// angles near their middles, up to about 20 % stretch). Into p's nearest edge pairs.
void edge_pairs_at(Walker walker, uint q, vec3 xq, bool near, uint o_end)
{
    uint p = walker.p;
    vec3 xp = walker.x;
    vec4 rp = walker.rest;
    uint base = contact_u.particle_count + 1u; // where the incident triangles' ids start
    vec4 rq = contact_rest(q);
    bool edges_at_q = EDGES && near && !corner_rest_near(rp, rq, walker.ee2);
    uint q_end = edges_at_q ? o_end : 0u;
    for (uint o = edges_at_q ? contact_incident(q) : 0u; o < q_end; o++) {
        uint t = contact_incident(base + o);
        uvec4 tri = contact_triangle(t);
        uint k0 = tri.x == q ? 0u : (tri.y == q ? 1u : 2u);
        for (uint w = 0u; w < 2u; w++) {
            uint j = w == 0u ? k0 : (k0 + 2u) % 3u; // edge j: corner j to corner j + 1
            uint from = corner_of(tri, j), to = corner_of(tri, (j + 1u) % 3u);
            uint b = w == 0u ? to : from; // the edge's other end
            vec3 xb = contact_x(b);
            vec4 rb = contact_rest(b);
            vec3 fa = w == 0u ? xq : xb, fb = w == 0u ? xb : xq;
            bool border = (tri.w & (1u << j)) != 0u;
            bool test = from != to && (from < to || border) && (border || walker.border) &&
                        !(b < q && within_reach(xp, xb, walker.reach2)) &&
                        !corner_rest_near(rp, rb, walker.ee2) &&
                        distance(xp, closest_on_segment(xp, fa, fb)) < walker.own_reach;
            // p's own edges against it (lavapipe ends a shader's loops after 65535
            // iterations in all, hash.h: only edges that can be within the radius of
            // one of them come here).
            for (uint i = 0u; i < (test ? walker.slots : 0u); i++) {
                uint r;
                bool own_border;
                if (!own_edge(p, i, r, own_border) || !(border || own_border))
                    continue;
                vec4 rr = contact_rest(r);
                if (r == q || r == b || corner_rest_near(rr, rq, walker.ee2) ||
                    corner_rest_near(rr, rb, walker.ee2))
                    continue;
                vec3 xr = contact_x(r);
                float s, u;
                vec3 c1, c2;
                closest_segments(xp, xr, fa, fb, s, u, c1, c2);
                precise float d = length(c1 - c2);
                if (d >= contact_u.detect_radius)
                    continue;
                uint item = CVK_EDGE_PAIR | (i << CVK_EDGE_OWN_SHIFT) | ((3u * t + j) << 1u);
                uint side = edge_side(xp, xr, fa, fb, c1, c2);
                bool remembered = false;
                for (uint k = 0u; k < K; k++) {
                    bool same = (last[k] >> 1u) == (item >> 1u);
                    remembered = remembered || same;
                    side = same && edges_inside(s, u) ? (last[k] & 1u) : side;
                }
                // A pair the last list held comes first, so that it keeps its side
                // while it stays within the radius: with only KE places, a pair that
                // fell out behind nearer ones and came back was judged afresh, on the
                // far side once the edges had been pushed through each other.
                INSERT_N(ekept, edist, KE, remembered ? d - contact_u.detect_radius : d,
                         item | side)
            }
        }
    }
}

// This lane's lists into its places in shared memory, for the particle's first lane to merge.
void share_lists()
{
    uint own = gl_LocalInvocationID.x * SLOTS;
    for (uint k = 0u; k < K; k++) {
        lane_kept[own + k] = kept[k];
        lane_dist[own + k] = dist[k];
    }
    for (uint k = 0u; EDGES && k < KE; k++) {
        lane_kept[own + K + k] = ekept[k];
        lane_dist[own + K + k] = edist[k];
    }
}

// The nearest K candidates of particle p among the corners in every LANES-th entry of the
// cells from `lane` on: p's list (one lane), or this invocation's part of it in shared memory.
// In steps: the cells worth walking, the lists started, p's own edges measured (edge pairs),
// then at every corner to go on from its triangles and its edges, and the lists handed on.
void walk(uint p, uint lane)
{
    float reach = 1.0 / hash_params_u.inv_cell; // radius + 1.5 × longest edge / √3
    // p's own edges (collision.edges) are measured below, once the cells are known.
    Walker walker = Walker(p, contact_x(p), contact_rest(p), reach * reach,
                           contact_u.exclusion * contact_u.exclusion,
                           contact_u.edge_exclusion * contact_u.edge_exclusion, 0u, 0.0, false);
    ivec3 home = hash_cell(walker.x);
    // First the cells that hold a corner to go on from, with nothing else live: on lavapipe
    // the candidate arrays below cost on every iteration of every loop they are live in, and
    // where the cloth is not folded there is no such cell at all.
    uint first_cell, last_cell;
    cells_to_search(walker, home, lane, first_cell, last_cell);
    start_lists(p);
    // collision.edges: the radius plus p's longest edge, beyond which no edge can be within
    // the radius of one of p's edges, and whether one of them is a border.
    walker.slots = EDGES ? own_slots(p) : 0u;
    walker.own_reach = longest_own_edge(p, walker.x, walker.slots, walker.border) +
                       contact_u.detect_radius;
    for (uint n = first_cell; n <= last_cell; n++) {
        ivec3 cell = hash_neighbour_cell(home, n);
        uvec2 range = hash_range(cell);
        for (uint e = range.x + lane; e < range.y; e += LANES) {
            uvec4 entry = hash_entry_point(e);
            uint q = entry.w;
            vec3 xq = uintBitsToFloat(entry.xyz); // for its cell, distance and triangles
            bool near = near_corner(walker.x, walker.rest, cell, q, xq, walker.reach2, walker.e2);
            uint o_end = near ? contact_incident(q + 1u) : 0u;
            triangles_at(walker, q, xq, near, o_end);
            edge_pairs_at(walker, q, xq, near, o_end);
        }
    }
    if (LANES == 1u)
        write_list(p);
    else
        share_lists();
}

void main()
{
    if (frame.search == 0u || pc.count == 0u)
        return; // adaptive search: the candidates of the last search still hold
    // The free particles of active patches (contact_compact.comp).
    uint listed = lists[CVK_LIST_SEARCH_COUNT];
    if (LANES == 1u) {
        for (uint i = gl_GlobalInvocationID.x; i < listed; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
            walk(lists[uint(CVK_LIST_HEADER) + i], 0u);
        return;
    }
    // LANES consecutive invocations per particle; every invocation of the workgroup goes
    // round the loop equally often (the barriers).
    uint per_group = gl_WorkGroupSize.x / LANES;
    uint lane = gl_LocalInvocationID.x % LANES;
    for (uint first = gl_WorkGroupID.x * per_group; first < listed;
         first += gl_NumWorkGroups.x * per_group) {
        uint i = first + gl_LocalInvocationID.x / LANES;
        uint p = i < listed ? lists[uint(CVK_LIST_HEADER) + i] : 0u;
        if (i < listed)
            walk(p, lane);
        barrier();
        if (i < listed && lane == 0u) {
            uint own = gl_LocalInvocationID.x * SLOTS;
            MERGE_LANES(kept, dist, K, 0u)
            if (EDGES) {
                MERGE_LANES(ekept, edist, KE, K)
            } else {
                ekept[0] = CVK_NO_CONTACT;
                edist[0] = INFINITY;
            }
            write_list(p);
        }
        barrier();
    }
}
