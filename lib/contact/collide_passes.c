/* The contact module's passes at the start of each substep: the colliders' poses (and the
   frame state's advance), and for self-contact the decision to search (adaptive search), the
   hash of the positions and the detection of particle–triangle candidates that the solver
   sweeps then resolve; and the search's state as the host sees it. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "contact/collide.h"
#include "shared/layout.h"
#include "core/error.h"
#include "plan/state.h"

cvk_result cvk_collide_create_detection(cvk_sim* s, cvk_error* error)
{
    cvk_collide* c = s->collide;
    /* A triangle within the detection radius of p has a corner within the radius plus the
       farthest any point of it is from its nearest corner: at most the longest edge / √3 (the
       circumradius of an equilateral triangle; less for any other shape of that longest edge).
       Cells that large keep that corner among the 27 cells around p while the cloth stretches
       up to 50 %. Edge contact (collision.edges) searches the same cells: an edge pair is
       found where an end of one edge is within that reach of an end of the other, which holds
       for edges crossing at right angles near their middles up to about 20 % stretch (wider
       cells, for every pair, made flat cloth search again: README, "Edge against edge"). */
    float cell = CVK_DETECT_RADIUS_THICKNESSES(c->detect_every) * c->thickness +
                 1.5f / sqrtf(3.0f) * c->longest_edge;
    cvk_hash_desc desc = {s->build.particle_count ? s->build.particle_count : 1, cell,
                          &s->positions};
    cvk_result r = cvk_hash_create(s->device.context, &desc, &c->hash, error);
    if (r != CVK_SUCCESS)
        return r;
    VkDescriptorSetLayout layouts[2] = {c->set_layout, c->hash.set_layout};
    VkPushConstantRange push = {VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(cvk_contact_push)};
    VkPipelineLayoutCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = 2,
        .pSetLayouts = layouts,
        .pushConstantRangeCount = 1,
        .pPushConstantRanges = &push,
    };
    VkResult vr = vkCreatePipelineLayout(s->device.context->device, &info, NULL, &c->detect_layout);
    return vr == VK_SUCCESS ? CVK_SUCCESS
                            : cvk_fail_vk(error, "vkCreatePipelineLayout (contact detection)", vr);
}

/* Adaptive search (collide.h): how far the particles moved since the last search, then whether
   this substep searches (which opens or closes the hash build and the search). */
static void add_search_decision(cvk_sim* s, cvk_plan* plan)
{
    cvk_collide* c = s->collide;
    uint32_t pass = cvk_plan_pass(plan, "contacts");
    cvk_contact_push all = {0, s->build.particle_count, 0, 0};
    cvk_op* op = cvk_plan_dispatch(plan, pass, CVK_PIPE_CONTACT_CHECK,
                                   c->descriptors.pipeline_layout, c->set, CVK_DOMAIN_PARTICLES, 0,
                                   s->build.particle_count, &all, sizeof all);
    if (op)
        snprintf(op->note, sizeof op->note, "bounds of the moves since the last search");
    cvk_contact_push one = {0, 1, 0, 0};
    op = cvk_plan_dispatch(plan, pass, CVK_PIPE_CONTACT_DECIDE, c->detect_layout, c->set,
                           CVK_DOMAIN_PARTICLES, 0, 1, &one, sizeof one);
    if (op) {
        op->groups = 1;
        op->set1 = c->hash.set;
        snprintf(op->note, sizeof op->note, "search if the bounds' half-diagonal > %.3g m",
                 (double)(CVK_SEARCH_AFTER_THICKNESSES * c->thickness));
    }
}

/* One phase of shaders/contact/contact_compact.comp (phase 1 over every particle, the others one
   invocation). Phases 2 and 3 write indirect commands. */
