/* The renderer's camera over time: render.camera_keyframes kept as two translation-only
   motions (the eye's and the target's), so a camera follows the keyframe rules of lib/scene/motion.c
   (straight lines between keyframes, held outside them, an optional loop), and the view
   resolved for a time. */
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "render/render_internal.h"

/* Copies the camera keyframes into the eye and target paths. */
cvk_result cvk_render_camera_create(cvk_renderer* rd, const cvk_render_desc* desc, cvk_error* error)
{
    rd->desc.camera_keyframes = NULL;
    rd->desc.camera_keyframe_count = 0;
    uint32_t n = desc->camera_keyframe_count;
    if (n == 0)
        return CVK_SUCCESS;
    cvk_keyframe* eye = calloc(n, sizeof *eye);
    cvk_keyframe* target = calloc(n, sizeof *target);
    if (!eye || !target) {
        free(eye);
        free(target);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %" PRIu32 " camera keyframes", n);
    }
    for (uint32_t i = 0; i < n; i++) {
        const cvk_camera_keyframe* k = &desc->camera_keyframes[i];
        eye[i] = (cvk_keyframe){.time = k->time, .rotation = {1.0f, 0.0f, 0.0f, 0.0f}};
        target[i] = (cvk_keyframe){.time = k->time, .rotation = {1.0f, 0.0f, 0.0f, 0.0f}};
        memcpy(eye[i].translation, k->eye, sizeof k->eye);
        memcpy(target[i].translation, k->target, sizeof k->target);
    }
    rd->eye_path = (cvk_motion){eye, n, desc->camera_loop};
    rd->target_path = (cvk_motion){target, n, desc->camera_loop};
    return CVK_SUCCESS;
}

void cvk_render_camera_destroy(cvk_renderer* rd)
{
    free((void*)rd->eye_path.keyframes);
    free((void*)rd->target_path.keyframes);
    rd->eye_path = rd->target_path = (cvk_motion){0};
    free(rd->fit_xyz);
    rd->fit_xyz = NULL;
    rd->fit_count = 0;
}

/* The view with the camera where its keyframes put it at `seconds` (without keyframes, the
   description's camera). */
void cvk_render_camera_resolve(cvk_renderer* rd, double seconds)
{
    cvk_render_desc d = rd->desc;
    if (rd->eye_path.keyframe_count > 0) {
        cvk_pose eye = cvk_motion_pose(&rd->eye_path, seconds), target = cvk_motion_pose(&rd->target_path, seconds);
        memcpy(d.eye, eye.translation, sizeof d.eye);
        memcpy(d.target, target.translation, sizeof d.target);
        d.auto_eye = d.auto_target = false;
    }
    cvk_view_fit fit = {rd->fit_xyz, rd->fit_count};
    cvk_view_resolve(&d, &rd->mesh->sim->build, rd->gravity, &rd->colliders.framing, d.fit ? &fit : NULL,
                     d.shadow_map_size, &rd->view);
}

/* Room for n points and the corners of the colliders' boxes (each finite collider at rest and
   at each keyframe), which go after them. */
static cvk_result fit_points(cvk_renderer* rd, uint64_t n, cvk_error* error)
{
    const cvk_view_colliders* c = &rd->colliders.framing;
    uint64_t count = n + 8u * c->box_count;
    double* xyz = malloc((size_t)count * 3 * sizeof *xyz + 1);
    if (!xyz)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %" PRIu64 " points to frame", count);
    for (uint32_t i = 0; i < c->box_count; i++)
        for (int corner = 0; corner < 8; corner++)
            for (int k = 0; k < 3; k++)
                xyz[3 * (n + 8u * i + (uint64_t)corner) + (uint64_t)k] =
                    corner & (1 << k) ? c->boxes[i].hi[k] : c->boxes[i].lo[k];
    free(rd->fit_xyz);
    rd->fit_xyz = xyz;
    rd->fit_count = count;
    return CVK_SUCCESS;
}

cvk_result cvk_render_camera_fit_particles(cvk_renderer* rd, cvk_error* error)
{
    uint64_t n = cvk_sim_particle_count(rd->mesh->sim);
    float* positions = malloc((size_t)n * 3 * sizeof *positions + 1);
    if (!positions)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %" PRIu64 " positions to frame", n);
    cvk_result r = cvk_sim_read_positions(rd->mesh->sim, positions, n, error);
    if (r == CVK_SUCCESS)
        r = fit_points(rd, n, error);
    for (uint64_t i = 0; r == CVK_SUCCESS && i < 3 * n; i++)
        rd->fit_xyz[i] = positions[i];
    free(positions);
    return r;
}

