#version 450
#extension GL_GOOGLE_include_directive : require
// The surface patches at a search (lib/contact/collide.h, "Patches"), in phases:
// 0 (with LANES > 1 only), one triangle per invocation: its bounding box at x_n, its unit
//   normal, and whether it is degenerate or squeezed (3 vec4 per triangle in patch_bounds,
//   after the patches' entries);
// 1, one patch per invocation: its bounding box over its triangles' and its normal cone (the
//   normalised sum of its triangles' unit normals, in the patch's order, as the axis, the
//   smallest cosine of a normal to it; -1 when it has a degenerate or squeezed triangle or
//   normals that cancel), from phase 0's entries or, with one lane, measured here;
// 2: whether it is active — not flat itself, or some other patch within the detection radius
//   of its box that is not a rest neighbour, or a neighbour that does not stay flat with it.
// Each patch's result depends on the data alone, not on the order of invocations or on LANES
// (phase 0 and 1 do the same arithmetic). LANES > 1 means a GPU (lib/sim/sim.c), where a patch's
// loop measuring its triangles was one long chain of dependent reads (phase 0 takes them
// apart; on lavapipe its writes cost more than the loop) and so was its loop over every other
// patch: in phase 2 LANES invocations share a patch, each looking at every LANES-th other
// patch, and the patch is active if one of them finds it so (phase 1 clears the flag).
layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint LANES = 1u;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

// Phase 1 with lanes reads this many triangles' entries before using them: the reads do not
// depend on each other, so a GPU keeps them in flight together.
const uint BATCH = 8u;

// The unit normal of triangle (a, b, c); 0 when it is degenerate.
vec3 unit_normal_of(vec3 a, vec3 b, vec3 c, out bool degenerate)
{
    vec3 n = cross(b - a, c - a);
    float len = length(n);
    degenerate = !(len > 0.0);
    return degenerate ? vec3(0.0) : n / len;
}

vec3 unit_normal(uint t)
{
    uvec4 tri = contact_triangle(t);
    bool degenerate;
    return unit_normal_of(contact_x(tri.x), contact_x(tri.y), contact_x(tri.z), degenerate);
}

// Whether one of the triangle's two shorter edges at rest is now shorter than
// CVK_PATCH_SQUEEZE of its rest length: a surface squeezed that much within its plane may have
// slid over itself there (a border crushed against a wall), which a flat normal cone does not
// show. The longest edge is left out: a cloth without shear springs shears freely, and its
// triangles' diagonals then shorten without anything sliding over anything.
bool squeezed(uvec4 tri, vec3 a, vec3 b, vec3 c)
{
    vec3 ra = contact_rest(tri.x).xyz, rb = contact_rest(tri.y).xyz, rc = contact_rest(tri.z).xyz;
    vec3 now = vec3(dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c));
    vec3 rest = vec3(dot(rb - ra, rb - ra), dot(rc - rb, rc - rb), dot(ra - rc, ra - rc));
    float longest = max(rest.x, max(rest.y, rest.z));
    float k = CVK_PATCH_SQUEEZE * CVK_PATCH_SQUEEZE;
    bvec3 shorter = lessThan(now, k * rest);
    // the longest at rest (the first of equals) does not count
    bool skip_x = rest.x == longest, skip_y = !skip_x && rest.y == longest;
    bool skip_z = !skip_x && !skip_y;
    return (shorter.x && !skip_x) || (shorter.y && !skip_y) || (shorter.z && !skip_z);
}

// Triangle t at x_n: its bounding box, its unit normal, and whether it is degenerate or
// squeezed (phase 0 writes these; phase 1 with one lane uses them at once).
void measure(uint t, out vec3 low, out vec3 high, out vec3 normal, out bool broken)
{
    uvec4 tri = contact_triangle(t);
    vec3 x0 = contact_x(tri.x), x1 = contact_x(tri.y), x2 = contact_x(tri.z);
    low = min(x0, min(x1, x2));
    high = max(x0, max(x1, x2));
    bool degenerate;
    normal = unit_normal_of(x0, x1, x2, degenerate);
    broken = degenerate || squeezed(tri, x0, x1, x2);
}

// Phase 0: triangle t's entries (its box, its unit normal, whether it is broken) after the
// patches' entries, which start at `triangles` in patch_bounds.
void triangle_entries(uint t, uint triangles)
{
    vec3 low, high, n;
    bool broken;
    measure(t, low, high, n, broken);
    patch_bounds[triangles + 3u * t] = vec4(low, 0.0);
    patch_bounds[triangles + 3u * t + 1u] = vec4(high, 0.0);
    patch_bounds[triangles + 3u * t + 2u] = vec4(n, broken ? 1.0 : 0.0);
}

