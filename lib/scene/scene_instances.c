/* A scene file's "instances" block: the scene's cloths, colliders and attachments repeated,
   copy k translated by its offset. Checked on the scene as written, then expanded in place,
   before the whole description is checked; the copies are plain cloths, colliders and
   attachments laid out copy by copy, so every pass runs over all of them in the dispatches it
   runs over one, and a particle's cloth tells its copy: it meets only that copy's colliders
   and, with self-contact, that copy's cloths (lib/contact/collide.h). */
#include "scene/scene_read.h"

#include <inttypes.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

static void offset_of(const cvk_instances_desc* in, uint32_t k, float out[3])
{
    for (int a = 0; a < 3; a++)
        out[a] = in->offsets ? in->offsets[k][a] : (float)k * in->spacing[a];
}

static void translate(float v[3], const float o[3])
{
    for (int a = 0; a < 3; a++)
        v[a] += o[a];
}

static void translate_box(cvk_box3* box, const float o[3])
{
    translate(box->min, o);
    translate(box->max, o);
}

/* Particles a copy of the scene holds, from its grids (a mesh's are known only once read). */
static uint64_t grid_particles(const cvk_scene_desc* d)
{
    uint64_t n = 0;
    for (uint32_t c = 0; c < d->cloth_count; c++)
        if (!d->cloths[c].mesh)
            n += (uint64_t)d->cloths[c].grid[0] * d->cloths[c].grid[1];
    return n;
}

/* What the block must be, on the scene as written (count already in desc->instances). */
static bool check_block(const cvk_scene_desc* d, bool has_count, uint32_t offset_count,
                        cvk_scene_issue* issue)
{
    const cvk_instances_desc* in = &d->instances;
    if (has_count && in->offsets && in->count != offset_count)
        return cvk_issue_at(issue, "instances.offsets", "has %" PRIu32 " offsets for %" PRIu32
                            " copies (instances.count); give one per copy", offset_count,
                            in->count);
    if (!cvk_check_count_range(issue, in->offsets ? "instances.offsets" : "instances.count",
                               in->count, 1, CVK_MAX_INSTANCES))
        return false;
    if (!cvk_check_position(issue, "instances.spacing", in->spacing, 3))
        return false;
    char path[CVK_KEY_PATH_MAX];
    for (uint32_t k = 0; in->offsets && k < in->count; k++)
        if (!cvk_check_position(issue, cvk_key_join_index(path, "instances.offsets", k),
                                in->offsets[k], 3))
            return false;
    float last[3];
    offset_of(in, in->count - 1, last);
    for (int a = 0; !in->offsets && a < 3; a++)
        if (!(fabs((double)last[a]) <= CVK_MAX_COORDINATE))
            return cvk_issue_at(issue, "instances.spacing", "%" PRIu32 " copies %s m apart "
                                "reach %s m, more than %g m from the origin", in->count,
                                cvk_float_text(in->spacing[a]).text,
                                cvk_float_text(last[a]).text, CVK_MAX_COORDINATE);
    if (in->count == 1)
        return true;
    uint64_t cloths = (uint64_t)d->cloth_count * in->count;
    if (cloths > CVK_MAX_INSTANCES)
        return cvk_issue_at(issue, "instances.count", "%" PRIu32 " copies of %" PRIu32
                            " cloths make %" PRIu64 ", more than the %u a scene holds",
                            in->count, d->cloth_count, cloths, CVK_MAX_INSTANCES);
    uint64_t particles = grid_particles(d) * in->count;
    if (particles > CVK_MAX_PARTICLES)
        return cvk_issue_at(issue, "instances.count", "%" PRIu32 " copies of %" PRIu64
                            " particles make %" PRIu64 ", more than clothvk supports (%" PRIu64 ")",
                            in->count, grid_particles(d), particles, CVK_MAX_PARTICLES);
    if ((uint64_t)d->collider_count * in->count > CVK_MAX_COLLIDERS)
        return cvk_issue_at(issue, "instances.count", "%" PRIu32 " copies of %" PRIu32
                            " collider%s make %" PRIu64 ", more than the %u a scene holds",
                            in->count, d->collider_count, d->collider_count == 1 ? "" : "s",
                            (uint64_t)d->collider_count * in->count, CVK_MAX_COLLIDERS);
    for (uint32_t a = 0; a < d->attachment_count; a++) {
        const cvk_motion* m = &d->attachments[a].motion;
        for (uint32_t k = 0; k < m->keyframe_count; k++) {
            const float* q = m->keyframes[k].rotation;
            if (q[1] != 0.0f || q[2] != 0.0f || q[3] != 0.0f) {
                cvk_key_path(path, "attachments.%" PRIu32 ".keyframes.%" PRIu32 ".rotation", a, k);
                return cvk_issue_at(issue, path, "turns the attached particles about the world "
                                    "origin, which would move each of the %" PRIu32 " copies "
                                    "(instances.count) differently; copies take attachments "
                                    "that only translate", in->count);
            }
        }
    }
    return true;
}

/* A collider moved by o: a static one's shape, a moving one's keyframes (the shape is posed
   by rotation, then translation, so only the translation may carry the offset). */