cvk_result cvk_renderer_fit(cvk_renderer* rd, const float lo[3], const float hi[3], cvk_error* error)
{
    if (!rd)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_renderer_fit needs a renderer");
    if (!rd->desc.fit)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_renderer_fit: the renderer's description has "
                        "render.fit off");
    if ((lo == NULL) != (hi == NULL))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_renderer_fit needs both corners or neither");
    cvk_result r;
    if (lo) {
        for (int k = 0; k < 3; k++)
            if (!(isfinite(lo[k]) && isfinite(hi[k]) && lo[k] <= hi[k]))
                return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_renderer_fit: the box must be finite "
                                "with lo <= hi, got [%g, %g] along axis %d", lo[k], hi[k], k);
        r = fit_points(rd, 8, error);
        for (int corner = 0; r == CVK_SUCCESS && corner < 8; corner++)
            for (int k = 0; k < 3; k++)
                rd->fit_xyz[3 * corner + k] = corner & (1 << k) ? hi[k] : lo[k];
    } else {
        r = cvk_render_camera_fit_particles(rd, error);
    }
    if (r != CVK_SUCCESS)
        return r;
    cvk_render_camera_resolve(rd, rd->seconds);
    cvk_render_write_uniforms(rd);
    return CVK_SUCCESS;
}

/* Distance from p to the box (0 inside it). */
static double box_distance(const double p[3], const void* to)
{
    const cvk_box* box = to;
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double out = fmax(fmax(box->lo[k] - p[k], p[k] - box->hi[k]), 0.0);
        d2 += out * out;
    }
    return sqrt(d2);
}

/* Samples of each straight stretch of the camera's path between keyframes. */
#define EYE_PATH_SAMPLES 16
/* How much longer than at rest a drawn triangle edge is taken to be. */
#define EDGE_STRETCH 1.1

double cvk_render_eye_least(const cvk_renderer* rd, const double eye[3],
                            double (*distance)(const double eye[3], const void* to), const void* to)
{
    const cvk_motion* path = &rd->eye_path;
    if (path->keyframe_count == 0)
        return distance(eye, to);
    double least = INFINITY;
    for (uint32_t i = 0; i < path->keyframe_count; i++) {
        const float* from = path->keyframes[i].translation;
        const float* next = path->keyframes[i + 1 < path->keyframe_count ? i + 1 : i].translation;
        double step = 0.0;
        for (int k = 0; k < 3; k++)
            step += ((double)next[k] - from[k]) * ((double)next[k] - from[k]);
        step = sqrt(step) / EYE_PATH_SAMPLES;
        for (int j = 0; j <= EYE_PATH_SAMPLES; j++) {
            double f = (double)j / EYE_PATH_SAMPLES, at[3];
            for (int k = 0; k < 3; k++)
                at[k] = from[k] + f * ((double)next[k] - from[k]);
            least = fmin(least, distance(at, to) - 0.5 * step);
        }
    }
    return least;
}

bool cvk_render_vertex_lit(const cvk_renderer* rd)
{
    const cvk_render_desc* d = &rd->desc;
    const cvk_build* b = &rd->mesh->sim->build;
    if (!(d->vertex_lighting > 0.0f) || d->smooth > 1 || b->triangle_count == 0)
        return false;
    for (uint32_t c = 0; c < b->cloth_count; c++)
        if (b->cloths[c].normal_map)
            return false;
    double longest = 0.0;
    for (uint64_t t = 0; t < b->triangle_count; t++)
        for (int e = 0; e < 3; e++) {
            uint32_t s = b->triangle_springs[3 * t + e];
            if (s != UINT32_MAX) {
                longest = fmax(longest, b->springs[s].rest);
                continue;
            }
            const float* p = &b->position[3 * (size_t)b->internal_of[b->triangles[3 * t + e]]];
            const float* q = &b->position[3 * (size_t)b->internal_of[b->triangles[3 * t + (e + 1) % 3]]];
            longest = fmax(longest, sqrt(((double)p[0] - q[0]) * ((double)p[0] - q[0]) +
                                         ((double)p[1] - q[1]) * ((double)p[1] - q[1]) +
                                         ((double)p[2] - q[2]) * ((double)p[2] - q[2])));
        }
    /* the angle a pixel spans at the middle of the picture */
    double pixel = 2.0 * tan(0.5 * d->fov_y * 3.14159265358979323846 / 180.0) / d->size[1];
    double nearest = cvk_render_eye_least(rd, rd->view.eye, box_distance, &rd->view.reach);
    if (!(nearest > 0.0) || !(pixel > 0.0))
        return false;
    return EDGE_STRETCH * longest / (nearest * pixel) <= d->vertex_lighting;
}