// The box of the patch's triangles (entries first to end of the patch table from ids), the sum
// of their unit normals in the patch's order, and whether one is broken: measured here with
// one lane, else gathered from phase 0's entries.
void patch_box_and_normals(uint first, uint end, uint ids, uint triangles, out vec3 low,
                           out vec3 high, out vec3 sum, out bool broken)
{
    low = vec3(3.0e38);
    high = vec3(-3.0e38);
    sum = vec3(0.0);
    broken = false;
    if (LANES == 1u) { // measured here
        for (uint i = first; i < end; i++) {
            vec3 lo, hi, n;
            bool bad;
            measure(patch_table(ids + i), lo, hi, n, bad);
            low = min(low, lo);
            high = max(high, hi);
            sum += n;
            broken = broken || bad;
        }
    } else { // gathered from phase 0, BATCH triangles' reads at a time, summed in order
        for (uint i = first; i < end; i += BATCH) {
            vec4 n[BATCH];
            vec3 lo[BATCH], hi[BATCH];
            for (uint j = 0u; j < BATCH; j++) {
                int e = int(triangles + 3u * patch_table(ids + min(i + j, end - 1u)));
                lo[j] = texelFetch(patch_bounds_t, e).xyz;
                hi[j] = texelFetch(patch_bounds_t, e + 1).xyz;
                n[j] = texelFetch(patch_bounds_t, e + 2);
            }
            for (uint j = 0u; j < BATCH; j++)
                if (i + j < end) {
                    low = min(low, lo[j]);
                    high = max(high, hi[j]);
                    sum += n[j].xyz;
                    broken = broken || n[j].w != 0.0;
                }
        }
    }
}

// The smallest cosine between the axis and the unit normals of the same triangles, from
// `cosine` down, stopping at -1 (a cone already marked broken stays so).
float cone_cosine(uint first, uint end, uint ids, uint triangles, vec3 axis, float cosine)
{
    if (LANES == 1u) {
        for (uint i = first; i < end && cosine > -1.0; i++)
            cosine = min(cosine, dot(unit_normal(patch_table(ids + i)), axis));
    } else {
        for (uint i = first; i < end && cosine > -1.0; i += BATCH) {
            vec3 n[BATCH];
            for (uint j = 0u; j < BATCH; j++)
                n[j] = texelFetch(patch_bounds_t, int(triangles + 3u * patch_table(ids + min(i + j, end - 1u)) + 2u)).xyz;
            for (uint j = 0u; j < BATCH; j++)
                cosine = min(cosine, dot(n[j], axis)); // a repeated last one changes nothing
        }
    }
    return cosine;
}

// Phase 1: patch a's entries, its box and its normal cone (the axis, the smallest cosine of a
// normal to it), and its activity flag cleared for phase 2's lanes.
void patch_entries(uint a, uint offsets, uint ids, uint triangles)
{
    if (LANES > 1u)
        patch_active[a] = 0u;
    uint first = patch_table(offsets + a), end = patch_table(offsets + a + 1u);
    vec3 low, high, sum;
    bool broken;
    patch_box_and_normals(first, end, ids, triangles, low, high, sum, broken);
    float len = length(sum);
    vec3 axis = len > 0.0 ? sum / len : vec3(0.0, 1.0, 0.0);
    float cosine = broken || !(len > 0.0) ? -1.0 : 1.0;
    cosine = cone_cosine(first, end, ids, triangles, axis, cosine);
    patch_bounds[3u * a] = vec4(low, 0.0);
    patch_bounds[3u * a + 1u] = vec4(high, 0.0);
    patch_bounds[3u * a + 2u] = vec4(axis, cosine);
}

// Phase 2: whether patch a is active, as far as lane `lane` of it sees (every LANES-th other
// patch): not flat itself, or near another patch that is not a rest neighbour, or near a
// neighbour that does not stay flat with it.
void patch_activity(uint a, uint lane, uint patches)
{
    vec3 low = texelFetch(patch_bounds_t, int(3u * a)).xyz;
    vec3 high = texelFetch(patch_bounds_t, int(3u * a + 1u)).xyz;
    vec4 cone = texelFetch(patch_bounds_t, int(3u * a + 2u));
    float limit = acos(contact_u.flat_cos);
    float r = contact_u.detect_radius;
    uint near = contact_u.patch_neighbours;
    uint near_first = patch_table(near + a), near_end = patch_table(near + a + 1u);
    bool busy = !(acos(clamp(cone.w, -1.0, 1.0)) <= limit);
    for (uint b = lane; b < patches && !busy; b += LANES) {
        vec3 low_b = texelFetch(patch_bounds_t, int(3u * b)).xyz;
        vec3 high_b = texelFetch(patch_bounds_t, int(3u * b + 1u)).xyz;
        bool overlap = all(lessThanEqual(low - r, high_b)) && all(lessThanEqual(low_b - r, high));
        if (b == a || !overlap)
            continue;
        bool adjacent = false;
        for (uint k = near_first; k < near_end; k++)
            adjacent = adjacent || patch_table(near + patches + 1u + k) == b;
        vec4 cone_b = texelFetch(patch_bounds_t, int(3u * b + 2u));
        // every normal of b within limit of a's axis: the two stay a height field over it
        float spread = acos(clamp(dot(cone.xyz, cone_b.xyz), -1.0, 1.0)) +
                       acos(clamp(cone_b.w, -1.0, 1.0));
        busy = !adjacent || !(spread <= limit);
    }
    if (LANES == 1u)
        patch_active[a] = busy ? 1u : 0u;
    else if (busy)
        atomicOr(patch_active[a], 1u);
}

void main()
{
    if (frame.search == 0u || pc.count == 0u)
        return;
    uint patches = contact_u.patch_count;
    uint offsets = contact_u.particle_count, ids = offsets + patches + 1u;
    uint triangles = 3u * patches; // where the triangles' entries start in patch_bounds
    for (uint item = gl_GlobalInvocationID.x; item < pc.count; item += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        if (pc.phase == 0u)
            triangle_entries(item, triangles);
        else if (pc.phase == 1u)
            patch_entries(item, offsets, ids, triangles);
        else
            patch_activity(item / LANES, item % LANES, patches);
    }
}
