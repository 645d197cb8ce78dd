/* The colliders as the host sees them: poses by lib/scene/motion.c and signed distances with the
   formulas of shaders/contact/collide.glsl, for statistics and tests; the substeps' split for a
   fast collider; the device's clock and poses set from the host (a loaded snapshot); the
   scene's instances as contact keeps them apart. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "contact/collide.h"
#include "core/error.h"
#include "core/vec3.h"
#include "plan/state.h"

cvk_pose cvk_collide_pose(const cvk_collide* c, uint32_t index, double t)
{
    if (index >= c->collider_count)
        return cvk_pose_identity();
    return cvk_motion_pose(&c->colliders[index].motion, t);
}

static const float up[3] = {0.0f, 1.0f, 0.0f};

/* The farthest point of collider d's surface from the scene origin, about which its keyframed
   rotations turn it, m (0 for a plane). */
static float reach_from_origin(const cvk_collider_desc* d, const cvk_sdf* f)
{
    switch (d->type) {
    case CVK_COLLIDER_SPHERE: return cvk_length3(d->center) + d->radius;
    case CVK_COLLIDER_BOX: return cvk_length3(d->center) + cvk_length3(d->half_extents);
    case CVK_COLLIDER_CAPSULE: return fmaxf(cvk_length3(d->a), cvk_length3(d->b)) + d->radius;
    case CVK_COLLIDER_FUNNEL: /* radius 1 m at the apex, e^(-height/a) at the far end */
        return cvk_length3(d->apex) + sqrtf(1.0f + d->height * d->height);
    case CVK_COLLIDER_MESH: {
        float most = 0.0f;
        for (uint32_t v = 0; f && v < f->vertex_count; v++)
            most = fmaxf(most, cvk_length3(f->xyz + 3u * v));
        return most;
    }
    default: return 0.0f;
    }
}

float cvk_collide_surface_speed(const cvk_collide* c, uint32_t index)
{
    if (index >= c->collider_count)
        return 0.0f;
    const cvk_collider_desc* d = &c->colliders[index];
    const cvk_keyframe* k = d->motion.keyframes;
    float reach = reach_from_origin(d, c->sdfs ? &c->sdfs[index] : NULL), fastest = 0.0f;
    for (uint32_t i = 0; k && i + 1 < d->motion.keyframe_count; i++) {
        double span = (double)k[i + 1].time - k[i].time;
        if (!(span > 0.0))
            continue;
        float step[3], qa[4], qb[4];
        for (int a = 0; a < 3; a++)
            step[a] = k[i + 1].translation[a] - k[i].translation[a];
        cvk_quat_normalize(k[i].rotation, qa);
        cvk_quat_normalize(k[i + 1].rotation, qb);
        double cosine = fabs((double)qa[0] * qb[0] + (double)qa[1] * qb[1] +
                             (double)qa[2] * qb[2] + (double)qa[3] * qb[3]);
        double angle = 2.0 * acos(cosine < 1.0 ? cosine : 1.0); /* slerp's shorter arc */
        double speed = (cvk_length3(step) + angle * reach) / span;
        fastest = fmaxf(fastest, (float)speed);
    }
    return fastest;
}

static float plane_distance(const cvk_collider_desc* d, const float l[3], float n[3])
{
    float normal[3] = {d->normal[0], d->normal[1], d->normal[2]};
    cvk_normalize3(normal, up);
    float rel[3] = {l[0] - d->point[0], l[1] - d->point[1], l[2] - d->point[2]};
    for (int k = 0; k < 3; k++)
        n[k] = normal[k];
    return cvk_dot3(normal, rel);
}

static float sphere_distance(const float centre[3], float radius, const float l[3], float n[3])
{
    float rel[3] = {l[0] - centre[0], l[1] - centre[1], l[2] - centre[2]};
    float len = cvk_length3(rel);
    for (int k = 0; k < 3; k++)
        n[k] = rel[k];
    cvk_normalize3(n, up);
    return len - radius;
}

