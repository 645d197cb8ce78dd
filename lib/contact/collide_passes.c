/* The contact module's passes at the start of each substep: the colliders' poses (and the
   frame state's advance), and for self-contact the decision to detect, the hash of the
   positions, detection and the bounds (collide.h); and the contact state as the host sees it. */
#include <stdlib.h>
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
    /* The cells: the radius plus the longest edge (midpoints) or plus the farthest a corner is
       from its triangle's centroid (centroids), so the 27 cells around a point hold every
       midpoint or centroid a pair within the radius needs (contact_edges.comp,
       contact_detect.comp). The decision writes them from what each detection measures
       (contact_decide.comp, before every build); this is only the first, with the cloth
       stretched by up to 50 %. */
    float cell = c->radius + c->longest;
    /* Salted with the instances (several copies), so that copies at one place fill different
       slots and detection walks past few of another copy's points. */
    bool salted = c->instance_of != NULL;
    uint32_t tc = s->build.triangle_count;
    cvk_hash_desc desc = {tc ? tc : 1, cell, &c->centroids, true,
                          salted ? &c->triangle_instances : NULL};
    cvk_result r = cvk_hash_create(s->device.context, &desc, &c->face_hash, error);
    if (r != CVK_SUCCESS)
        return r;
    /* The edges' midpoints, which edge–edge detection walks (contact_edges.comp): an edge
       within the radius of another has its midpoint within the radius plus half of each
       edge's length of the other's, within the same cells. */
    cvk_hash_desc edge_desc = {c->edge_count ? c->edge_count : 1, cell, &c->midpoints, true,
                               salted ? &c->edge_instances : NULL};
    r = cvk_hash_create(s->device.context, &edge_desc, &c->edge_hash, error);
    if (r != CVK_SUCCESS)
        return r;
    /* The walks: the contact set and one hash; the fused detection (contact_faces_fused.comp,
       contact_edges_fused.comp): its hash as set 1 and the midpoints' as set 2 (whose cells
       the decision decides), and the build's push data before the walks'. */
    VkDescriptorSetLayout layouts[3] = {c->set_layout, c->face_hash.set_layout,
                                        c->edge_hash.set_layout};
    r = cvk_cached_pipeline_layout(s->device.context, layouts, 2, VK_SHADER_STAGE_COMPUTE_BIT,
                                   sizeof(cvk_contact_push), &c->detect_layout, error);
    if (r != CVK_SUCCESS)
        return r;
    return cvk_cached_pipeline_layout(s->device.context, layouts, 3, VK_SHADER_STAGE_COMPUTE_BIT,
                                      sizeof(cvk_contact_hash_push), &c->fused_layout, error);
}

/* One phase of contact_check.comp (over every particle, a pipeline a phase; the build for the
   scene's run count where the colliders' types are fixed, cvk_collide.runs, as the contact
   pass's) or contact_decide.comp (one invocation; phase 1 writes indirect commands). */
static void add_decision(cvk_sim* s, cvk_plan* plan, cvk_pipeline_id pipeline, uint32_t phase,
                         const cvk_hash* hash, const char* note)
{
    cvk_collide* c = s->collide;
    if (pipeline == CVK_PIPE_CONTACT_CHECK)
        pipeline = phase == 0 ? cvk_collide_pipeline(c, pipeline, CVK_PIPE_CONTACT_CHECK_RUNS2)
                              : cvk_collide_pipeline(c, CVK_PIPE_CONTACT_CHECK_EXCEED,
                                                     CVK_PIPE_CONTACT_CHECK_EXCEED_RUNS2);
    bool decide = pipeline == CVK_PIPE_CONTACT_DECIDE;
    uint32_t count = decide ? 1 : s->build.particle_count;
    cvk_contact_push push = {0, count, phase, cvk_plan_walk_group_items(plan)};
    cvk_op* op = cvk_plan_dispatch(plan, cvk_plan_pass(plan, "contacts"), pipeline,
                                   c->detect_layout, c->set, CVK_DOMAIN_PARTICLES, 0, count,
                                   &push, sizeof push);
    if (!op)
        return;
    op->set1 = hash->set;
    if (decide)
        op->groups = 1;
    if (decide && phase >= 1)
        op->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT;
    snprintf(op->note, sizeof op->note, "%s", note);
}

/* Detection's passes, dispatched through the commands the decision wrote (no workgroups at a
   substep that does not detect): at word `slot` of `commands`, the work lists (CVK_LIST_*) or
   the edge cells' buffer (CVK_CELLS_*). */
