/* The scene keys of attachments (kinematic particles moved by keyframes): JSON, validation of
   descriptions and what the build makes of them (pinned particles, the attached list, the
   errors only the cloth's shape can tell). Every message is compared exactly. */
#include "scene_checks.h"

#include "topology/build.h"

#define GRID "'cloths': [{'grid': [4, 3]}]"

static void test_default(void)
{
    cvk_scene_desc d = cvk_default_scene_desc();
    CHECK(d.attachments == NULL);
    CHECK_INT(d.attachment_count, 0);
    /* An attachment's defaults: what a zeroed one meant (a scene file's missing keys). */
    cvk_attachment_desc a = cvk_default_attachment_desc();
    CHECK_INT(a.cloth, 0);
    CHECK(a.pins == NULL);
    CHECK_INT(a.pin_count, 0);
    CHECK(a.pin_vertices == NULL);
    CHECK_INT(a.pin_vertex_count, 0);
    CHECK(!a.use_pin_box);
    for (int k = 0; k < 3; k++) {
        CHECK_FLOAT(a.pin_box.min[k], 0.0f);
        CHECK_FLOAT(a.pin_box.max[k], 0.0f);
    }
    CHECK(a.motion.keyframes == NULL);
    CHECK_INT(a.motion.keyframe_count, 0);
    CHECK(!a.motion.loop);
    CHECK(a.cookie_ != 0);
}

static void test_parse(void)
{
    cvk_scene* scene = PARSE_OK("{" GRID ", 'attachments': ["
                                " {'cloth': 0, 'pins': [[0, 0], [3, 0]], 'loop': true, 'keyframes':"
                                "  [{'time': 0}, {'time': 1, 'translation': [1, 0, 0], 'rotation': [0, 0, 1, 0]}]},"
                                " {'pin_box': [[-1, -1, 0.9], [1, 1, 1.1]]}]}");
    if (!scene)
        return;
    const cvk_scene_desc* d = cvk_scene_get_desc(scene);
    CHECK_INT(d->attachment_count, 2);
    const cvk_attachment_desc* a = d->attachments;
    CHECK_INT(a[0].cloth, 0);
    CHECK_INT(a[0].pin_count, 2);
    CHECK_INT(a[0].pins[1][0], 3);
    CHECK(!a[0].use_pin_box);
    CHECK(a[0].motion.loop);
    CHECK_INT(a[0].motion.keyframe_count, 2);
    CHECK_FLOAT(a[0].motion.keyframes[1].translation[0], 1.0f);
    CHECK_FLOAT(a[0].motion.keyframes[0].rotation[0], 1.0f); /* the default rotation */
    CHECK_FLOAT(a[0].motion.keyframes[1].rotation[2], 1.0f);
    CHECK_INT(a[1].cloth, 0); /* the default */
    CHECK_INT(a[1].pin_count, 0);
    CHECK(a[1].use_pin_box);
    CHECK_FLOAT(a[1].pin_box.max[2], 1.1f);
    CHECK_INT(a[1].motion.keyframe_count, 0);
    cvk_scene_destroy(scene);
}

static void test_bad_json(void)
{
    EXPECT_INVALID("{" GRID ", 'attachments': [{'cloth': 0, 'pinz': [[0, 0]]}]}",
                   "t.json: attachments.0.pinz: unknown key (expected one of: cloth, pins, pin_box, "
                   "keyframes, loop)");
    EXPECT_INVALID("{" GRID ", 'attachments': {'cloth': 0}}",
                   "t.json: attachments: expected an array of attachment objects, got an object");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'cloth': 1, 'pins': [[0, 0]]}]}",
                   "t.json: attachments.0.cloth: must be the index of one of the scene's 1 cloths "
                   "(0 to 0), got 1");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'cloth': -1, 'pins': [[0, 0]]}]}",
                   "t.json: attachments.0.cloth: must be at least 0, got -1");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'cloth': 0, 'pins': []}]}",
                   "t.json: attachments.0: attaches no particles; give \"pins\" (not empty) or "
                   "\"pin_box\"");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'cloth': 0}]}",
                   "t.json: attachments.0: attaches no particles; give \"pins\" (not empty) or "
                   "\"pin_box\"");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'pins': [[0, 0], [4, 0]]}]}",
                   "t.json: attachments.0.pins.1: [4, 0] is outside the 4 x 3 grid");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'pins': [5]}]}",
                   "t.json: attachments.0.pins: a grid cloth takes [i, j] pairs, not vertex indices");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'pin_box': [[0, 1, 0], [1, 0, 1]]}]}",
                   "t.json: attachments.0.pin_box: min 1 is above max 0 on axis y");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'pins': [[0, 0]], 'keyframes':"
                   " [{'time': 1}, {'time': 0.5}]}]}",
                   "t.json: attachments.0.keyframes.1.time: must be greater than the previous "
                   "keyframe's time (1), got 0.5");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'pins': [[0, 0]], 'keyframes':"
                   " [{'translation': [1, 0, 0]}]}]}",
                   "t.json: attachments.0.keyframes.0.time: missing; a keyframe needs its time");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'pins': [[0, 0]], 'keyframes':"
                   " [{'time': 0, 'rotation': [0, 0, 0, 0]}]}]}",
                   "t.json: attachments.0.keyframes.0.rotation: must not be zero, got [0, 0, 0, 0]");
    EXPECT_INVALID("{" GRID ", 'attachments': [{'pins': [[0, 0]], 'loop': true,"
                   " 'keyframes': [{'time': 0}]}]}",
                   "t.json: attachments.0.loop: a looping motion needs at least two keyframes, got 1");
    EXPECT_INVALID("{" GRID ", 'solver': {'method': 'explicit'}, 'attachments': [{'pins': [[0, 0]]}]}",
                   "t.json: solver.method: explicit does not move attached particles; remove "
                   "\"attachments\", or use pd or implicit");
    /* implicit moves attached particles (lib/features/attach.h): its scene is taken */
    cvk_scene* implicit = PARSE_OK("{" GRID ", 'solver': {'method': 'implicit', 'linear': 'cg'},"
                                   " 'attachments': [{'pins': [[0, 0]]}]}");
    if (implicit)
        cvk_scene_destroy(implicit);
    EXPECT_INVALID("{" GRID ", 'solver': {'linear': 'gs-cpu'}, 'attachments': [{'pins': [[0, 0]]}]}",
                   "t.json: solver.linear: gs-cpu (the host reference) does not move attached "
                   "particles; remove \"attachments\", or use rbgs, jacobi or chebyshev");
}

