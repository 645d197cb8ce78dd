#version 450
#extension GL_GOOGLE_include_directive : require
// The work lists of a search (lib/contact/collide.h, "Patches"), in phases:
// 0 (one invocation): both lists emptied;
// 1 (every particle): where the search sees it (the adaptive search's reference); a free
//   particle of an active patch, or on no triangle, is listed to search, any other has no
//   candidates;
// 2 (one invocation): the search's indirect command, and the hash is built only when some
//   particle searches;
// 3 (one invocation, after the search): the contact passes' indirect command.
// The lists' order follows the atomics, but what is done for a listed particle does not depend
// on where in the list it is.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
#define HASH_SET 1
#include "contact/hash_common.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

uint groups_for(uint items)
{
    uint groups = (items + pc.per_group - 1u) / pc.per_group;
    return min(groups, 65535u);
}

void main()
{
    if (frame.search == 0u || pc.count == 0u)
        return;
    if (pc.phase == 0u) {
        lists[CVK_LIST_SEARCH_COUNT] = 0u;
        lists[CVK_LIST_CONTACT_COUNT] = 0u;
        return;
    }
    if (pc.phase == 2u) {
        uint searching = lists[CVK_LIST_SEARCH_COUNT];
        lists[CVK_LIST_SEARCH_GROUPS] = groups_for(searching);
        lists[CVK_LIST_SEARCH_GROUPS + 1] = 1u;
        lists[CVK_LIST_SEARCH_GROUPS + 2] = 1u;
        hash_params.build = searching > 0u ? 1u : 0u;
        return;
    }
    if (pc.phase == 3u) {
        lists[CVK_LIST_CONTACT_GROUPS] = groups_for(lists[CVK_LIST_CONTACT_COUNT]);
        lists[CVK_LIST_CONTACT_GROUPS + 1] = 1u;
        lists[CVK_LIST_CONTACT_GROUPS + 2] = 1u;
        return;
    }
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        uint p = pc.first + i;
        searched[p] = vec4(contact_x(p), 0.0);
        if (p >= contact_u.free_count)
            continue; // a pinned particle is only seen (the adaptive search's reference)
        uint own = patch_table(p);
        if (own == CVK_NO_PATCH || patch_active[own] != 0u)
            lists[uint(CVK_LIST_HEADER) + atomicAdd(lists[CVK_LIST_SEARCH_COUNT], 1u)] = p;
        else
            contacts[p * uint(CVK_CONTACTS_PER_PARTICLE)] = CVK_NO_CONTACT;
    }
}
