#version 450
#extension GL_GOOGLE_include_directive : require
// The decision to detect (lib/contact/collide.h) in one dispatch of ONE workgroup, where the
// plan fuses (cvk_plan.fused): contact_check.comp's phase 0, contact_decide.comp's phase 0,
// the check's phase 1, the decision's phase 1, and when it detects, contact_edges.comp's
// phase 1 (the midpoints, the centroids, the reach) and contact_decide.comp's phases 2 and 3
// (the cells of the centroids' hash, bound as set 1, and of the midpoints' hash, whose
// parameters are bound as set 2) — the same functions in the same order, with a workgroup
// barrier between them instead of a dispatch and a pipeline barrier. The check's and the
// measure's results are atomic minima, maxima, ors and sums, which do not depend on how the
// items are shared among invocations, so all of it is the same bits as the eight dispatches'.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#define CONTACT_TYPES_ID 1
#define CONTACT_COHERENT
#include "contact/collide.glsl"
#define HASH_SET 1
#include "contact/hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)
#include "contact/contact_check.glsl"
#include "contact/contact_decide.glsl"
#include "contact/measure.glsl"
// The midpoints' hash parameters (its set's parameter buffer: hash_common.glsl's HashParams).
layout(std430, set = 2, binding = CVK_HASH_BINDING_PARAMS) buffer MidpointParams {
    cvk_hash_params midpoint_params;
};

void decided()
{
    memoryBarrierBuffer();
    barrier();
}

void main()
{
    if (pc.count == 0u)
        return; // the warm-up dispatch changes nothing
    uint lanes = gl_WorkGroupSize.x, lane = gl_LocalInvocationID.x;
    check_moves(lane, lanes);
    decided();
    if (lane == 0u)
        decide_shift();
    decided();
    check_exceed(lane, lanes);
    decided();
    if (lane == 0u)
        decide_detect();
    decided();
    if (frame.search != 0u) // the same for every invocation, read after the barrier
        measure_longest(0u, contact_u.edge_count, lane, lanes);
    decided();
    if (lane == 0u) {
        decide_cells(true);
        // contact_decide.comp's phase 3: decide_cells(false) on the midpoints' hash
        if (frame.search != 0u) {
            float cell = detection_cell(false);
            midpoint_params.cell_size = cell;
            midpoint_params.inv_cell = 1.0 / cell;
        }
        midpoint_params.build = frame.search;
    }
}
