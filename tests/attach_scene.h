/* The attachment tests' scene (tests/features/test_attach.c, tests/solvers/test_implicit_attach.c): a W × H
   cloth hanging in the x-y plane whose top corners are attached, one pair sliding (looping),
   the other turning, and how far its attached particles are from their keyframes. */
#ifndef CVK_TEST_ATTACH_SCENE_H
#define CVK_TEST_ATTACH_SCENE_H

#include "harness.h"
#include "scene/motion.h"

#define W 6
#define H 5

static const cvk_keyframe slide[3] = {
    {.time = 0.0f, .rotation = {1, 0, 0, 0}},
    {.time = 0.1f, .translation = {0.2f, 0.0f, 0.0f}, .rotation = {1, 0, 0, 0}},
    {.time = 0.2f, .rotation = {1, 0, 0, 0}}, /* back where it started: a closed loop */
};
/* 30 degrees about z (about the world origin), with a lift. */
static const cvk_keyframe turn[2] = {
    {.time = 0.05f, .rotation = {1, 0, 0, 0}},
    {.time = 0.3f, .translation = {0.0f, 0.05f, 0.0f}, .rotation = {0.9659258f, 0, 0, 0.2588190f}},
};
static const uint32_t slide_pins[2][2] = {{0, 0}, {1, 0}};
static const uint32_t turn_pins[1][2] = {{W - 1, 0}};

typedef struct setup {
    cvk_scene_desc scene;
    cvk_cloth_desc cloth;
    cvk_attachment_desc attachments[2];
    cvk_collider_desc collider;
} setup;

/* The scene; `collider` adds a plane far below, whose pass counts the substeps. */
static void attach_make_scene(setup* s, bool collider)
{
    s->cloth = cvk_default_cloth_desc();
    s->cloth.grid[0] = W;
    s->cloth.grid[1] = H;
    s->cloth.size[0] = 0.5f;
    s->cloth.size[1] = 0.4f;
    memcpy(s->cloth.origin, (float[3]){-0.25f, 1.0f, 0.0f}, sizeof s->cloth.origin);
    memcpy(s->cloth.v_axis, (float[3]){0.0f, -1.0f, 0.3f}, sizeof s->cloth.v_axis);
    s->cloth.stiffness.structural = 1e4f;
    s->cloth.stiffness.shear = 1e3f;
    s->attachments[0] = cvk_default_attachment_desc();
    s->attachments[0].pins = slide_pins;
    s->attachments[0].pin_count = 2;
    s->attachments[0].motion = (cvk_motion){.keyframes = slide, .keyframe_count = 3, .loop = true};
    s->attachments[1] = cvk_default_attachment_desc();
    s->attachments[1].pins = turn_pins;
    s->attachments[1].pin_count = 1;
    s->attachments[1].motion = (cvk_motion){.keyframes = turn, .keyframe_count = 2};
    s->scene = cvk_default_scene_desc();
    s->scene.substeps = 4;
    s->scene.cloths = &s->cloth;
    s->scene.cloth_count = 1;
    s->scene.attachments = s->attachments;
    s->scene.attachment_count = 2;
    if (collider) { /* far below: its pass counts the substeps, nothing touches it */
        s->collider = cvk_default_collider_desc();
        s->collider.point[1] = -5.0f;
        s->scene.colliders = &s->collider;
        s->scene.collider_count = 1;
    }
}

/* The largest distance of a grid attachment's particles from where its motion puts them at
   time t, given the positions at creation (user order). */
static double attachment_error(const cvk_scene_desc* scene, const float* start, const float* x,
                               double t)
{
    double worst = 0.0;
    for (uint32_t a = 0; a < scene->attachment_count; a++) {
        const cvk_attachment_desc* d = &scene->attachments[a];
        cvk_pose pose = cvk_motion_pose(&d->motion, t);
        for (uint32_t p = 0; p < d->pin_count; p++) {
            size_t i = (size_t)d->pins[p][1] * scene->cloths[d->cloth].grid[0] + d->pins[p][0];
            float want[3];
            cvk_pose_apply(&pose, &start[3 * i], want);
            for (int k = 0; k < 3; k++)
                worst = fmax(worst, fabs((double)x[3 * i + k] - want[k]));
        }
    }
    return worst;
}

#endif
