// The decision to detect (lib/contact/collide.h), one invocation's work, its phases 0 and 1
// as functions, for contact_decide.comp (a dispatch a phase) and contact_faces_fused.comp (the
// whole decision in one workgroup): include after contact/collide.glsl and the push block.
vec3 centre(uint lx, uint ly, uint lz, uint hx, uint hy, uint hz)
{
    if (contact.shift == 0u || lx == CVK_MOTION_LOW_EMPTY)
        return vec3(0.0);
    vec3 low = vec3(from_ordered(lx), from_ordered(ly), from_ordered(lz));
    vec3 high = vec3(from_ordered(hx), from_ordered(hy), from_ordered(hz));
    vec3 c = 0.5 * (low + high);
    return all(lessThanEqual(abs(c), vec3(1.0e30))) ? c : vec3(0.0);
}

// The particles the last substep held at their bounds (contact_check.comp) added to the run's
// count, a 64-bit sum with the carry by hand, and the substep counted (none follows a state
// write: frame.force).
void add_held()
{
    uint held = frame.held_lo + motion_bounds.held;
    frame.held_hi += held < frame.held_lo ? 1u : 0u;
    frame.held_lo = held;
    frame.held_substeps += frame.force == 0u ? 1u : 0u;
    motion_bounds.held = 0u;
}

uint groups_for(uint items)
{
    return min((items + pc.per_group - 1u) / pc.per_group, 65535u);
}

#ifdef HASH_COMMON_GLSL
// Phases 2 and 3 (after contact_edges.comp phase 1 measured the reach): the cells of the hash
// bound as set 1 — the centroids' (faces) or the midpoints' — and whether it builds.
// Detecting: cells as wide as the reach measured now (contact_edges.comp phase 1), so the
// walk over 27 cells finds every pair within the radius however the cloth stretches (up to a
// cell 16 times the first, past which the walks would visit most of a scene blown apart): a
// triangle within the radius of a vertex has its centroid within the radius plus the farthest
// its corners are from it (contact_detect.comp), an edge within the radius of another its
// midpoint within the radius plus half of each edge's length (contact_edges.comp).
float detection_cell(bool faces)
{
    float reach = faces ? uintBitsToFloat(motion_bounds.spread) : uintBitsToFloat(frame.longest);
    float cell = contact.radius + reach;
    return clamp(cell, contact.radius, 16.0 * (contact.radius + contact.longest));
}

void decide_cells(bool faces)
{
    if (frame.search != 0u) {
        float cell = detection_cell(faces);
        hash_params.cell_size = cell;
        hash_params.inv_cell = 1.0 / cell;
    }
    hash_params.build = frame.search;
}
#endif

// Phase 0: the shift the substep would have without detecting.
void decide_shift()
{
    vec3 next = centre(motion_bounds.e_low_x, motion_bounds.e_low_y, motion_bounds.e_low_z,
                       motion_bounds.e_high_x, motion_bounds.e_high_y, motion_bounds.e_high_z);
    motion_bounds.next_x = next.x;
    motion_bounds.next_y = next.y;
    motion_bounds.next_z = next.z;
}

// Phase 1: detect or not; the shift for the substep; the bounds reset.
void decide_detect()
{
    // A detection that only the moves ask for waits for a substep whose index is a multiple
    // of the interval (collision.detection_interval; at 1, none waits): until then the
    // particles that would pass their bounds are held at them.
    uint exceed = motion_bounds.exceed;
    bool waits = (exceed & CVK_EXCEED_NOW) == 0u && frame.step % contact.detection_interval != 0u;
    bool search = frame.force != 0u || (exceed != 0u && !waits);
    // A detection shifts by the centre of the last substep's displacements (after the host
    // wrote the state, the written velocities times dt: lib/contact/collide.h), the motion
    // expected of all; held at 0 otherwise a cloth thrown faster than its bound a substep
    // would lose its speed to the bounds. No shift when a particle is near a collider: the
    // shift, checked against no bound at a detection, could carry a particle the collider
    // stops into the collider, and its push out would then move it past its bound (the
    // substeps that do not detect take a shift every particle's extrapolated move fits:
    // contact_check.comp phase 1).
    vec3 shift = search ? (motion_bounds.near != 0u
                               ? vec3(0.0)
                               : centre(motion_bounds.v_low_x, motion_bounds.v_low_y,
                                        motion_bounds.v_low_z, motion_bounds.v_high_x,
                                        motion_bounds.v_high_y, motion_bounds.v_high_z))
                        : vec3(motion_bounds.next_x, motion_bounds.next_y, motion_bounds.next_z);
    frame.shift_x = shift.x;
    frame.shift_y = shift.y;
    frame.shift_z = shift.z;
    frame.search = search ? 1u : 0u;
    frame.longest = 0u; // measured by detection (contact_edges.comp phase 1)
    motion_bounds.spread = 0u;
    lists[CVK_LIST_PARTICLE_GROUPS] = search ? groups_for(contact.particle_count) : 0u;
    lists[CVK_LIST_PARTICLE_GROUPS + 1] = 1u;
    lists[CVK_LIST_PARTICLE_GROUPS + 2] = 1u;
    lists[CVK_LIST_EDGE_GROUPS] = search ? groups_for(contact.edge_count) : 0u;
    lists[CVK_LIST_EDGE_GROUPS + 1] = 1u;
    lists[CVK_LIST_EDGE_GROUPS + 2] = 1u;
    // Emptied: the edge detection fills the list of its listing pass (none without detection),
    // and the bounds pass the particles in pairs again (contact_bound.comp).
    list_clear(CVK_LIST_EDGE_PAIRS_GROUPS);
    // Emptied: the edge detection's cells and the edges that walk (none without detection:
    // contact_edges.comp phases 3 and 0).
    cells[0] = 0u;
    cells[1] = 1u;
    cells[2] = 1u;
    cells[CVK_CELLS_COUNT] = 0u;
    cells[CVK_CELLS_POOL_USED] = 0u;
    cells[CVK_CELLS_WALK] = 0u;
    cells[CVK_CELLS_WALK + 1u] = 1u;
    cells[CVK_CELLS_WALK + 2u] = 1u;
    cells[CVK_CELLS_WALK + 3u] = 0u;
    if (search)
        list_clear(CVK_LIST_LISTED_GROUPS);
    frame.searches += search ? 1u : 0u;
    add_held();
    frame.force = 0u;
    motion_bounds.e_low_x = motion_bounds.e_low_y = motion_bounds.e_low_z = CVK_MOTION_LOW_EMPTY;
    motion_bounds.v_low_x = motion_bounds.v_low_y = motion_bounds.v_low_z = CVK_MOTION_LOW_EMPTY;
    motion_bounds.e_high_x = motion_bounds.e_high_y = motion_bounds.e_high_z = CVK_MOTION_HIGH_EMPTY;
    motion_bounds.v_high_x = motion_bounds.v_high_y = motion_bounds.v_high_z = CVK_MOTION_HIGH_EMPTY;
    motion_bounds.exceed = 0u;
    motion_bounds.near = 0u;
}
