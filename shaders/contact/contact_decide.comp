#version 450
#extension GL_GOOGLE_include_directive : require
// Adaptive candidate search, second half (lib/contact/collide.h): one invocation decides whether this
// substep searches — when asked to (the first substep, positions written from the host) or when
// half the diagonal of the displacements' bounds since the last search (contact_check.comp),
// which bounds how far any is from their centre, is more than search_after — and opens or
// closes the hash build (set 1) and the search (contact_detect.comp) accordingly. The bounds
// are reset for contact_check.comp at the next substep.
layout(local_size_x = 1) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
#define HASH_SET 1
#include "contact/hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

void main()
{
    if (pc.count == 0u)
        return; // the warm-up dispatch changes nothing
    // The farthest any displacement since the last search can be from the bounds' centre:
    // half their diagonal (infinite where contact_check.comp met a non-finite one).
    float moved = 0.0;
    if (motion_bounds.low_x != CVK_MOTION_LOW_EMPTY) {
        vec3 low = vec3(from_ordered(motion_bounds.low_x), from_ordered(motion_bounds.low_y),
                        from_ordered(motion_bounds.low_z));
        vec3 high = vec3(from_ordered(motion_bounds.high_x), from_ordered(motion_bounds.high_y),
                         from_ordered(motion_bounds.high_z));
        moved = 0.5 * length(high - low);
    }
    bool search = frame.force != 0u || !(moved <= contact.search_after);
    frame.search = search ? 1u : 0u;
    hash_params.build = search ? 1u : 0u;
    if (!search) // the search's indirect dispatch does nothing (contact_compact.comp arms it)
        lists[CVK_LIST_SEARCH_GROUPS] = 0u;
    frame.searches += search ? 1u : 0u;
    frame.force = 0u;
    motion_bounds.low_x = motion_bounds.low_y = motion_bounds.low_z = CVK_MOTION_LOW_EMPTY;
    motion_bounds.high_x = motion_bounds.high_y = motion_bounds.high_z = CVK_MOTION_HIGH_EMPTY;
}
