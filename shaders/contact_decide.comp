#version 450
#extension GL_GOOGLE_include_directive : require
// Adaptive candidate search, second half (lib/collide.h): one invocation decides whether this
// substep searches — when asked to (the first substep, positions written from the host) or when
// a displacement since the last search is more than search_after from the displacements'
// centre (contact_check.comp) — and opens or closes the hash build (set 1) and the search
// (contact_detect.comp) accordingly. The farthest move and the bounds are reset for
// contact_check.comp at the next substep.
layout(local_size_x = 1) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "collide.glsl"
#define HASH_SET 1
#include "hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

void main()
{
    if (pc.count == 0u)
        return; // the warm-up dispatch changes nothing
    bool search = frame.force != 0u || uintBitsToFloat(frame.moved) > contact.search_after;
    frame.search = search ? 1u : 0u;
    hash_params.build = search ? 1u : 0u;
    if (!search) // the search's indirect dispatch does nothing (contact_compact.comp arms it)
        lists[CVK_LIST_SEARCH_GROUPS] = 0u;
    frame.searches += search ? 1u : 0u;
    frame.moved = 0u;
    frame.force = 0u;
    motion_bounds.low_x = motion_bounds.low_y = motion_bounds.low_z = CVK_MOTION_LOW_EMPTY;
    motion_bounds.high_x = motion_bounds.high_y = motion_bounds.high_z = CVK_MOTION_HIGH_EMPTY;
}