static void add_compact(cvk_sim* s, cvk_plan* plan, uint32_t phase, const char* note)
{
    cvk_collide* c = s->collide;
    uint32_t count = phase == 1 ? s->build.particle_count : 1;
    /* the search's workgroups take workgroup_size / search_lanes particles each */
    uint32_t per_group = phase == 2 ? plan->workgroup_size / s->search_lanes
                                    : plan->workgroup_size;
    cvk_contact_push push = {0, count, phase, per_group};
    cvk_op* op = cvk_plan_dispatch(plan, cvk_plan_pass(plan, "contacts"), CVK_PIPE_CONTACT_COMPACT,
                                   c->detect_layout, c->set, CVK_DOMAIN_PARTICLES, 0, count, &push,
                                   sizeof push);
    if (!op)
        return;
    if (phase != 1)
        op->groups = 1;
    if (phase >= 2)
        op->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT;
    op->set1 = c->hash.set;
    snprintf(op->note, sizeof op->note, "%s", note);
}

/* The patches' activity and the search list (collide.h, "Patches"). */
static void add_lists(cvk_sim* s, cvk_plan* plan)
{
    cvk_collide* c = s->collide;
    add_compact(s, plan, 0, "lists emptied");
    static const char* const notes[3] = {"triangles' boxes, normals", "boxes, normal cones",
                                         "active or not"};
    for (uint32_t phase = s->search_lanes > 1 ? 0 : 1; phase < 3 && c->patch_count > 0; phase++) {
        /* phase 0: one invocation per triangle; 2: search_lanes per patch */
        uint32_t count = phase == 0   ? s->build.triangle_count
                         : phase == 1 ? c->patch_count
                                      : c->patch_count * s->search_lanes;
        cvk_contact_push push = {0, count, phase, plan->workgroup_size};
        cvk_op* op = cvk_plan_dispatch(plan, cvk_plan_pass(plan, "contacts"), CVK_PIPE_CONTACT_PATCH,
                                       c->descriptors.pipeline_layout, c->set, CVK_DOMAIN_PARTICLES,
                                       0, count, &push, sizeof push);
        cvk_hash_one_item_each(plan, op); /* lavapipe's loop budget: see hash.h */
        if (op)
            snprintf(op->note, sizeof op->note, "%u patches: %s", c->patch_count, notes[phase]);
    }
    add_compact(s, plan, 1, "search list, where each particle is seen");
    add_compact(s, plan, 2, "search command; hash built if any listed");
}

/* One phase of shaders/contact/untangle.comp: 0 and 7 over the search's contact list, 1 one
   invocation (the command of the others), the others over every particle through that
   command. */
static void add_untangle(cvk_sim* s, cvk_plan* plan, uint32_t phase, const char* note)
{
    cvk_collide* c = s->collide;
    uint32_t pass = cvk_plan_pass(plan, "contacts");
    cvk_contact_push push = {0, s->build.particle_count, phase, plan->workgroup_size};
    cvk_op* op;
    if (phase == 1) {
        op = cvk_plan_dispatch(plan, pass, CVK_PIPE_UNTANGLE, c->descriptors.pipeline_layout,
                               c->set, CVK_DOMAIN_PARTICLES, 0, 1, &push, sizeof push);
        if (op)
            op->groups = 1;
    } else {
        bool listed = phase == 0 || phase == 7;
        VkDeviceSize offset = 4u * (listed ? CVK_LIST_CONTACT_GROUPS : CVK_LIST_UNTANGLE_GROUPS);
        op = cvk_plan_dispatch_indirect(plan, pass, CVK_PIPE_UNTANGLE,
                                        c->descriptors.pipeline_layout, c->set,
                                        CVK_DOMAIN_PARTICLES, c->lists.buffer, offset, &push,
                                        sizeof push);
        if (op)
            op->count = s->build.particle_count;
    }
    if (op) {
        /* the indirect commands share the buffer every phase writes */
        op->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT;
        snprintf(op->note, sizeof op->note, "%s", note);
    }
}

/* The untangling step after a search (collide.h, "Untangling"): cut edges, the regions they
   bound (CVK_UNTANGLE_ROUNDS rounds of labels with pointer jumping), the enclosed regions'
   pairs marked, and the arrays cleared. */
