#version 450
#extension GL_GOOGLE_include_directive : require
// The decision to detect, the faces' hash build and the faces' detection in one dispatch of ONE
// workgroup, where the plan fuses (cvk_plan.fused): the decision's phases (contact_check.comp's
// and contact_decide.comp's: the check, the shift, the decision, and when it detects
// contact_edges.comp's measure and both hashes' cells), then the passes of the centroids' hash
// build (hash_common.glsl's hash_*_pass, the hash_*.comp dispatches' work, nothing while its
// parameters close the build), then contact_detect.comp's walk over every
// particle (nothing at a substep that does not detect) — the same functions in the same order,
// with a workgroup barrier between them instead of a dispatch and a pipeline barrier. What a
// part reads that an earlier one wrote in this dispatch goes through the storage buffers,
// coherent: the frame and bounds state (CONTACT_COHERENT), the centroids the build hashes
// (MEASURE_COHERENT, HASH_POINT_OF) and the hash itself (HASH_FUSED). The check's and the
// measure's results are atomic minima, maxima, ors and sums, no reader of the hash depends on
// the order of a slot's entries and each particle's list is sorted, so all of it is the same
// bits as the unfused passes'.
// No invocation waits on another workgroup: correct on any conformant device.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#define CONTACT_TYPES_ID 1
#define CONTACT_COHERENT
#define MEASURE_COHERENT
#include "contact/collide.glsl"
#include "contact/measure.glsl"
#define HASH_SET 1
#define HASH_BUILD
#define HASH_FUSED
#define HASH_PUSH_DECLARED
CVK_DECLARE_PUSH(CVK_CONTACT_HASH_PUSH_FIELDS)
#define HASH_POINT_OF(q) (centroids[q].xyz)
#include "contact/hash_common.glsl"
#include "contact/contact_check.glsl"
#include "contact/contact_decide.glsl"
#include "contact/contact_detect.glsl"
// The midpoints' hash parameters (its set's parameter buffer: hash_common.glsl's HashParams).
layout(std430, set = 2, binding = CVK_HASH_BINDING_PARAMS) buffer MidpointParams {
    cvk_hash_params midpoint_params;
};

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
    // the decision (contact_check.comp and contact_decide.comp, phases 0 and 1)
    check_moves(lane, lanes);
    passed();
    if (lane == 0u)
        decide_shift();
    passed();
    check_exceed(lane, lanes);
    passed();
    if (lane == 0u)
        decide_detect();
    passed();
    if (frame.search != 0u) // the same for every invocation, read after the barrier
        measure_longest(0u, contact_u.edge_count, lane, lanes);
    passed();
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
    passed();
    // the centroids' hash build (hash_*.comp), a barrier after it
    hash_build_fused();
    // contact_detect.comp, over every particle
    if (frame.search == 0u)
        return;
    for (uint i = lane; i < pc.count; i += lanes)
        detect(pc.first + i);
}

void main()
{
    work();
    note_loops_cut(pc.count); // after the work, whatever it returned from (bounds.glsl)
}
