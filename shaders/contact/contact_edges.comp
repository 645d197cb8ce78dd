#version 450
#extension GL_GOOGLE_include_directive : require
// Edge detection's phases, one a dispatch (contact/contact_edges.glsl says what each does).
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#define CONTACT_TYPES_ID 2
#include "contact/collide.glsl"
#define HASH_SET 1
#include "contact/hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)
#include "contact/contact_edges.glsl"
// The phase, a pipeline each (lib/core/pipelines.h): an `if` on the push constants' phase left
// every other phase's code in each dispatch, run once under an empty mask for every SIMD
// vector on lavapipe (the 40 x 40 contact drape's edge detection 0.83-0.94 of before without
// it, the six-cloth pile's 0.87-0.88; the same bits).
layout(constant_id = 3) const uint PHASE = 0u;

void work()
{
    if (pc.count == 0u)
        return;
    if (LISTING) {
        uint count = lists[CVK_LIST_EDGE_PAIRS_COUNT], start = list_start(CVK_LIST_EDGE_PAIRS_GROUPS);
        for (uint i = gl_GlobalInvocationID.x; i < count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
            detect_listing(lists[start + i]);
        return;
    }
    if (PHASE == 1u) {
        measure_longest(pc.first, pc.count, gl_GlobalInvocationID.x,
                        gl_NumWorkGroups.x * gl_WorkGroupSize.x);
        return;
    }
    if (PHASE == 2u) {
        list_near();
        return;
    }
    if (PHASE == 3u) {
        find_cells();
        return;
    }
    if (PHASE == 4u) {
        gather_cells();
        return;
    }
    if (PHASE == 5u) {
        walk_listed();
        return;
    }
    // Phase 0 takes the edges in the order of the midpoints' hash, the i-th entry's edge, so
    // neighbouring invocations have edges of one cell, which loop over the same list: on
    // lavapipe a loop runs as often as its longest lane (the six-cloth pile's edge detection
    // 1.96-2.05 times its faces' in the same runs against 2.08-2.12, the same bits).
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
        detect(hash_entry_point(pc.first + i).w);
}

void main()
{
    work();
    note_loops_cut(pc.count); // after the work, whatever it returned from (bounds.glsl)
}
