#version 450
#extension GL_GOOGLE_include_directive : require
// The decision to detect (lib/contact/collide.h), one invocation, in two phases around
// contact_check.comp's:
// 0: the shift the substep would have without detecting — the centre of the bounds of the
//    extrapolated displacements (none where a particle is kinematic: params.shift 0);
// 2 and 3 (after contact_edges.comp measured the longest edge and the triangles' spread): the
//    cells of the centroids' hash (2) or of the midpoints' (3), whichever is bound as set 1,
//    for detection, and whether it builds;
// 1: detect when asked to (the first substep, positions written from the host) or when some
//    particle would leave its bound: write detection's indirect commands (phases 2 and 3 open
//    or close the hashes' builds); the shift for the substep (after a detection: the centre
//    of the last substep's displacements, the motion expected of all, or none when a particle
//    is near a collider); the count of particles held at their bounds added up; the bounds
//    reset.
layout(local_size_x = 1) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
#define HASH_SET 1
#include "contact/hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

#include "contact/contact_decide.glsl"

void main()
{
    if (pc.count == 0u)
        return; // the warm-up dispatch changes nothing
    if (pc.phase >= 2u) {
        decide_cells(pc.phase == 2u);
        return;
    }
    if (pc.phase == 0u)
        decide_shift();
    else
        decide_detect();
}
