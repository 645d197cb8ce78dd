/* The renderer's camera over time: render.camera_keyframes kept as two translation-only
   motions (the eye's and the target's), so a camera follows the keyframe rules of lib/scene/motion.c
   (straight lines between keyframes, held outside them, an optional loop), and the view
   resolved for a time. */
#include <inttypes.h>
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
    cvk_view_resolve(&d, &rd->mesh->sim->build, rd->gravity, &rd->colliders.framing, d.shadow_map_size, &rd->view);
}