static bool translate_collider(cvk_reader* rd, cvk_collider_desc* c, const float o[3])
{
    if (c->motion.keyframe_count > 0) {
        cvk_keyframe* keys = cvk_blocks_alloc(rd->blocks, c->motion.keyframe_count, sizeof *keys);
        if (!keys)
            return false;
        memcpy(keys, c->motion.keyframes, c->motion.keyframe_count * sizeof *keys);
        for (uint32_t k = 0; k < c->motion.keyframe_count; k++)
            translate(keys[k].translation, o);
        c->motion.keyframes = keys;
        return true;
    }
    switch (c->type) {
    case CVK_COLLIDER_PLANE:
        translate(c->point, o);
        break;
    case CVK_COLLIDER_SPHERE:
    case CVK_COLLIDER_BOX:
        translate(c->center, o);
        break;
    case CVK_COLLIDER_CAPSULE:
        translate(c->a, o);
        translate(c->b, o);
        break;
    case CVK_COLLIDER_FUNNEL:
        translate(c->apex, o);
        break;
    case CVK_COLLIDER_MESH:
    case CVK_COLLIDER_TYPE_COUNT:
        translate(c->transform.translation, o);
        break;
    }
    return true;
}

static bool expand(cvk_reader* rd, cvk_scene_desc* d)
{
    const uint32_t n = d->instances.count;
    cvk_cloth_desc* cloths = cvk_blocks_alloc(rd->blocks, (size_t)n * d->cloth_count, sizeof *cloths);
    cvk_collider_desc* colliders =
        cvk_blocks_alloc(rd->blocks, (size_t)n * d->collider_count + 1, sizeof *colliders);
    cvk_attachment_desc* attachments =
        cvk_blocks_alloc(rd->blocks, (size_t)n * d->attachment_count + 1, sizeof *attachments);
    if (!cloths || !colliders || !attachments)
        return false;
    for (uint32_t k = 0; k < n; k++) {
        float o[3];
        offset_of(&d->instances, k, o);
        for (uint32_t c = 0; c < d->cloth_count; c++) {
            cvk_cloth_desc* cloth = &cloths[(size_t)k * d->cloth_count + c];
            *cloth = d->cloths[c];
            translate(cloth->mesh ? cloth->transform.translation : cloth->origin, o);
            if (cloth->use_pin_box)
                translate_box(&cloth->pin_box, o);
        }
        for (uint32_t c = 0; c < d->collider_count; c++) {
            cvk_collider_desc* collider = &colliders[(size_t)k * d->collider_count + c];
            *collider = d->colliders[c];
            if (!translate_collider(rd, collider, o))
                return false;
        }
        for (uint32_t a = 0; a < d->attachment_count; a++) {
            cvk_attachment_desc* attachment = &attachments[(size_t)k * d->attachment_count + a];
            *attachment = d->attachments[a];
            attachment->cloth += k * d->cloth_count;
            if (attachment->use_pin_box)
                translate_box(&attachment->pin_box, o);
        }
    }
    d->cloths = cloths;
    d->cloth_count *= n;
    d->colliders = d->collider_count ? colliders : d->colliders;
    d->collider_count *= n;
    d->attachments = d->attachment_count ? attachments : d->attachments;
    d->attachment_count *= n;
    return true;
}

cvk_result cvk_reader_expand_instances(cvk_reader* rd, json_t* block, cvk_scene_desc* desc)
{
    json_t* offsets = json_object_get(block, "offsets");
    uint32_t offset_count = (uint32_t)json_array_size(offsets);
    bool has_count = json_object_get(block, "count") != NULL;
    if (!has_count) /* one copy per offset, or the scene as written */
        desc->instances.count = desc->instances.offsets ? offset_count : 1;
    cvk_scene_issue issue;
    if (!check_block(desc, has_count, offset_count, &issue))
        return cvk_reader_fail_problem(rd, issue.path, issue.problem);
    if (desc->instances.count > 1 && !expand(rd, desc))
        return cvk_reader_fail_memory(rd);
    return CVK_SUCCESS;
}

/* ---- the block's keys ---- */

static cvk_result read_offsets(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                               void* dest)
{
    (void)f;
    cvk_instances_desc* in = dest;
    if (!json_is_array(value) || json_array_size(value) == 0)
        return cvk_reader_fail_type(rd, path, "a non-empty array of [x, y, z] offsets", value);
    size_t count = json_array_size(value);
    if (count > CVK_MAX_INSTANCES)
        return cvk_reader_fail_at(rd, path, "%zu offsets, more than the %u copies a scene may make",
                                  count, CVK_MAX_INSTANCES);
    float (*offsets)[3] = cvk_blocks_alloc(rd->blocks, count, sizeof *offsets);
    if (!offsets)
        return cvk_reader_fail_memory(rd);
    static const cvk_field xyz = {.key = "offsets", .read = cvk_read_floats, .count = 3};
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < count; i++) {
        cvk_json_join_index(element, path, i);
        cvk_result r = cvk_read_floats(rd, &xyz, json_array_get(value, i), element, offsets[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    in->offsets = (const float (*)[3])offsets; /* their number: cvk_reader_expand_instances */
    return CVK_SUCCESS;
}

static const cvk_field instances_fields[] = {
    {.key = "count", .read = cvk_read_uint, .offset = offsetof(cvk_instances_desc, count), .min = 1},
    {.key = "spacing", .read = cvk_read_floats, .offset = offsetof(cvk_instances_desc, spacing), .count = 3},
    {.key = "offsets", .read = read_offsets, .offset = 0},
};
static const cvk_table instances_table = FIELDS(instances_fields);

cvk_result cvk_read_instances(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    cvk_scene_desc* desc = dest;
    if (!json_is_object(value))
        return cvk_reader_fail_type(rd, path, "an object (count, spacing or offsets)", value);
    return cvk_read_object(rd, &instances_table, value, path, &desc->instances);
}