static float box_distance(const cvk_collider_desc* d, const float l[3], float n[3])
{
    float q[4], conj[4];
    cvk_quat_normalize(d->rotation, q);
    conj[0] = q[0];
    conj[1] = -q[1];
    conj[2] = -q[2];
    conj[3] = -q[3];
    float rel[3] = {l[0] - d->center[0], l[1] - d->center[1], l[2] - d->center[2]}, b[3];
    cvk_quat_rotate(conj, rel, b);
    float e[3], outside[3], local_n[3] = {0};
    for (int k = 0; k < 3; k++) {
        e[k] = fabsf(b[k]) - d->half_extents[k];
        outside[k] = fmaxf(e[k], 0.0f);
    }
    float inside = fminf(fmaxf(e[0], fmaxf(e[1], e[2])), 0.0f);
    float dist = cvk_length3(outside) + inside;
    if (fmaxf(e[0], fmaxf(e[1], e[2])) > 0.0f) {
        for (int k = 0; k < 3; k++)
            local_n[k] = outside[k] * (b[k] < 0.0f ? -1.0f : 1.0f);
    } else {
        int axis = e[0] >= e[1] && e[0] >= e[2] ? 0 : (e[1] >= e[2] ? 1 : 2);
        local_n[axis] = b[axis] >= 0.0f ? 1.0f : -1.0f;
    }
    cvk_normalize3(local_n, up);
    cvk_quat_rotate(q, local_n, n);
    return dist;
}

static float capsule_distance(const cvk_collider_desc* d, const float l[3], float n[3])
{
    float ab[3] = {d->b[0] - d->a[0], d->b[1] - d->a[1], d->b[2] - d->a[2]};
    float al[3] = {l[0] - d->a[0], l[1] - d->a[1], l[2] - d->a[2]};
    float len2 = cvk_dot3(ab, ab);
    float t = len2 > 0.0f ? fminf(fmaxf(cvk_dot3(al, ab) / len2, 0.0f), 1.0f) : 0.0f;
    float closest[3] = {d->a[0] + t * ab[0], d->a[1] + t * ab[1], d->a[2] + t * ab[2]};
    return sphere_distance(closest, d->radius, l, n);
}

/* The same Gauss-Newton search as funnel_closest in shaders/contact/collide.glsl. */
static float funnel_distance(const cvk_collider_desc* d, const float l[3], float n[3])
{
    float rel[3] = {l[0] - d->apex[0], l[1] - d->apex[1], l[2] - d->apex[2]};
    float rho = sqrtf(rel[0] * rel[0] + rel[2] * rel[2]);
    float radial[3] = {1.0f, 0.0f, 0.0f};
    if (rho > 0.0f) {
        radial[0] = rel[0] / rho;
        radial[2] = rel[2] / rho;
    }
    float a = d->funnel_a, h = d->height;
    float s = fminf(fmaxf(rel[1], -h), 0.0f);
    for (int i = 0; i < 8; i++) {
        float r = expf(s / a), dr = r / a;
        float g = (r - rho) * dr + (s - rel[1]);
        s = fminf(fmaxf(s - g / (dr * dr + 1.0f), -h), 0.0f);
    }
    float to_x = expf(s / a) - rho, to_y = s - rel[1];
    float away[3] = {-to_x * radial[0], -to_y, -to_x * radial[2]};
    float r = expf(s / a);
    float fallback[3] = {radial[0], -r / a, radial[2]};
    cvk_normalize3(fallback, up);
    for (int k = 0; k < 3; k++)
        n[k] = away[k];
    cvk_normalize3(n, fallback);
    return sqrtf(to_x * to_x + to_y * to_y);
}

static float mesh_distance(const cvk_sdf* f, const float l[3], float n[3])
{
    float e = 0.5f * f->voxel;
    for (int k = 0; k < 3; k++) {
        float hi[3] = {l[0], l[1], l[2]}, lo[3] = {l[0], l[1], l[2]};
        hi[k] += e;
        lo[k] -= e;
        n[k] = cvk_sdf_sample(f, hi) - cvk_sdf_sample(f, lo);
    }
    cvk_normalize3(n, up);
    return cvk_sdf_sample(f, l);
}

