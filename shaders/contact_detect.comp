#version 450
#extension GL_GOOGLE_include_directive : require
// Particle–triangle candidates, once per substep: for each free particle, the triangles of any
// cloth within the detection radius at the start of the substep (x_n), found through the
// spatial hash (a triangle is visited through its lowest corner, which lies in one of the 27
// cells around the particle), skipping triangles of its own cloth that were near it at rest. The nearest CVK_CONTACTS_PER_PARTICLE are kept, with the side of the
// triangle the particle is on, which the sweeps then keep it on (pd_contact_u.glsl). The
// enumeration order is fixed (cells in order, entries sorted in each slot), so the result does
// not depend on thread timing.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "collide.glsl"
#define HASH_SET 1
#include "hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

const uint K = uint(CVK_CONTACTS_PER_PARTICLE);
const float INFINITY = 3.0e38; // beyond any distance kept

// Of one cloth and near at rest (lib/collide.c, cvk_collide_rest_near): not a contact_u.
bool rest_near(vec4 rp, uvec4 t)
{
    float e2 = contact_u.exclusion * contact_u.exclusion;
    vec4 ra = contact_rest(t.x), rb = contact_rest(t.y), rc = contact_rest(t.z);
    vec3 da = rp.xyz - ra.xyz, db = rp.xyz - rb.xyz, dc = rp.xyz - rc.xyz;
    return (ra.w == rp.w && dot(da, da) < e2) || (rb.w == rp.w && dot(db, db) < e2) ||
           (rc.w == rp.w && dot(dc, dc) < e2);
}

void main()
{
    if (frame.search == 0u)
        return; // adaptive search: the candidates of the last search still hold
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint p = pc.first + i;
        vec3 xp = contact_x(p);
        searched[p] = vec4(xp, 0.0);
        if (p >= contact_u.free_count)
            continue; // a pinned particle is only seen (the adaptive search's reference)
        vec4 rp = contact_rest(p);
        uint kept[K];
        float dist[K];
        for (uint k = 0u; k < K; k++) {
            kept[k] = CVK_NO_CONTACT;
            dist[k] = INFINITY;
        }
        ivec3 home = hash_cell(xp);
        uint base = contact_u.particle_count + 1u;
        float reach = 1.0 / hash_params_u.inv_cell; // ≥ radius + 1.5 × the longest edge
        float reach2 = reach * reach;
        float exclusion2 = contact_u.exclusion * contact_u.exclusion;
        for (uint n = 0u; n < 27u; n++) {
            ivec3 cell = hash_neighbour_cell(home, n);
            uvec2 range = hash_range(cell);
            for (uint e = range.x; e < range.y; e++) {
                uint q = hash_entry(e);
                vec3 xq = hash_point(q); // fetched once: for its cell and its distance
                // A triangle within the detection radius has its owner within the radius plus
                // its longest edge, less than a cell (lib/collide_passes.c): farther owners are
                // skipped by an empty range, which lavapipe's loops honour.
                // q is a corner of every triangle it owns: if q was near p at rest, all of
                // them are skipped (the common case inside one cloth).
                // An entry of another cell sharing the slot is skipped the same way.
                vec3 to_q = xq - xp;
                vec4 rq = contact_rest(q);
                vec3 rest_to_q = rq.xyz - rp.xyz;
                bool near = hash_cell(xq) == cell && dot(to_q, to_q) < reach2 &&
                            (rq.w != rp.w || dot(rest_to_q, rest_to_q) >= exclusion2);
                uint o_end = near ? contact_owned(q + 1u) : 0u;
                for (uint o = near ? contact_owned(q) : 0u; o < o_end; o++) {
                    uint t = contact_owned(base + o);
                    uvec4 tri = contact_triangle(t);
                    if (rest_near(rp, tri))
                        continue;
                    vec3 a = contact_x(tri.x), b = contact_x(tri.y), c = contact_x(tri.z);
                    vec3 w;
                    vec3 closest = closest_on_triangle(xp, a, b, c, w);
                    float d = length(xp - closest);
                    if (d >= contact_u.detect_radius)
                        continue;
                    uint side = dot(xp - closest, cross(b - a, c - a)) < 0.0 ? 1u : 0u;
                    // Insert by distance, keeping the K nearest (ties: first found first). Every
                    // index is a constant once the loop unrolls: a variable index into a
                    // private array is a per-lane memory loop on lavapipe (the search took 1.4x
                    // as long with the usual insertion loop).
                    uint item = (t << 1u) | side;
                    for (uint k = K - 1u; k > 0u; k--) {
                        bool shift = dist[k - 1u] > d;
                        bool here = !shift && dist[k] > d;
                        kept[k] = shift ? kept[k - 1u] : (here ? item : kept[k]);
                        dist[k] = shift ? dist[k - 1u] : (here ? d : dist[k]);
                    }
                    kept[0] = dist[0] > d ? item : kept[0];
                    dist[0] = dist[0] > d ? d : dist[0];
                }
            }
        }
        for (uint k = 0u; k < K; k++)
            contacts[p * K + k] = kept[k];
    }
}
