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
    cvk_view_resolve(&d, &rd->mesh->sim->build, rd->gravity, &rd->colliders.framing, d.fit ? &rd->fit_box : NULL,
                     d.shadow_map_size, &rd->view);
}

/* The colliders' boxes (each finite collider at rest and at each keyframe) added to `box`. */
static void add_collider_boxes(const cvk_renderer* rd, cvk_box* box)
{
    const cvk_view_colliders* c = &rd->colliders.framing;
    for (uint32_t i = 0; i < c->box_count; i++) {
        cvk_box_add(box, c->boxes[i].lo);
        cvk_box_add(box, c->boxes[i].hi);
    }
}

cvk_result cvk_render_camera_fit_particles(cvk_renderer* rd, cvk_error* error)
{
    uint64_t n = cvk_sim_particle_count(rd->mesh->sim);
    float* xyz = malloc((size_t)n * 3 * sizeof *xyz + 1);
    if (!xyz)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %" PRIu64 " positions to frame", n);
    cvk_result r = cvk_sim_read_positions(rd->mesh->sim, xyz, n, error);
    if (r == CVK_SUCCESS) {
        cvk_box_empty(&rd->fit_box);
        for (uint64_t i = 0; i < n; i++)
            cvk_box_add(&rd->fit_box, (double[3]){xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
        add_collider_boxes(rd, &rd->fit_box);
    }
    free(xyz);
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
    if (lo) {
        for (int k = 0; k < 3; k++)
            if (!(isfinite(lo[k]) && isfinite(hi[k]) && lo[k] <= hi[k]))
                return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_renderer_fit: the box must be finite "
                                "with lo <= hi, got [%g, %g] along axis %d", lo[k], hi[k], k);
        cvk_box_empty(&rd->fit_box);
        cvk_box_add(&rd->fit_box, (double[3]){lo[0], lo[1], lo[2]});
        cvk_box_add(&rd->fit_box, (double[3]){hi[0], hi[1], hi[2]});
        add_collider_boxes(rd, &rd->fit_box);
    } else {
        cvk_result r = cvk_render_camera_fit_particles(rd, error);
        if (r != CVK_SUCCESS)
            return r;
    }
    cvk_render_camera_resolve(rd, rd->seconds);
    cvk_render_write_uniforms(rd);
    return CVK_SUCCESS;
}
