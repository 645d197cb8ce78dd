// Detection's last pass on one particle (contact_bound.comp; contact_edges_fused.comp after
// edge detection, where the plan fuses): what contact_bound.comp says. Include after
// contact/collide.glsl.
#ifndef CONTACT_BOUND_GLSL
#define CONTACT_BOUND_GLSL

const uint KS = uint(CVK_SIDES_PER_PARTICLE);

// p's side list (contact_detect.comp) in ascending (vertex, entry) order, whatever order the
// atomics gave it, ended by an empty pair where it is not full (its readers stop there:
// cloth_push.glsl), and its count cleared for the next detection. A particle that is a corner
// in more pairs than the list holds (crowded) keeps none of them: which KS it would keep is
// the order in which invocations reached the atomics, and the run would not repeat bit for bit
// (the twist, contact-twist.json, from frame 158 under another workgroup size). Its own list
// and its edges' pairs still push it. Returns whether p was crowded. Sorted in registers, read
// and written once: on lavapipe each storage-buffer access is a loop over the lanes, and a
// loop runs as often as its longest lane, so only the pairs and the end are written (every
// slot of the list, 32 stores a particle, was most of the bounds' pass).
uint side_v[KS], side_e[KS];
bool sort_sides(uint p)
{
    uint filled = sides[p];
    bool crowded = filled > KS;
    uint count = crowded ? 0u : filled;
    uint base = contact_u.particle_count + 2u * p * KS;
    for (uint i = 0u; i < count; i++) {
        uint v = imageLoad(sides_t, int(base + 2u * i)).x;
        uint e = imageLoad(sides_t, int(base + 2u * i + 1u)).x;
        uint j = i;
        for (; j > 0u && (side_v[j - 1u] > v || (side_v[j - 1u] == v && side_e[j - 1u] > e)); j--) {
            side_v[j] = side_v[j - 1u];
            side_e[j] = side_e[j - 1u];
        }
        side_v[j] = v;
        side_e[j] = e;
    }
    for (uint i = 0u; i < count; i++) {
        sides[base + 2u * i] = side_v[i];
        sides[base + 2u * i + 1u] = side_e[i];
    }
    if (count < KS)
        sides[base + 2u * count] = CVK_NO_CONTACT;
    sides[p] = 0u;
    return crowded;
}

// The crowded particles an invocation met (sort_sides) added to frame.crowded_lo/hi, once an
// invocation: a 64-bit sum from 32-bit atomics (the addition that wraps the low word carries).
void add_crowded(uint crowded)
{
    if (crowded == 0u)
        return;
    uint before = atomicAdd(frame.crowded_lo, crowded);
    if (before + crowded < before)
        atomicAdd(frame.crowded_hi, 1u);
}

// Particle p's bound, where it is now, its sides sorted and its nearest distance cleared;
// listed for the cloth contact pass (its command's workgroups of per_group particles) where it
// is free and in some pair. Returns 1 where p was crowded (sort_sides), else 0.
uint bound_one(uint p, uint per_group)
{
    uint base = contact_u.particle_count + 1u;
    float d = min(contact_u.radius, uintBitsToFloat(nearest[p]));
    // Whether p is in any pair: the cloth contact pass's work (pd_contact.comp).
    bool listed = sides[p] != 0u || contact_entry(p * uint(CVK_CONTACTS_PER_PARTICLE)) != CVK_NO_CONTACT;
    for (uint o = particle_edge(p); o < particle_edge(p + 1u); o++) {
        uint e = particle_edge(base + o);
        d = min(d, uintBitsToFloat(NEAREST(contact_u.particle_count + e)));
        listed = listed || edge_entry(e * uint(CVK_CONTACTS_PER_EDGE)) != CVK_NO_CONTACT;
    }
    vec3 x = contact_x(p);
    vec3 ax = abs(x);
    float floor_gap = max(float(CVK_GAP_FLOOR_THICKNESSES) * contact_u.thickness,
                          float(CVK_GAP_FLOOR_RELATIVE) * max(ax.x, max(ax.y, ax.z)));
    searched[p] = vec4(x, contact_u.gamma * max(d - floor_gap, 0.0));
    // The free particles in pairs, the cloth contact pass's work until the next detection
    // (shaders/solvers/pd_contact.comp), with its workgroups: one particle an invocation.
    if (listed && p < contact_u.free_count)
        list_append(CVK_LIST_LISTED_GROUPS, p, per_group);
    bool crowded = sort_sides(p);
    nearest[p] = 0x7f7f7f7fu; // 3.4e38: none yet (as lib/contact/collide.c fills it)
    return crowded ? 1u : 0u;
}

#endif