static cvk_op* add_detection(cvk_sim* s, cvk_plan* plan, const char* pass,
                             cvk_pipeline_id pipeline, uint32_t count, const cvk_buffer* commands,
                             uint32_t slot, const cvk_hash* hash, const char* note)
{
    cvk_collide* c = s->collide;
    cvk_contact_push push = {0, count, 0, cvk_plan_walk_group_items(plan)};
    cvk_op* op = cvk_plan_dispatch_indirect(plan, cvk_plan_pass(plan, pass), pipeline,
                                            c->detect_layout, c->set, CVK_DOMAIN_PARTICLES,
                                            commands->buffer, 4u * slot, &push, sizeof push);
    if (!op)
        return NULL;
    op->count = count;
    op->set1 = hash->set;
    snprintf(op->note, sizeof op->note, "%s", note);
    return op;
}

/* One of the two fused detection dispatches (one workgroup): `hash`'s build of `points`,
   bound as set 1, and the contact passes over `count` items after it. */
static cvk_result add_fused_detection(cvk_sim* s, cvk_plan* plan, const char* pass,
                                      cvk_pipeline_id pipeline, const cvk_hash* hash,
                                      uint32_t points, uint32_t count, const char* note,
                                      cvk_error* error)
{
    cvk_collide* c = s->collide;
    cvk_hash_push build;
    cvk_result r = cvk_hash_build_push(hash, points, &build, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_contact_hash_push push;
    _Static_assert(sizeof push == sizeof build + sizeof(cvk_contact_push), "build, then contact");
    cvk_contact_push contact = {0, count, 0, cvk_plan_walk_group_items(plan)};
    memcpy(&push, &build, sizeof build);
    memcpy((char*)&push + sizeof build, &contact, sizeof contact);
    cvk_op* op = cvk_plan_dispatch(plan, cvk_plan_pass(plan, pass), pipeline, c->fused_layout,
                                   c->set, CVK_DOMAIN_PARTICLES, 0, count, &push, sizeof push);
    if (op) {
        op->groups = 1; /* one workgroup: its barriers order the passes */
        op->set1 = hash->set;
        op->set2 = c->edge_hash.set;
        op->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT; /* the work lists' commands */
        snprintf(op->note, sizeof op->note, "%s", note);
    }
    return cvk_plan_check(plan, error);
}

/* Where the plan fuses (cvk_plan.fused): detection in two dispatches of one workgroup each —
   the decision, the faces' hash and their walk (contact_faces_fused.comp), then the
   midpoints' hash, the edges' walks and the bounds (contact_edges_fused.comp) — each doing
   nothing of a detection at a substep that does not detect. */
static cvk_result add_fused_self_contact(cvk_sim* s, cvk_plan* plan, cvk_error* error)
{
    cvk_collide* c = s->collide;
    char note[128];
    snprintf(note, sizeof note,
             "past %.2g of a bound? detect or not; if so: measure, the faces' hash, vertices "
             "against faces; one workgroup of %u", (double)CVK_REDETECT_FRACTION,
             plan->fused_workgroup_size);
    cvk_result r = add_fused_detection(s, plan, "contacts", CVK_PIPE_CONTACT_FACES_FUSED,
                                       &c->face_hash, s->build.triangle_count,
                                       s->build.particle_count, note, error);
    if (r != CVK_SUCCESS)
        return r;
    snprintf(note, sizeof note,
             "if detecting: the midpoints' hash, edges against edges within %.3g m, bounds: "
             "%.2g of the nearest; one workgroup of %u", (double)c->radius,
             (double)CVK_BOUND_GAMMA, plan->fused_workgroup_size);
    return add_fused_detection(s, plan, "detect edges", CVK_PIPE_CONTACT_EDGES_FUSED,
                               &c->edge_hash, c->edge_count, c->edge_count, note, error);
}

static cvk_result add_self_contact(cvk_sim* s, cvk_plan* plan, cvk_error* error)
{
    cvk_collide* c = s->collide;
    uint32_t n = s->build.particle_count;
    const cvk_hash *faces = &c->face_hash, *midpoints = &c->edge_hash;
    char note[128];
    if (plan->fused)
        return add_fused_self_contact(s, plan, error);
    add_decision(s, plan, CVK_PIPE_CONTACT_CHECK, 0, faces, "bounds of the extrapolated moves");
    add_decision(s, plan, CVK_PIPE_CONTACT_DECIDE, 0, faces, "the shift without detection");
    snprintf(note, sizeof note, "moves past %.2g of a bound?", (double)CVK_REDETECT_FRACTION);
    add_decision(s, plan, CVK_PIPE_CONTACT_CHECK, 1, faces, note);
    add_decision(s, plan, CVK_PIPE_CONTACT_DECIDE, 1, faces, "detect or not: commands, shift");
    add_detection(s, plan, "detect edges", CVK_PIPE_CONTACT_EDGES_MEASURE, c->edge_count,
                  &c->lists, CVK_LIST_EDGE_GROUPS, faces,
                  "the longest edge, the midpoints, the centroids and their corners' reach");
    add_decision(s, plan, CVK_PIPE_CONTACT_DECIDE, 2, faces,
                 "centroid cells: the radius + the farthest corner from a centroid");
    add_decision(s, plan, CVK_PIPE_CONTACT_DECIDE, 3, midpoints,
                 "midpoint cells: the radius + the longest edge");
    cvk_result r = cvk_hash_add_passes(faces, plan, s->build.triangle_count, true, error);
    if (r == CVK_SUCCESS)
        r = cvk_hash_add_passes(midpoints, plan, c->edge_count, true, error);
    if (r != CVK_SUCCESS)
        return r;
    /* The edges' phase 2 writes the listing pass's indirect command (the edges with pairs).
       Every pass here binds the work lists writable (the listing pass too, as far as the
       shader's code says: its appends are specialised away), so each is followed by the barrier
       the lists' commands need. */
    struct {
        const char* pass;
        cvk_pipeline_id pipeline;
        uint32_t count;
        const cvk_buffer* commands;
        uint32_t slot;
        const cvk_hash* hash;
        const char* what;
    } passes[] = {
        {"detect faces", CVK_PIPE_CONTACT_DETECT, n, &c->lists, CVK_LIST_PARTICLE_GROUPS, faces,
         "vertices against faces within %.3g m"},
        {"detect edges", CVK_PIPE_CONTACT_EDGES_CELLS, c->edge_count, &c->lists,
         CVK_LIST_EDGE_GROUPS, midpoints, "one edge a cell of the midpoints"},
        {"detect edges", CVK_PIPE_CONTACT_EDGES_GATHER, c->edge_count, &c->cells, 0, midpoints,
         "each cell's list of the midpoints around it"},
        {"detect edges", CVK_PIPE_CONTACT_EDGES, c->edge_count, &c->lists, CVK_LIST_EDGE_GROUPS,
         midpoints, "edges against edges within %.3g m: distances, each pair once"},
        {"detect edges", CVK_PIPE_CONTACT_EDGES_WALK, c->edge_count, &c->cells, CVK_CELLS_WALK,
         midpoints, "the same for the edges past their cells' lists: walked"},
        {"detect edges", CVK_PIPE_CONTACT_EDGES_NEAREST, c->edge_count, &c->lists,
         CVK_LIST_EDGE_GROUPS, midpoints, "each edge's nearest pairs from its bucket"},
        {"detect edges", CVK_PIPE_CONTACT_EDGES_LISTS, c->edge_count, &c->lists,
         CVK_LIST_EDGE_PAIRS_GROUPS, midpoints,
         "the pairs of the edges past their buckets: walked again"},
    };
    for (size_t i = 0; i < sizeof passes / sizeof passes[0]; i++) {
        snprintf(note, sizeof note, passes[i].what, (double)c->radius);
        cvk_op* op = add_detection(s, plan, passes[i].pass, passes[i].pipeline, passes[i].count,
                                   passes[i].commands, passes[i].slot, passes[i].hash, note);
        if (op)
            op->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT;
    }
    snprintf(note, sizeof note, "bounds: %.2g of the nearest", (double)CVK_BOUND_GAMMA);
    cvk_op* bounds = add_detection(s, plan, "bounds", CVK_PIPE_CONTACT_BOUND, n, &c->lists,
                                   CVK_LIST_PARTICLE_GROUPS, faces, note);
    if (bounds) /* it writes the cloth contact pass's indirect command */
        bounds->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT;
    return CVK_SUCCESS;
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
    if (c->self && (s->build.free_count > 0 || s->build.attached_count > 0)) {
        cvk_result r = add_self_contact(s, plan, error);
        if (r != CVK_SUCCESS)
            return r;
    }
    return cvk_plan_check(plan, error);
}

/* ---- the search's state on the host: written positions, statistics, snapshots ----------- */

cvk_result cvk_collide_positions_written(cvk_sim* s, const float* x, const float* v,
                                         cvk_error* error)
{
    cvk_collide* c = s->collide;
    if (!c->self)
        return CVK_SUCCESS;
    size_t n = s->build.particle_count;
    float* before = malloc(16u * (n ? n : 1));
    if (!before)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the contact state");
    float dt = s->params.dt;
    for (size_t p = 0; p < n; p++) {
        for (int k = 0; k < 3; k++)
            before[4 * p + k] = x[3 * p + k] - (v ? dt * v[3 * p + k] : 0.0f);
        before[4 * p + 3] = 0.0f;
    }
    cvk_result r = cvk_device_upload(&s->device, &c->previous, before, 16u * (VkDeviceSize)n, error);
    free(before);
    if (r != CVK_SUCCESS)
        return r;
    /* Detect at the next substep; and a new state: a detection cut short before it no longer
       holds (cvk_sim_watch_reset clears the watch's copy). */
    uint32_t words[2] = {1, 0};
    memcpy(s->device.staging.mapped, words, sizeof words);
    cvk_staging_copy jobs[] = {{&c->frame, 0, offsetof(cvk_gpu_frame, force), sizeof(uint32_t)},
                               {&c->frame, sizeof(uint32_t), offsetof(cvk_gpu_frame, cut),
                                sizeof(uint32_t)}};
    return cvk_device_copy_from_staging(&s->device, jobs, 2, error);
}

cvk_result cvk_collide_counts(cvk_sim* s, uint64_t* searches, uint64_t* held,
                              double* held_fraction, uint64_t* crowded, bool* cut,
                              cvk_error* error)
{
    *searches = *held = *crowded = 0;
    *held_fraction = 0.0;
    *cut = false;
    if (!s->collide->self)
        return CVK_SUCCESS;
    cvk_gpu_frame frame;
    cvk_result r = cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd,
                                       &s->collide->frame, &frame, sizeof frame, error);
    if (r == CVK_SUCCESS) {
        *searches = frame.searches;
        *cut = frame.cut != 0;
        *held = (uint64_t)frame.held_hi << 32 | frame.held_lo;
        double counted = (double)frame.held_substeps * s->build.free_count;
        *held_fraction = counted > 0.0 ? (double)*held / counted : 0.0;
        *crowded = (uint64_t)frame.crowded_hi << 32 | frame.crowded_lo;
    }
    return r;
}

