#version 450
#extension GL_GOOGLE_include_directive : require
// The decision to detect, over the particles (lib/contact/collide.h), in two phases around
// contact_decide.comp's:
// 0: each particle's displacement since detection extrapolated over the substep by its last
//    substep's (e = x_n - seen + (x_n - x_before)) and its last substep's (v), bounded per axis
//    (atomic min and max on order-preserving bits: the result does not depend on thread
//    timing); and the free particles the last substep ended past `redetect` of their bound
//    from its centre counted: motion the bounds held back (lib/contact/collide.h:
//    cvk_collide_counts). Not only those on it: a particle the sweeps clamped to its bound
//    mid-solve ends a little inside it, pulled back by neighbours held too (the 40 x 40 drape
//    in one substep of 1/60 s: 6276 of 48000 particle-substeps past 0.9 of their bound in
//    30 frames, 14 on it; in 8 substeps 6 of 384000);
// 1: whether some particle's e is farther than `redetect` of its bound from the shift the
//    substep would have without detecting (e's centre; contact_decide.comp phase 0), or that
//    shift would centre its bound too near a collider; x_n kept as the next substep's
//    x_before.
// A pipeline a phase (PHASE, id 2): llvmpipe runs the code an `if` on a push constant skips,
// under an empty mask, and both phases measure every particle's distance to the colliders.
layout(local_size_x_id = 0) in;
layout(constant_id = 2) const uint PHASE = 0u;
#include "shared/layout.h"
#define CONTACT_SET 0
#define CONTACT_TYPES_ID 1
#include "contact/collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)
#include "contact/contact_check.glsl"

void main()
{
    if (pc.count == 0u)
        return;
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (PHASE == 1u)
        check_exceed(gl_GlobalInvocationID.x, stride);
    else
        check_moves(gl_GlobalInvocationID.x, stride);
}
