#version 450
#extension GL_GOOGLE_include_directive : require
// Particle–triangle candidates, once per substep: for each free particle, the triangles of any
// cloth within the detection radius at the start of the substep (x_n), found through the
// spatial hash (a triangle is visited through its lowest corner, which lies in one of the 27
// cells around the particle), skipping its own triangles and those of particles it is joined
// to by a spring. The nearest CVK_CONTACTS_PER_PARTICLE are kept, with the side of the
// triangle the particle is on, which the sweeps then keep it on (pd_contact.glsl). The
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

bool joined(uint p, uvec4 t)
{
    if (t.x == p || t.y == p || t.z == p)
        return true;
    uint base = contact.particle_count + 1u;
    for (uint i = near_list[p]; i < near_list[p + 1u]; i++) {
        uint q = near_list[base + i];
        if (q == t.x || q == t.y || q == t.z)
            return true;
    }
    return false;
}

void main()
{
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint p = pc.first + i;
        vec3 xp = contact_x[p].xyz;
        uint kept[K];
        float dist[K];
        uint found = 0u;
        ivec3 home = hash_cell(xp);
        uint base = contact.particle_count + 1u;
        for (uint n = 0u; n < 27u; n++) {
            ivec3 cell = hash_neighbour_cell(home, n);
            uvec2 range = hash_range(cell);
            for (uint e = range.x; e < range.y; e++) {
                uint q = hash_entry(e);
                if (!hash_in_cell(q, cell))
                    continue; // another cell sharing the slot
                for (uint o = owned[q]; o < owned[q + 1u]; o++) {
                    uint t = owned[base + o];
                    uvec4 tri = triangles[t];
                    if (joined(p, tri))
                        continue;
                    vec3 a = contact_x[tri.x].xyz, b = contact_x[tri.y].xyz, c = contact_x[tri.z].xyz;
                    vec3 w;
                    vec3 closest = closest_on_triangle(xp, a, b, c, w);
                    float d = length(xp - closest);
                    if (d >= contact.detect_radius)
                        continue;
                    uint side = dot(xp - closest, cross(b - a, c - a)) < 0.0 ? 1u : 0u;
                    // Insert by distance, keeping the K nearest (ties: first found first).
                    uint at = found < K ? found : K;
                    while (at > 0u && dist[at - 1u] > d) {
                        if (at < K) {
                            dist[at] = dist[at - 1u];
                            kept[at] = kept[at - 1u];
                        }
                        at--;
                    }
                    if (at < K) {
                        dist[at] = d;
                        kept[at] = (t << 1u) | side;
                        found = min(found + 1u, K);
                    }
                }
            }
        }
        for (uint k = 0u; k < K; k++)
            contacts[p * K + k] = k < found ? kept[k] : CVK_NO_CONTACT;
    }
}