/* The parts of the contact state in a snapshot, in order. */
#define SNAPSHOT_PARTS 7
static uint32_t snapshot_parts(const cvk_sim* s, cvk_buffer* buffers[SNAPSHOT_PARTS],
                               VkDeviceSize sizes[SNAPSHOT_PARTS])
{
    const cvk_collide* c = s->collide;
    if (!c->self)
        return 0;
    VkDeviceSize n = s->build.particle_count, ec = c->edge_count ? c->edge_count : 1;
    buffers[0] = (cvk_buffer*)&c->frame;
    sizes[0] = sizeof(cvk_gpu_frame);
    buffers[1] = (cvk_buffer*)&c->searched;
    sizes[1] = 16u * n;
    buffers[2] = (cvk_buffer*)&c->contacts;
    sizes[2] = 4u * CVK_CONTACTS_PER_PARTICLE * n;
    buffers[3] = (cvk_buffer*)&c->edge_contacts;
    sizes[3] = 4u * CVK_CONTACTS_PER_EDGE * ec;
    buffers[4] = (cvk_buffer*)&c->previous;
    sizes[4] = 16u * n;
    buffers[5] = (cvk_buffer*)&c->lists;
    sizes[5] = 4u * (CVK_LIST_HEADER + n + ec);
    buffers[6] = (cvk_buffer*)&c->sides;
    sizes[6] = 4u * n * (1u + 2u * CVK_SIDES_PER_PARTICLE);
    return SNAPSHOT_PARTS;
}

