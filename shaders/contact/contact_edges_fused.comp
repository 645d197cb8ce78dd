#version 450
#extension GL_GOOGLE_include_directive : require
// The midpoints' hash build, edge detection and the bounds in one dispatch of ONE workgroup,
// where the plan fuses (cvk_plan.fused): the passes of the hash build (hash_common.glsl's
// hash_*_pass, the hash_*.comp dispatches' work, nothing while its parameters close the
// build), then
// contact_edges.comp's phases 3, 4, 0, 5 and 2 and its listing pass, then contact_bound.comp — the
// same functions in the same order, with a workgroup barrier between them instead of a
// dispatch and a pipeline barrier, the walks nothing at a substep that does not detect
// (frame.search, as the decision left it), where the unfused passes' indirect commands have no
// workgroups. What one part writes and a later one reads (the hash, the cells, their lists in
// the pool, the nearest distances and buckets, the work lists, the edges' pairs) goes through
// the storage buffers, coherent (HASH_FUSED, collide.glsl's EDGES_FUSED). Their results are
// atomic minima and lists whose readers do not depend on their order (the hash's slots, the
// cells' lists, the pool's places) or whose order the phases after them fix (each edge's
// nearest pairs sorted, each particle's sides sorted), so the same bits as the unfused
// passes'. No invocation waits on another workgroup:
// correct on any conformant device.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#define CONTACT_TYPES_ID 1
#define EDGES_FUSED
#include "contact/collide.glsl"
#define HASH_SET 1
#define HASH_BUILD
#define HASH_FUSED
#define HASH_PUSH_DECLARED
CVK_DECLARE_PUSH(CVK_CONTACT_HASH_PUSH_FIELDS)
#include "contact/hash_common.glsl"
#include "contact/contact_edges.glsl"
#include "contact/contact_bound.glsl"

void passed()
{
    memoryBarrierBuffer();
    barrier();
}

void work()
{
    if (pc.count == 0u)
        return; // the warm-up dispatch changes nothing
    uint lanes = gl_WorkGroupSize.x, lane = gl_LocalInvocationID.x;
    // the midpoints' hash build (hash_*.comp), a barrier after it
    hash_build_fused();
    if (frame.search == 0u)
        return; // no detection: the same for every invocation
    find_cells();
    passed();
    gather_cells();
    passed();
    for (uint i = lane; i < pc.count; i += lanes)
        detect(hash_entry_point(pc.first + i).w); // in the hash's order, as contact_edges.comp
    passed();
    walk_listed();
    passed();
    list_near();
    passed();
    LISTING = true;
    uint count = lists[CVK_LIST_EDGE_PAIRS_COUNT], start = list_start(CVK_LIST_EDGE_PAIRS_GROUPS);
    for (uint i = lane; i < count; i += lanes)
        detect_listing(lists[start + i]);
    passed();
    uint crowded = 0u;
    for (uint p = lane; p < contact_u.particle_count; p += lanes)
        crowded += bound_one(p, pc.per_group);
    add_crowded(crowded);
}

void main()
{
    work();
    note_loops_cut(pc.count); // after the work, whatever it returned from (bounds.glsl)
}