static void add_untangling(cvk_sim* s, cvk_plan* plan)
{
    add_untangle(s, plan, 0, "untangling: own edges through listed faces");
    add_untangle(s, plan, 1, "untangling: command (none without a cut edge)");
    _Static_assert(CVK_UNTANGLE_ROUNDS % 2 == 0, "the last round writes the first array");
    for (uint32_t round = 0; round < CVK_UNTANGLE_ROUNDS; round++)
        add_untangle(s, plan, round == 0 ? 2 : (round % 2 ? 3 : 4),
                     "untangling: lowest label's label across uncut edges");
    add_untangle(s, plan, 5, "untangling: regions' sizes, cutters, converged");
    add_untangle(s, plan, 6, "untangling: each cloth's largest region");
    add_untangle(s, plan, 7, "untangling: enclosed particles' pairs marked");
    add_untangle(s, plan, 8, "untangling: cleared");
}

cvk_result cvk_collide_add_passes(cvk_sim* s, cvk_plan* plan, cvk_error* error)
{
    cvk_collide* c = s->collide;
    if (!c->colliding)
        return CVK_SUCCESS;
    if (c->collider_count > 0) {
        uint32_t pass = cvk_plan_pass(plan, "colliders");
        cvk_contact_push push = {0, c->collider_count, 0, 0};
        cvk_op* op = cvk_plan_dispatch(plan, pass, CVK_PIPE_COLLIDER_POSES,
                                       c->descriptors.pipeline_layout, c->set, CVK_DOMAIN_PARTICLES,
                                       0, c->collider_count, &push, sizeof push);
        if (op) {
            op->groups = 1; /* one workgroup: it advances the frame state once */
            snprintf(op->note, sizeof op->note, "poses at t and t + dt, step += 1");
        }
    }
    if (c->self && s->build.free_count > 0) {
        uint32_t first = plan->op_count;
        if (c->detect_every == 0)
            add_search_decision(s, plan);
        add_lists(s, plan);
        cvk_result r = cvk_hash_add_passes(&c->hash, plan, s->build.particle_count, true,
                                              error);
        if (r != CVK_SUCCESS)
            return r;
        uint32_t pass = cvk_plan_pass(plan, "contacts");
        cvk_contact_push push = {0, s->build.particle_count, 0,
                                 plan->workgroup_size / s->search_lanes};
        cvk_op* op = cvk_plan_dispatch_indirect(plan, pass, CVK_PIPE_CONTACT_DETECT,
                                                c->detect_layout, c->set, CVK_DOMAIN_PARTICLES,
                                                c->lists.buffer, 4u * CVK_LIST_SEARCH_GROUPS,
                                                &push, sizeof push);
        if (op) {
            op->count = s->build.particle_count;
            op->set1 = c->hash.set;
            if (s->search_lanes > 1)
                snprintf(op->note, sizeof op->note, "listed: pairs%s within %.3g m, %u lanes",
                         c->edges ? " and edges" : "", (double)c->detect_radius, s->search_lanes);
            else
                snprintf(op->note, sizeof op->note, "listed: pairs%s within %.3g m",
                         c->edges ? " and edges" : "", (double)c->detect_radius);
        }
        add_compact(s, plan, 3, "contact list -> contact passes' command");
        add_untangling(s, plan);
        for (uint32_t i = first; c->detect_every > 1 && i < plan->op_count; i++)
            plan->ops[i].every = c->detect_every; /* candidates for the substeps until the next */
    }
    return cvk_plan_check(plan, error);
}

/* ---- the search's state on the host: written positions, statistics, snapshots ----------- */