static void test_validate_desc(void)
{
    fixture f;
    fixture_init(&f);
    f.cloths[0].grid[0] = 4;
    f.cloths[0].grid[1] = 3;
    cvk_attachment_desc zero = {.cloth = 0, .pin_count = 1};
    f.scene.attachments = &zero;
    f.scene.attachment_count = 1;
    EXPECT_DESC_INVALID(&f.scene, "attachments.0: attachment description was not made by "
                                  "cvk_default_attachment_desc()");
    cvk_attachment_desc a = cvk_default_attachment_desc();
    a.pin_count = 1;
    f.scene.attachments = &a;
    EXPECT_DESC_INVALID(&f.scene, "attachments.0.pins: is NULL but pin_count is 1");
    f.scene.attachments = NULL;
    EXPECT_DESC_INVALID(&f.scene, "attachments: is NULL but attachment_count is 1");
}

/* Builds a parsed scene; returns its result and fills err. */
static cvk_result build(const char* single_quoted, cvk_build* b, cvk_error* err)
{
    cvk_scene* scene = PARSE_OK(single_quoted);
    if (!scene)
        return CVK_ERROR_INVALID_ARGUMENT;
    cvk_result r = cvk_build_create(cvk_scene_get_desc(scene), b, err);
    cvk_scene_destroy(scene);
    return r;
}

/* Attached particles are pinned and listed with their attachment, cloth by cloth. */
static void test_build(void)
{
    cvk_build b;
    cvk_error err = {0};
    cvk_result r = build("{'cloths': [{'grid': [4, 3], 'pins': [[1, 2]]}, {'grid': [2, 2]}],"
                         " 'attachments': [{'cloth': 1, 'pins': [[1, 1]]},"
                         "  {'cloth': 0, 'pins': [[0, 0], [3, 0]]}]}",
                         &b, &err);
    CHECK_INT(r, CVK_SUCCESS);
    if (r != CVK_SUCCESS) {
        printf("    %s\n", err.message);
        return;
    }
    CHECK_INT(b.particle_count - b.free_count, 4); /* one pin, three attached */
    CHECK_INT(b.attached_count, 3);
    const uint32_t users[3] = {0, 3, 12 + 3}, attachment[3] = {1, 1, 0};
    for (uint32_t i = 0; i < 3 && i < b.attached_count; i++) {
        CHECK_INT(b.user_of[b.attached[i]], users[i]);
        CHECK(b.attached[i] >= b.free_count);
        CHECK_INT(b.attached_to[i], attachment[i]);
    }
    cvk_build_destroy(&b);
}

static void expect_build_error(const char* single_quoted, const char* message)
{
    cvk_build b;
    cvk_error err = {0};
    cvk_result r = build(single_quoted, &b, &err);
    CHECK_INT(r, CVK_ERROR_INVALID_ARGUMENT);
    CHECK_STR(err.message, message);
    if (r == CVK_SUCCESS)
        cvk_build_destroy(&b);
}

static void test_build_errors(void)
{
    expect_build_error("{" GRID ", 'attachments': [{'pins': [[0, 0], [1, 0]]}, {'pins': [[1, 0]]}]}",
                       "attachments.1: particle 1 of cloth 0 is already in attachments.0");
    expect_build_error("{" GRID ", 'attachments': [{'pin_box': [[5, 5, 5], [6, 6, 6]]}]}",
                       "attachments.0.pin_box: holds none of the cloth's 12 vertices");
}

int main(void)
{
    test_default();
    test_parse();
    test_bad_json();
    test_validate_desc();
    test_build();
    test_build_errors();
    printf("%d checks, %d failed\n", T.checks, T.failures);
    return T.failures ? 1 : 0;
}