float cvk_collide_distance(const cvk_collide* c, uint32_t index, double t, const float p[3],
                           float normal[3])
{
    float n[3] = {0.0f, 1.0f, 0.0f};
    if (index >= c->collider_count)
        return INFINITY;
    const cvk_collider_desc* d = &c->colliders[index];
    cvk_pose pose = cvk_collide_pose(c, index, t);
    float l[3];
    cvk_pose_apply_inverse(&pose, p, l);
    float dist;
    switch (d->type) {
    case CVK_COLLIDER_PLANE: dist = plane_distance(d, l, n); break;
    case CVK_COLLIDER_SPHERE: dist = sphere_distance(d->center, d->radius, l, n); break;
    case CVK_COLLIDER_BOX: dist = box_distance(d, l, n); break;
    case CVK_COLLIDER_CAPSULE: dist = capsule_distance(d, l, n); break;
    case CVK_COLLIDER_FUNNEL: dist = funnel_distance(d, l, n); break;
    default: dist = mesh_distance(&c->sdfs[index], l, n); break;
    }
    if (normal)
        cvk_quat_rotate(pose.rotation, n, normal);
    return dist;
}

/* The most of the thickness a keyframed collider's surface may move in one substep with
   self-contact (cvk_collide_split_substeps): pd's, and implicit Euler's. */
#define CVK_COLLIDER_STEP 0.35
#define CVK_COLLIDER_STEP_IMPLICIT 0.175

double cvk_collide_move_limit(bool implicit)
{
    return implicit ? CVK_COLLIDER_STEP_IMPLICIT : CVK_COLLIDER_STEP;
}

/* The fastest collider's surface speed, m/s (0: none moves), and which it is. */
static float fastest_collider(const cvk_collide* c, uint32_t* which)
{
    float fastest = 0.0f;
    *which = 0;
    for (uint32_t i = 0; i < c->collider_count; i++) {
        float v = cvk_collide_surface_speed(c, i);
        if (v > fastest) {
            fastest = v;
            *which = i;
        }
    }
    return fastest;
}

double cvk_collide_fastest_move(const cvk_sim* s, const cvk_collide* c)
{
    uint32_t which;
    return (double)fastest_collider(c, &which) * s->params.dt / c->thickness;
}

void cvk_collide_split_substeps(cvk_sim* s, cvk_collide* c, bool implicit)
{
    uint32_t which;
    float fastest = fastest_collider(c, &which);
    double move = (double)fastest * s->params.dt;
    double most = cvk_collide_move_limit(implicit) * c->thickness;
    if (!(move > most))
        return;
    double parts = ceil(move / most);
    double room = floor((double)CVK_MAX_SUBSTEPS / s->params.substeps);
    uint32_t k = (uint32_t)(parts < room ? parts : room);
    if (k < 2)
        return;
    const char* name = c->colliders[which].name;
    snprintf(s->split_note, sizeof s->split_note,
             "substeps split: %u substeps of %.3g ms a frame run as %u of %.3g ms, so that "
             "collider %u%s%s%s (%.3g m/s) moves at most %.2g of the thickness a substep",
             s->params.substeps, 1e3 * s->params.dt, k * s->params.substeps,
             1e3 * s->params.dt / k, which, name ? " \"" : "", name ? name : "",
             name ? "\"" : "", fastest, fastest * s->params.dt / k / c->thickness);
    s->params.damping = (float)(1.0 - pow(1.0 - (double)s->params.damping, 1.0 / k));
    s->params.dt /= k;
    s->params.substeps *= k;
    if (s->note_count < sizeof s->notes / sizeof s->notes[0])
        s->notes[s->note_count++] = s->split_note;
}

cvk_result cvk_collide_set_step(cvk_sim* s, uint64_t step, cvk_error* error)
{
    cvk_gpu_frame frame = {.step = (uint32_t)step, .search = 1, .force = 1};
    cvk_result r = cvk_device_upload(&s->device, &s->collide->frame, &frame, sizeof frame, error);
    return r == CVK_SUCCESS ? cvk_collide_write_poses(s, step, error) : r;
}

cvk_result cvk_collide_write_poses(cvk_sim* s, uint64_t step, cvk_error* error)
{
    const cvk_collide* c = s->collide;
    if (c->collider_count == 0)
        return CVK_SUCCESS;
    cvk_gpu_pose* poses = calloc(c->collider_count, sizeof *poses);
    if (!poses)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %u collider poses",
                        c->collider_count);
    cvk_collide_poses_at(c, step, s->params.dt, poses);
    cvk_result r = cvk_device_upload(&s->device, &s->collide->poses, poses, c->collider_count * sizeof *poses, error);
    free(poses);
    return r;
}