cvk_result cvk_collide_positions_written(cvk_sim* s, cvk_error* error)
{
    cvk_collide* c = s->collide;
    if (!c->self)
        return CVK_SUCCESS;
    /* The sides the candidates kept belong to the old positions. */
    cvk_result r = cvk_device_fill_buffer(&s->device, &c->contacts, 0xff, error);
    if (r != CVK_SUCCESS)
        return r;
    uint32_t force = 1;
    memcpy(s->device.staging.mapped, &force, sizeof force);
    cvk_staging_copy job = {&c->frame, 0, offsetof(cvk_gpu_frame, force), sizeof force};
    return cvk_device_copy_from_staging(&s->device, &job, 1, error);
}

cvk_result cvk_collide_searches(cvk_sim* s, uint64_t* out, cvk_error* error)
{
    *out = 0;
    if (!s->collide->self)
        return CVK_SUCCESS;
    cvk_gpu_frame frame;
    cvk_result r = cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd,
                                       &s->collide->frame, &frame, sizeof frame, error);
    if (r == CVK_SUCCESS)
        *out = frame.searches;
    return r;
}

/* The four parts of the contact state in a snapshot, in order. */
static uint32_t snapshot_parts(const cvk_sim* s, cvk_buffer* buffers[4], VkDeviceSize sizes[4])
{
    const cvk_collide* c = s->collide;
    if (!c->self)
        return 0;
    VkDeviceSize n = s->build.particle_count;
    buffers[0] = (cvk_buffer*)&c->frame;
    sizes[0] = sizeof(cvk_gpu_frame);
    buffers[1] = (cvk_buffer*)&c->searched;
    sizes[1] = 16u * n;
    buffers[2] = (cvk_buffer*)&c->contacts;
    sizes[2] = 4u * CVK_CONTACTS_PER_PARTICLE * n;
    buffers[3] = (cvk_buffer*)&c->lists;
    sizes[3] = 4u * (CVK_LIST_HEADER + 2u * n);
    return 4;
}

uint64_t cvk_collide_snapshot_size(const cvk_sim* s)
{
    cvk_buffer* buffers[4];
    VkDeviceSize sizes[4];
    uint64_t total = 0;
    for (uint32_t i = 0, n = snapshot_parts(s, buffers, sizes); i < n; i++)
        total += sizes[i];
    return total;
}

cvk_result cvk_collide_save_snapshot(cvk_sim* s, unsigned char* data, cvk_error* error)
{
    cvk_buffer* buffers[4];
    VkDeviceSize sizes[4];
    cvk_result r = CVK_SUCCESS;
    for (uint32_t i = 0, n = snapshot_parts(s, buffers, sizes); r == CVK_SUCCESS && i < n; i++) {
        r = cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd, buffers[i], data,
                                sizes[i], error);
        data += sizes[i];
    }
    return r;
}

cvk_result cvk_collide_check_snapshot(const cvk_sim* s, const unsigned char* data,
                                     cvk_error* error)
{
    cvk_buffer* buffers[4];
    VkDeviceSize sizes[4];
    if (snapshot_parts(s, buffers, sizes) == 0 || s->collide->edges)
        return CVK_SUCCESS;
    /* Edge pairs are read only by a contact pass built for them. */
    const unsigned char* kept = data + sizes[0] + sizes[1];
    for (VkDeviceSize i = 0; i < sizes[2] / 4u; i++) {
        uint32_t e;
        memcpy(&e, kept + 4u * i, sizeof e);
        if (e != CVK_NO_CONTACT && (e & CVK_EDGE_PAIR) != 0u)
            return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                            "cvk_sim_load_snapshot: the snapshot holds edge contact candidates "
                            "(collision.edges); this simulation has no edge contact");
    }
    return CVK_SUCCESS;
}

cvk_result cvk_collide_load_snapshot(cvk_sim* s, const unsigned char* data, cvk_error* error)
{
    cvk_buffer* buffers[4];
    VkDeviceSize sizes[4];
    cvk_result r = CVK_SUCCESS;
    for (uint32_t i = 0, n = snapshot_parts(s, buffers, sizes); r == CVK_SUCCESS && i < n; i++) {
        r = cvk_device_upload(&s->device, buffers[i], data, sizes[i], error);
        data += sizes[i];
    }
    return r;
}