uint64_t cvk_collide_snapshot_size(const cvk_sim* s)
{
    cvk_buffer* buffers[SNAPSHOT_PARTS];
    VkDeviceSize sizes[SNAPSHOT_PARTS];
    uint64_t total = 0;
    for (uint32_t i = 0, n = snapshot_parts(s, buffers, sizes); i < n; i++)
        total += sizes[i];
    return total;
}

cvk_result cvk_collide_save_snapshot(cvk_sim* s, unsigned char* data, cvk_error* error)
{
    cvk_buffer* buffers[SNAPSHOT_PARTS];
    VkDeviceSize sizes[SNAPSHOT_PARTS];
    cvk_result r = CVK_SUCCESS;
    for (uint32_t i = 0, n = snapshot_parts(s, buffers, sizes); r == CVK_SUCCESS && i < n; i++) {
        r = cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd, buffers[i], data,
                                sizes[i], error);
        data += sizes[i];
    }
    return r;
}

cvk_result cvk_collide_load_snapshot(cvk_sim* s, const unsigned char* data, cvk_error* error)
{
    cvk_buffer* buffers[SNAPSHOT_PARTS];
    VkDeviceSize sizes[SNAPSHOT_PARTS];
    cvk_result r = CVK_SUCCESS;
    for (uint32_t i = 0, n = snapshot_parts(s, buffers, sizes); r == CVK_SUCCESS && i < n; i++) {
        r = cvk_device_upload(&s->device, buffers[i], data, sizes[i], error);
        data += sizes[i];
    }
    return r;
}