/* The contact pass then tests each collider with its type's code alone (contact/collide.glsl's
   FOR_EACH_COLLIDER); one type needs no runs, as the constant's type bits leave that type's
   code alone. */
uint32_t cvk_collide_runs(const cvk_collide* c, uint32_t* runs)
{
    uint32_t n = c->instance_colliders, bits = 0, count = 0, length = 0;
    *runs = 0;
    for (uint32_t j = 0; j < n; j++) {
        cvk_collider_type type = c->colliders[j].type;
        for (uint32_t i = 1; i < c->instance_count; i++)
            if (c->colliders[(size_t)i * n + j].type != type)
                return 0;
        if (j == 0 || type != c->colliders[j - 1].type) {
            if (count == CVK_COLLIDER_RUNS)
                return 0;
            count++;
            length = 0;
        }
        if (++length > CVK_COLLIDER_RUN_MAX)
            return 0;
        uint32_t shift = CVK_COLLIDER_RUNS_SHIFT + 6u * (count - 1);
        bits = (bits & ~(63u << shift)) | (((uint32_t)type + 1u) | length << 3) << shift;
    }
    if (count < 2)
        return 0;
    *runs = count;
    return bits;
}

_Static_assert(CVK_PIPE_PD_CONTACT_RUNS4 == CVK_PIPE_PD_CONTACT_RUNS2 + CVK_COLLIDER_RUNS - 2 &&
                   CVK_PIPE_CONTACT_CHECK_RUNS4 ==
                       CVK_PIPE_CONTACT_CHECK_RUNS2 + CVK_COLLIDER_RUNS - 2 &&
                   CVK_PIPE_CONTACT_CHECK_EXCEED_RUNS4 ==
                       CVK_PIPE_CONTACT_CHECK_EXCEED_RUNS2 + CVK_COLLIDER_RUNS - 2,
               "one pipeline a run count, in order");

bool cvk_collide_has_funnels(const cvk_collide* c)
{
    return (c->types & (1u << CVK_COLLIDER_FUNNEL)) != 0;
}

cvk_pipeline_id cvk_collide_pipeline(const cvk_collide* c, cvk_pipeline_id generic,
                                     cvk_pipeline_id runs2)
{
    return c->runs ? (cvk_pipeline_id)(runs2 + c->runs - 2) : generic;
}

uint32_t cvk_collide_instance_count(const cvk_build* b, const cvk_scene_desc* scene)
{
    uint32_t n = scene->instances.count;
    if (n <= 1 || b->cloth_count % n != 0 || scene->collider_count % n != 0)
        return 1;
    return n;
}

/* Each particle's instance (lib/scene/scene_instances.c lays the copies out one after
   another, so a particle's cloth tells its copy). */
cvk_result cvk_collide_find_instances(struct cvk_sim* s, cvk_collide* c, const cvk_scene_desc* scene,
                                      cvk_error* error)
{
    const cvk_build* b = &s->build;
    uint32_t n = cvk_collide_instance_count(b, scene);
    c->instance_count = 1;
    c->instance_colliders = c->collider_count;
    if (n == 1)
        return CVK_SUCCESS;
    c->instance_of = malloc((b->particle_count ? b->particle_count : 1) * sizeof *c->instance_of);
    if (!c->instance_of)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "instances: out of host memory for %u particles", b->particle_count);
    uint32_t cloths = b->cloth_count / n;
    for (uint32_t p = 0; p < b->particle_count; p++)
        c->instance_of[p] = cvk_build_cloth_of(b, p) / cloths;
    c->instance_count = n;
    c->instance_colliders = c->collider_count / n;
    return CVK_SUCCESS;
}

cvk_result cvk_collide_triangle_instances(const cvk_build* b, uint32_t instance_count,
                                          uint32_t** out, cvk_error* error)
{
    *out = NULL;
    if (instance_count <= 1)
        return CVK_SUCCESS;
    uint32_t* t = malloc((b->triangle_count ? b->triangle_count : 1) * sizeof *t);
    if (!t)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "instances: out of host memory for %u triangles", b->triangle_count);
    uint32_t cloths = b->cloth_count / instance_count;
    for (uint32_t i = 0; i < b->triangle_count; i++)
        t[i] = cvk_build_cloth_of_user(b, b->triangles[3 * (size_t)i]) / cloths;
    *out = t;
    return CVK_SUCCESS;
}
