/* The scene keys of collisions: the collision block, colliders of every type with their
   keyframes, and a cloth's initial velocity: defaults, validation of programmatic
   descriptions, JSON, overrides and a mesh collider's file relative to the scene file. Every
   message is compared exactly. */
#include "scene_checks.h"

#include <math.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- defaults and names ---- */

static void check_default_collider(const cvk_collider_desc* c)
{
    CHECK_INT(c->type, CVK_COLLIDER_PLANE);
    CHECK_STR(c->name, NULL);
    for (int k = 0; k < 3; k++) {
        CHECK_FLOAT(c->point[k], 0.0f);
        CHECK_FLOAT(c->normal[k], k == 1 ? 1.0f : 0.0f);
        CHECK_FLOAT(c->center[k], 0.0f);
        CHECK_FLOAT(c->half_extents[k], 0.25f);
        CHECK_FLOAT(c->a[k], 0.0f);
        CHECK_FLOAT(c->b[k], 0.0f);
        CHECK_FLOAT(c->apex[k], 0.0f);
        CHECK_FLOAT(c->transform.scale[k], 1.0f);
        CHECK_FLOAT(c->transform.translation[k], 0.0f);
    }
    CHECK_FLOAT(c->radius, 0.25f);
    for (int k = 0; k < 4; k++) {
        CHECK_FLOAT(c->rotation[k], k == 0 ? 1.0f : 0.0f);
        CHECK_FLOAT(c->transform.rotation[k], k == 0 ? 1.0f : 0.0f);
    }
    CHECK_FLOAT(c->funnel_a, 0.5f);
    CHECK_FLOAT(c->height, 1.0f);
    CHECK_STR(c->file, NULL);
    CHECK_FLOAT(c->friction, -1.0f);
    CHECK_FLOAT(c->static_friction, -1.0f);
    CHECK(c->motion.keyframes == NULL);
    CHECK_INT(c->motion.keyframe_count, 0);
    CHECK(!c->motion.loop);
    CHECK_FLOAT(c->color[0], 0.55f);
    CHECK_FLOAT(c->color[1], 0.55f);
    CHECK_FLOAT(c->color[2], 0.6f);
    CHECK_FLOAT(c->roughness, 0.5f);
    CHECK_STR(c->texture, NULL);
    CHECK_FLOAT(c->texture_scale, 1.0f);
}

static void check_default_collision(const cvk_scene_desc* d)
{
    CHECK(!d->collision.self);
    CHECK_FLOAT(d->collision.thickness, 0.0f);
    CHECK_FLOAT(d->collision.radius, 0.0f);
    CHECK_FLOAT(d->collision.friction, 0.3f);
    CHECK_FLOAT(d->collision.static_friction, 0.4f);
    CHECK(!d->collision.allow_intersecting_start);
    CHECK_INT(d->collision.detection_interval, 1);
    CHECK_INT(d->collision.detect_every, 0);
    CHECK_FLOAT(d->collision.exclusion, 0.0f);
    CHECK(!d->collision.edges);
    CHECK(d->colliders == NULL);
    CHECK_INT(d->collider_count, 0);
}

/* Scene, cloth and collider defaults; with only its type changed, every collider but a mesh
   (which needs a file) is valid. */
static void test_defaults(void)
{
    cvk_scene_desc scene = cvk_default_scene_desc();
    check_default_collision(&scene);
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    for (int k = 0; k < 3; k++)
        CHECK_FLOAT(cloth.velocity[k], 0.0f);
    cvk_collider_desc collider = cvk_default_collider_desc();
    check_default_collider(&collider);

    fixture f;
    fixture_init(&f);
    f.scene.colliders = &collider;
    f.scene.collider_count = 1;
    for (int type = 0; type < CVK_COLLIDER_TYPE_COUNT; type++) {
        collider.type = (cvk_collider_type)type;
        if (type != CVK_COLLIDER_MESH)
            EXPECT_DESC_VALID(&f.scene);
    }
    EXPECT_DESC_INVALID(&f.scene, "colliders.0.file: a mesh collider needs a mesh file, got NULL");
    collider.file = "chair.obj";
    EXPECT_DESC_VALID(&f.scene);
}

static void test_names(void)
{
    CHECK_STR(cvk_collider_type_name(CVK_COLLIDER_PLANE), "plane");
    CHECK_STR(cvk_collider_type_name(CVK_COLLIDER_SPHERE), "sphere");
    CHECK_STR(cvk_collider_type_name(CVK_COLLIDER_BOX), "box");
    CHECK_STR(cvk_collider_type_name(CVK_COLLIDER_CAPSULE), "capsule");
    CHECK_STR(cvk_collider_type_name(CVK_COLLIDER_FUNNEL), "funnel");
    CHECK_STR(cvk_collider_type_name(CVK_COLLIDER_MESH), "mesh");
    CHECK_STR(cvk_collider_type_name(CVK_COLLIDER_TYPE_COUNT), NULL);
    CHECK_STR(cvk_collider_type_name((cvk_collider_type)-1), NULL);
}

/* ---- validation of programmatic descriptions ---- */

/* A scene of one default cloth and up to four colliders, all from the defaults. */
typedef struct collide_fixture {
    fixture base;
    cvk_collider_desc colliders[4];
} collide_fixture;

static cvk_collider_desc* collide_init(collide_fixture* f, cvk_collider_type type)
{
    fixture_init(&f->base);
    for (int i = 0; i < 4; i++)
        f->colliders[i] = cvk_default_collider_desc();
    f->colliders[0].type = type;
    f->base.scene.colliders = f->colliders;
    f->base.scene.collider_count = 1;
    return &f->colliders[0];
}

static void test_validate_collision(void)
{
    fixture f;
    fixture_init(&f);
    f.scene.collision.thickness = -0.01f;
    EXPECT_DESC_INVALID(&f.scene, "collision.thickness: must be at least 0, got -0.01");
    f.scene.collision.thickness = NAN;
    EXPECT_DESC_INVALID(&f.scene, "collision.thickness: must be a finite number, got nan");
    f.scene.collision.thickness = INFINITY;
    EXPECT_DESC_INVALID(&f.scene, "collision.thickness: must be a finite number, got inf");
    f.scene.collision.thickness = 1.5f;
    EXPECT_DESC_INVALID(&f.scene, "collision.thickness: must be at most 1 m, got 1.5");
    f.scene.collision.thickness = 1.0f; /* a metre is the most */
    EXPECT_DESC_VALID(&f.scene);
    f.scene.collision.thickness = 0.005f;
    EXPECT_DESC_VALID(&f.scene);
    f.scene.collision.friction = -0.1f;
    EXPECT_DESC_INVALID(&f.scene, "collision.friction: must be at least 0, got -0.1");
    f.scene.collision.friction = 0.5f;
    EXPECT_DESC_INVALID(&f.scene, "collision.static_friction: must be at least friction (0.5), got 0.4");
    f.scene.collision.static_friction = INFINITY;
    EXPECT_DESC_INVALID(&f.scene, "collision.static_friction: must be a finite number, got inf");
    f.scene.collision.static_friction = 0.5f; /* equal is fine: no static phase */
    EXPECT_DESC_VALID(&f.scene);
    f.scene.collision.friction = f.scene.collision.static_friction = 0.0f;
    EXPECT_DESC_VALID(&f.scene);
}

/* The contact radius: finite, at most a metre, more than a given thickness (a default
   thickness is known only from the build: tests/sim/test_clean_start.c). */
static void test_validate_radius(void)
{
    fixture f;
    fixture_init(&f);
    f.scene.collision.radius = -0.01f;
    EXPECT_DESC_INVALID(&f.scene, "collision.radius: must be at least 0, got -0.01");
    f.scene.collision.radius = NAN;
    EXPECT_DESC_INVALID(&f.scene, "collision.radius: must be a finite number, got nan");
    f.scene.collision.radius = -INFINITY;
    EXPECT_DESC_INVALID(&f.scene, "collision.radius: must be a finite number, got -inf");
    f.scene.collision.radius = 2.0f;
    EXPECT_DESC_INVALID(&f.scene, "collision.radius: must be at most 1 m, got 2");
    f.scene.collision.radius = 0.001f; /* the thickness is the default: checked at creation */
    EXPECT_DESC_VALID(&f.scene);
    f.scene.collision.thickness = 0.005f;
    EXPECT_DESC_INVALID(&f.scene, "collision.radius: 0.001 is not more than the thickness 0.005 "
                                  "(contact acts between the thickness and the radius)");
    f.scene.collision.radius = 0.005f;
    EXPECT_DESC_INVALID(&f.scene, "collision.radius: 0.005 is not more than the thickness 0.005 "
                                  "(contact acts between the thickness and the radius)");
    f.scene.collision.radius = 0.006f;
    EXPECT_DESC_VALID(&f.scene);
    f.scene.collision.radius = 0.0f; /* 1.3 thicknesses */
    EXPECT_DESC_VALID(&f.scene);
}

/* The detection interval: 0 and 1 detect at the substep that needs it; at most 64. */
static void test_validate_detection_interval(void)
{
    fixture f;
    fixture_init(&f);
    f.scene.collision.detection_interval = 65;
    EXPECT_DESC_INVALID(&f.scene, "collision.detection_interval: must be at most 64 substeps, got 65");
    f.scene.collision.detection_interval = UINT32_MAX;
    EXPECT_DESC_INVALID(&f.scene, "collision.detection_interval: must be at most 64 substeps, got 4294967295");
    f.scene.collision.detection_interval = 64;
    EXPECT_DESC_VALID(&f.scene);
    f.scene.collision.detection_interval = 0;
    EXPECT_DESC_VALID(&f.scene);
    cvk_scene* scene = PARSE_OK("{'cloths': [{}], 'collision': {'self': true, 'detection_interval': 4}}");
    if (scene)
        CHECK_INT(cvk_scene_get_desc(scene)->collision.detection_interval, 4);
    cvk_scene_destroy(scene);
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'detection_interval': 100}}",
                   "t.json: collision.detection_interval: must be at most 64 substeps, got 100");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'detection_interval': 2.5}}",
                   "t.json: collision.detection_interval: expected a whole number, got 2.5");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'detection_interval': -2}}",
                   "t.json: collision.detection_interval: must be at least 0, got -2");
}

/* The keys of the earlier contact load and are checked no more: they have no effect (the
   simulation's notes name them, tests/sim/test_clean_start.c). */
static void test_keys_without_effect(void)
{
    fixture f;
    fixture_init(&f);
    f.scene.collision.edges = true; /* without self: once an error */
    f.scene.collision.exclusion = 0.1f;
    f.scene.collision.detect_every = 1000; /* more than substeps: once an error */
    EXPECT_DESC_VALID(&f.scene);
    cvk_scene* scene = PARSE_OK("{'cloths': [{}], 'collision': {'edges': true, 'exclusion': 0.1, "
                                "'detect_every': 9, 'allow_intersecting_start': true, "
                                "'radius': 0.02}}");
    if (scene) {
        const cvk_collision_desc* c = &cvk_scene_get_desc(scene)->collision;
        CHECK(c->edges);
        CHECK_FLOAT(c->exclusion, 0.1f);
        CHECK_INT(c->detect_every, 9);
        CHECK(c->allow_intersecting_start);
        CHECK_FLOAT(c->radius, 0.02f);
    }
    cvk_scene_destroy(scene);
}

static void test_validate_collider_list(void)
{
    collide_fixture f;
    collide_init(&f, CVK_COLLIDER_PLANE);
    f.base.scene.colliders = NULL;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders: is NULL but collider_count is 1");
    f.base.scene.collider_count = 0; /* nothing to collide with */
    EXPECT_DESC_VALID(&f.base.scene);

    /* More than the 64 the uniform arrays hold is fine (they are read from storage buffers);
       past CVK_MAX_COLLIDERS the count is refused before any is read. */
    static cvk_collider_desc many[65];
    for (int i = 0; i < 65; i++)
        many[i] = cvk_default_collider_desc();
    f.base.scene.colliders = many;
    f.base.scene.collider_count = 65;
    EXPECT_DESC_VALID(&f.base.scene);
    f.base.scene.collider_count = (1u << 20) + 1;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders: at most 1048576 colliders, got 1048577");

    collide_init(&f, CVK_COLLIDER_PLANE);
    f.base.scene.collider_count = 2;
    f.colliders[1] = (cvk_collider_desc){0};
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.1: collider description was not made by cvk_default_collider_desc()");
    f.colliders[1] = cvk_default_collider_desc();
    f.colliders[1].type = (cvk_collider_type)9;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.1.type: unknown collider type 9");
    f.colliders[1].type = CVK_COLLIDER_TYPE_COUNT;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.1.type: unknown collider type 6");
    f.colliders[1] = cvk_default_collider_desc();
    f.colliders[1].name = "edge\x1b[2J";
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.1.name: contains the control character \\x1b at byte 4");
}

static void test_validate_shapes(void)
{
    collide_fixture f;
    cvk_collider_desc* c = collide_init(&f, CVK_COLLIDER_PLANE);
    memset(c->normal, 0, sizeof c->normal);
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.normal: must not be zero, got [0, 0, 0]");
    c = collide_init(&f, CVK_COLLIDER_PLANE);
    c->point[2] = INFINITY;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.point.2: must be a finite number, got inf");

    c = collide_init(&f, CVK_COLLIDER_SPHERE);
    c->radius = -0.5f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.radius: must be greater than 0, got -0.5");
    c->radius = 0.0f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.radius: must be greater than 0, got 0");
    c->radius = 1.0f;
    c->center[1] = NAN;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.center.1: must be a finite number, got nan");
    /* Fields of another type are not looked at. */
    c = collide_init(&f, CVK_COLLIDER_SPHERE);
    memset(c->normal, 0, sizeof c->normal);
    c->half_extents[0] = -1.0f;
    EXPECT_DESC_VALID(&f.base.scene);

    c = collide_init(&f, CVK_COLLIDER_BOX);
    c->half_extents[1] = 0.0f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.half_extents.1: must be greater than 0, got 0");
    c->half_extents[1] = 0.1f;
    memset(c->rotation, 0, sizeof c->rotation);
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.rotation: must not be zero, got [0, 0, 0, 0]");
    c->rotation[3] = 2.0f; /* normalised by the library */
    EXPECT_DESC_VALID(&f.base.scene);

    c = collide_init(&f, CVK_COLLIDER_CAPSULE);
    c->radius = -1.0f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.radius: must be greater than 0, got -1");
    c->radius = 0.1f;
    c->b[0] = -INFINITY;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.b.0: must be a finite number, got -inf");

    c = collide_init(&f, CVK_COLLIDER_FUNNEL);
    c->funnel_a = 0.0f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.a: must be greater than 0, got 0");
    c->funnel_a = 0.3f;
    c->height = -2.0f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.height: must be greater than 0, got -2");

    c = collide_init(&f, CVK_COLLIDER_MESH);
    c->file = "";
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.file: must name a mesh file, got an empty string");
    c->file = "chair.obj";
    c->transform.scale[2] = 0.0f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.transform.scale.2: must not be zero, got 0");
    c->transform.scale[2] = 1.0f;
    memset(c->transform.rotation, 0, sizeof c->transform.rotation);
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.transform.rotation: must not be zero, got [0, 0, 0, 0]");
}

/* Below 0 a coefficient is the scene's; the pair in use needs static ≥ kinetic. */
static void test_validate_friction(void)
{
    collide_fixture f;
    cvk_collider_desc* c = collide_init(&f, CVK_COLLIDER_PLANE);
    c->friction = 0.4f; /* with the scene's static 0.4 */
    EXPECT_DESC_VALID(&f.base.scene);
    c->friction = 0.5f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.static_friction: is not given, and collision.static_friction "
                                       "(0.4) is below this collider's friction (0.5): give a static_friction of at "
                                       "least 0.5");
    c->static_friction = 0.45f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.static_friction: must be at least friction (0.5), got 0.45");
    c->static_friction = 0.6f;
    EXPECT_DESC_VALID(&f.base.scene);
    c->friction = -1.0f; /* the scene's 0.3 */
    c->static_friction = 0.2f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.static_friction: must be at least collision.friction (0.3), "
                                       "got 0.2");
    c->static_friction = 0.0f;
    c->friction = 0.0f; /* frictionless */
    EXPECT_DESC_VALID(&f.base.scene);
    c->friction = -INFINITY; /* not "below 0": not a number to use at all */
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.friction: must be a finite number, got -inf");
    c->friction = 0.0f;
    c->static_friction = NAN;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.static_friction: must be a finite number, got nan");

    c = collide_init(&f, CVK_COLLIDER_PLANE);
    c->color[2] = 1.01f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.color.2: must be between 0 and 1, got 1.01");
}

static void test_validate_keyframes(void)
{
    cvk_keyframe keys[3] = {
        {.time = 0.0f, .rotation = {1, 0, 0, 0}},
        {.time = 0.5f, .translation = {0, 1, 0}, .rotation = {0, 0, 1, 0}},
        {.time = 1.0f, .rotation = {1, 0, 0, 0}},
    };
    collide_fixture f;
    cvk_collider_desc* c = collide_init(&f, CVK_COLLIDER_SPHERE);
    c->motion = (cvk_motion){.keyframes = keys, .keyframe_count = 3, .loop = true};
    EXPECT_DESC_VALID(&f.base.scene);
    keys[2].time = 0.5f;
    EXPECT_DESC_INVALID(&f.base.scene,
                        "colliders.0.keyframes.2.time: must be greater than the previous keyframe's time (0.5), got 0.5");
    keys[2].time = 0.25f;
    EXPECT_DESC_INVALID(&f.base.scene,
                        "colliders.0.keyframes.2.time: must be greater than the previous keyframe's time (0.5), got 0.25");
    keys[2].time = 1.0f;
    keys[0].time = -0.1f;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.keyframes.0.time: must be at least 0, got -0.1");
    keys[0].time = NAN;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.keyframes.0.time: must be a finite number, got nan");
    keys[0].time = 0.0f;
    memset(keys[1].rotation, 0, sizeof keys[1].rotation);
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.keyframes.1.rotation: must not be zero, got [0, 0, 0, 0]");
    keys[1].rotation[0] = 1.0f;
    keys[1].translation[0] = INFINITY;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.keyframes.1.translation.0: must be a finite number, got inf");
    keys[1].translation[0] = 0.0f;

    c->motion.keyframe_count = 1;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.loop: a looping motion needs at least two keyframes, got 1");
    c->motion.keyframe_count = 0;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.loop: a looping motion needs at least two keyframes, got 0");
    c->motion.loop = false;
    EXPECT_DESC_VALID(&f.base.scene);
    c->motion.keyframe_count = 1; /* held at its one pose */
    EXPECT_DESC_VALID(&f.base.scene);
    c->motion.keyframes = NULL;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.keyframes: is NULL but keyframe_count is 1");

    /* 10000 keyframes per collider is the most. */
    static cvk_keyframe many[10001];
    for (int i = 0; i < 10001; i++)
        many[i] = (cvk_keyframe){.time = (float)i, .rotation = {1, 0, 0, 0}};
    c->motion = (cvk_motion){.keyframes = many, .keyframe_count = 10000};
    EXPECT_DESC_VALID(&f.base.scene);
    c->motion.keyframe_count = 10001;
    EXPECT_DESC_INVALID(&f.base.scene, "colliders.0.keyframes: at most 10000 keyframes, got 10001");
}

static void test_validate_velocity(void)
{
    fixture f;
    fixture_init(&f);
    f.cloths[0].velocity[2] = -8.0f;
    EXPECT_DESC_VALID(&f.scene);
    f.cloths[0].velocity[0] = NAN;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.velocity.0: must be a finite number, got nan");
    /* 1e4 m/s is the most, in magnitude, not per axis. */
    f.cloths[0].velocity[0] = 6000.0f;
    f.cloths[0].velocity[2] = 8000.0f;
    EXPECT_DESC_VALID(&f.scene);
    f.cloths[0].velocity[1] = 200.0f;
    EXPECT_DESC_INVALID(&f.scene,
                        "cloths.0.velocity: must be at most 10000 m/s in magnitude, got 10002 m/s ([6000, 200, 8000])");
    f.cloths[0].velocity[1] = 1e4f;
    EXPECT_DESC_INVALID(&f.scene,
                        "cloths.0.velocity: must be at most 10000 m/s in magnitude, got 14142.136 m/s ([6000, 10000, 8000])");
}

/* ---- JSON ---- */

static const char* const every_type =
    "{'cloths': [{'velocity': [1, -2, 3.5]}, {}],"
    " 'collision': {'self': true, 'thickness': 0.004, 'friction': 0.2, 'static_friction': 0.25},"
    " 'colliders': ["
    "  {'type': 'plane', 'name': 'floor', 'point': [0, -1, 0], 'normal': [0, 2, 0], 'friction': 0.6,"
    "   'static_friction': 0.8, 'color': [0.1, 0.2, 0.3]},"
    "  {'type': 'sphere', 'center': [1, 2, 3], 'radius': 0.3,"
    "   'keyframes': [{'time': 0, 'translation': [0, 0, -2]}, {'time': 0.4, 'translation': [0, 0, 2],"
    "     'rotation': [0, 1, 0, 0]}], 'loop': true},"
    "  {'type': 'box', 'center': [0, 0.5, 0], 'half_extents': [0.5, 0.25, 1], 'rotation': [0.9, 0, 0.1, 0],"
    "   'material': {'color': [0.4, 0.3, 0.2], 'roughness': 0.8, 'texture': 'wood.png', 'texture_scale': 0.3}},"
    "  {'type': 'capsule', 'a': [0, 0, 0], 'b': [1, 0, 0], 'radius': 0.05, 'friction': 0},"
    "  {'type': 'funnel', 'apex': [0, 2, 0], 'a': 0.35, 'height': 1.5},"
    "  {'type': 'mesh', 'file': 'meshes/chair.obj', 'transform': {'scale': 2, 'rotation': [0, 0, 1, 0],"
    "   'translation': [0, 0.1, 0]}, 'keyframes': [{'time': 1, 'rotation': [0, 0, 1, 0]}]}]}";

static void check_every_type(const cvk_scene_desc* d)
{
    CHECK_FLOAT(d->cloths[0].velocity[0], 1.0f);
    CHECK_FLOAT(d->cloths[0].velocity[1], -2.0f);
    CHECK_FLOAT(d->cloths[0].velocity[2], 3.5f);
    CHECK_FLOAT(d->cloths[1].velocity[1], 0.0f);
    CHECK(d->collision.self);
    CHECK_FLOAT(d->collision.thickness, 0.004f);
    CHECK_FLOAT(d->collision.friction, 0.2f);
    CHECK_FLOAT(d->collision.static_friction, 0.25f);
    CHECK_INT(d->collider_count, 6);
    const cvk_collider_desc* c = d->colliders;
    CHECK_INT(c[0].type, CVK_COLLIDER_PLANE);
    CHECK_STR(c[0].name, "floor");
    CHECK_FLOAT(c[0].point[1], -1.0f);
    CHECK_FLOAT(c[0].normal[1], 2.0f); /* normalised where it is used, not here */
    CHECK_FLOAT(c[0].friction, 0.6f);
    CHECK_FLOAT(c[0].static_friction, 0.8f);
    CHECK_FLOAT(c[0].color[2], 0.3f);
    CHECK_INT(c[1].type, CVK_COLLIDER_SPHERE);
    CHECK_STR(c[1].name, NULL);
    CHECK_FLOAT(c[1].center[2], 3.0f);
    CHECK_FLOAT(c[1].radius, 0.3f);
    CHECK_FLOAT(c[1].friction, -1.0f); /* the scene's */
    CHECK_FLOAT(c[1].color[0], 0.55f);
    CHECK_INT(c[1].motion.keyframe_count, 2);
    CHECK(c[1].motion.loop);
    CHECK_FLOAT(c[1].motion.keyframes[0].translation[2], -2.0f);
    CHECK_FLOAT(c[1].motion.keyframes[0].rotation[0], 1.0f); /* the default rotation */
    CHECK_FLOAT(c[1].motion.keyframes[1].time, 0.4f);
    CHECK_FLOAT(c[1].motion.keyframes[1].rotation[1], 1.0f);
    CHECK_INT(c[2].type, CVK_COLLIDER_BOX);
    CHECK_FLOAT(c[2].center[1], 0.5f);
    CHECK_FLOAT(c[2].half_extents[2], 1.0f);
    CHECK_FLOAT(c[2].rotation[0], 0.9f);
    CHECK_FLOAT(c[2].rotation[2], 0.1f);
    CHECK_FLOAT(c[2].color[0], 0.4f); /* material.color is the collider's color */
    CHECK_FLOAT(c[2].color[2], 0.2f);
    CHECK_FLOAT(c[2].roughness, 0.8f);
    CHECK_FLOAT(c[1].roughness, 0.5f); /* the default */
    CHECK_STR(c[2].texture, "wood.png"); /* cvk_scene_parse keeps it as written */
    CHECK_FLOAT(c[2].texture_scale, 0.3f);
    CHECK_STR(c[1].texture, NULL);
    CHECK_FLOAT(c[1].texture_scale, 1.0f); /* the default */
    CHECK_INT(c[2].motion.keyframe_count, 0);
    CHECK(!c[2].motion.loop);
    CHECK_INT(c[3].type, CVK_COLLIDER_CAPSULE);
    CHECK_FLOAT(c[3].b[0], 1.0f);
    CHECK_FLOAT(c[3].radius, 0.05f);
    CHECK_FLOAT(c[3].friction, 0.0f);
    CHECK_FLOAT(c[3].static_friction, -1.0f);
    CHECK_INT(c[4].type, CVK_COLLIDER_FUNNEL);
    CHECK_FLOAT(c[4].apex[1], 2.0f);
    CHECK_FLOAT(c[4].funnel_a, 0.35f);
    CHECK_FLOAT(c[4].a[0], 0.0f); /* a funnel's "a" is funnel_a, not the capsule's end */
    CHECK_FLOAT(c[4].height, 1.5f);
    CHECK_INT(c[5].type, CVK_COLLIDER_MESH);
    CHECK_STR(c[5].file, "meshes/chair.obj"); /* cvk_scene_parse keeps it as written */
    CHECK_FLOAT(c[5].transform.scale[2], 2.0f);
    CHECK_FLOAT(c[5].transform.rotation[2], 1.0f);
    CHECK_FLOAT(c[5].transform.translation[1], 0.1f);
    CHECK_INT(c[5].motion.keyframe_count, 1);
    CHECK_FLOAT(c[5].motion.keyframes[0].time, 1.0f);
}

static void test_json(void)
{
    cvk_scene* scene = PARSE_OK(every_type);
    if (scene)
        check_every_type(cvk_scene_get_desc(scene));
    cvk_scene_destroy(scene);

    /* Without the keys: the defaults. */
    scene = PARSE_OK("{'cloths': [{}], 'collision': {}, 'colliders': []}");
    if (scene)
        check_default_collision(cvk_scene_get_desc(scene));
    cvk_scene_destroy(scene);
    scene = PARSE_OK("{'cloths': [{}], 'colliders': [{'type': 'plane'}]}");
    if (scene)
        check_default_collider(&cvk_scene_get_desc(scene)->colliders[0]);
    cvk_scene_destroy(scene);
}

static void test_json_types(void)
{
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'cone'}]}",
                   "t.json: colliders.0.type: unknown collider type \"cone\" (expected plane, sphere, box, capsule, "
                   "funnel or mesh)");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'plane'}, {'radius': 1}]}",
                   "t.json: colliders.1.type: missing; a collider needs its type: plane, sphere, box, capsule, funnel "
                   "or mesh");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 2}]}",
                   "t.json: colliders.0.type: expected a string, got the number 2");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': {'type': 'plane'}}",
                   "t.json: colliders: expected an array of collider objects, got an object");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': ['plane']}",
                   "t.json: colliders.0: expected a collider object, got the string \"plane\"");
    /* A key of another type is an unknown key, and the message says the collider's type. */
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'box', 'radius': 0.5}]}",
                   "t.json: colliders.0.radius: unknown key for a box collider (expected one of: type, name, friction, "
                   "static_friction, color, keyframes, loop, material, center, half_extents, rotation)");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'normal': [0, 1, 0], 'type': 'sphere'}]}",
                   "t.json: colliders.0.normal: unknown key for a sphere collider (expected one of: type, name, "
                   "friction, static_friction, color, keyframes, loop, material, center, radius)");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'funnel', 'b': [0, 1, 0]}]}",
                   "t.json: colliders.0.b: unknown key for a funnel collider (expected one of: type, name, friction, "
                   "static_friction, color, keyframes, loop, material, apex, a, height)");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'capsule', 'a': 0.5}]}",
                   "t.json: colliders.0.a: expected an array of 3 numbers, got the number 0.5");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'funnel', 'a': [0, 1, 0]}]}",
                   "t.json: colliders.0.a: expected a number, got an array of 3");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'plane', 'mesh': 'a.obj'}]}",
                   "t.json: colliders.0.mesh: unknown key for a plane collider (expected one of: type, name, friction, "
                   "static_friction, color, keyframes, loop, material, point, normal)");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'mesh', 'center': [0, 0, 0], 'file': 'a.obj'}]}",
                   "t.json: colliders.0.center: unknown key for a mesh collider (expected one of: type, name, "
                   "friction, static_friction, color, keyframes, loop, material, file, transform)");
    /* The collider's material block: its keys, and the range of its roughness. */
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'material': {'shine': 1}}]}",
                   "t.json: colliders.0.material.shine: unknown key (expected one of: color, roughness, texture, "
                   "texture_scale)");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'material': {'texture_scale': -1}}]}",
                   "t.json: colliders.0.material.texture_scale: must be greater than 0, got -1");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'material': {'texture_scale': [1, 1]}}]}",
                   "t.json: colliders.0.material.texture_scale: expected a number, got an array of 2");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'material': {'texture': ''}}]}",
                   "t.json: colliders.0.material.texture: must name an image file, got an empty string");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'material': {'roughness': 0.05}}]}",
                   "t.json: colliders.0.material.roughness: must be between 0.1 and 1, got 0.05");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'material': {'color': [0.2, 1.5, 0.2]}}]}",
                   "t.json: colliders.0.color.1: must be between 0 and 1, got 1.5");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'material': [0.2, 0.2, 0.2]}]}",
                   "t.json: colliders.0.material: expected an object, got an array of 3");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'thickness': 0.01, 'margin': 0.01}}",
                   "t.json: collision.margin: unknown key (expected one of: self, thickness, radius, friction, "
                   "static_friction, allow_intersecting_start, detection_interval, detect_every, exclusion, "
                   "edges)");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'self': true, 'edges': 'yes'}}",
                   "t.json: collision.edges: expected true or false, got the string \"yes\"");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'radius': '2 cm'}}",
                   "t.json: collision.radius: expected a number, got the string \"2 cm\"");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'allow_intersecting_start': 1}}",
                   "t.json: collision.allow_intersecting_start: expected true or false, got the number 1");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'thickness': 0.01, 'radius': 0.005}}",
                   "t.json: collision.radius: 0.005 is not more than the thickness 0.01 (contact acts "
                   "between the thickness and the radius)");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'thickness': 3}}",
                   "t.json: collision.thickness: must be at most 1 m, got 3");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'exclusion': '1 cm'}}",
                   "t.json: collision.exclusion: expected a number, got the string \"1 cm\"");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'self': 1}}",
                   "t.json: collision.self: expected true or false, got the number 1");
    EXPECT_INVALID("{'cloths': [{'velocity': [1, 2]}]}",
                   "t.json: cloths.0.velocity: expected an array of 3 numbers, got an array of 2");
}

static void test_json_values(void)
{
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'radius': -0.2}]}",
                   "t.json: colliders.0.radius: must be greater than 0, got -0.2");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'plane', 'normal': [0, 0, 0]}]}",
                   "t.json: colliders.0.normal: must not be zero, got [0, 0, 0]");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'box', 'half_extents': [1, 0, 1]}]}",
                   "t.json: colliders.0.half_extents.1: must be greater than 0, got 0");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'box', 'rotation': [0, 0, 0, 0]}]}",
                   "t.json: colliders.0.rotation: must not be zero, got [0, 0, 0, 0]");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'funnel', 'a': 0}]}",
                   "t.json: colliders.0.a: must be greater than 0, got 0");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'mesh'}]}",
                   "t.json: colliders.0.file: a mesh collider needs a mesh file, got NULL");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'mesh', 'file': ''}]}",
                   "t.json: colliders.0.file: must name a mesh file, got an empty string");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'plane', 'color': [0, 0, 2]}]}",
                   "t.json: colliders.0.color.2: must be between 0 and 1, got 2");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'center': [0, NaN, 0]}]}",
                   "t.json: colliders.0.center.1: must be a finite number, got NaN");
    EXPECT_INVALID("{'cloths': [{'velocity': [0, 0, -2e4]}]}",
                   "t.json: cloths.0.velocity: must be at most 10000 m/s in magnitude, got 20000 m/s ([0, 0, -20000])");
}

static void test_json_friction(void)
{
    /* Negative friction is the C API's "the scene's"; a scene file leaves the key out. */
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'plane', 'friction': -1}]}",
                   "t.json: colliders.0.friction: must be at least 0, got -1 (leave it out for collision.friction)");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'plane', 'static_friction': -0.5}]}",
                   "t.json: colliders.0.static_friction: must be at least 0, got -0.5 (leave it out for "
                   "collision.static_friction)");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'plane', 'friction': -1e39}]}",
                   "t.json: colliders.0.friction: is too large for single precision (at most "
                   "3.4028235e+38 in magnitude), got -1e+39");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'plane', 'friction': 0.6, 'static_friction': 0.5}]}",
                   "t.json: colliders.0.static_friction: must be at least friction (0.6), got 0.5");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'plane', 'friction': 0.6}]}",
                   "t.json: colliders.0.static_friction: is not given, and collision.static_friction (0.4) is below "
                   "this collider's friction (0.6): give a static_friction of at least 0.6");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'plane', 'static_friction': 0.1}]}",
                   "t.json: colliders.0.static_friction: must be at least collision.friction (0.3), got 0.1");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'friction': 0.5}}",
                   "t.json: collision.static_friction: must be at least friction (0.5), got 0.4");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'friction': -0.5}}",
                   "t.json: collision.friction: must be at least 0, got -0.5");
    EXPECT_INVALID("{'cloths': [{}], 'collision': {'thickness': -1}}",
                   "t.json: collision.thickness: must be at least 0, got -1");
    /* The scene's defaults, raised together, cover a collider that gives neither. */
    cvk_scene* scene = PARSE_OK("{'cloths': [{}], 'collision': {'friction': 0.7, 'static_friction': 0.9},"
                                " 'colliders': [{'type': 'plane'}]}");
    cvk_scene_destroy(scene);
}

static void test_json_keyframes(void)
{
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'keyframes': [{'time': 1}, {'time': 0.5}]}]}",
                   "t.json: colliders.0.keyframes.1.time: must be greater than the previous keyframe's time (1), "
                   "got 0.5");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'keyframes': [{'time': 1}, {'time': 1}]}]}",
                   "t.json: colliders.0.keyframes.1.time: must be greater than the previous keyframe's time (1), got 1");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'box', 'keyframes': [{'time': 0,"
                   " 'rotation': [0, 0, 0, 0]}]}]}",
                   "t.json: colliders.0.keyframes.0.rotation: must not be zero, got [0, 0, 0, 0]");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'box', 'loop': true, 'keyframes': [{'time': 0}]}]}",
                   "t.json: colliders.0.loop: a looping motion needs at least two keyframes, got 1");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'box', 'keyframes': [{'translation': [0, 1, 0]}]}]}",
                   "t.json: colliders.0.keyframes.0.time: missing; a keyframe needs its time");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'box', 'keyframes': [{'time': 0, 'scale': 2}]}]}",
                   "t.json: colliders.0.keyframes.0.scale: unknown key (expected one of: time, translation, rotation)");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'box', 'keyframes': {'time': 0}}]}",
                   "t.json: colliders.0.keyframes: expected an array of keyframe objects, got an object");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'box', 'keyframes': [{'time': -1}]}]}",
                   "t.json: colliders.0.keyframes.0.time: must be at least 0, got -1");
    EXPECT_INVALID("{'cloths': [{}], 'colliders': [{'type': 'box', 'loop': 'yes'}]}",
                   "t.json: colliders.0.loop: expected true or false, got the string \"yes\"");
}

/* ---- overrides ---- */

static void test_overrides(void)
{
    const char* const sets[] = {"colliders.0.radius=0.3", "collision.self=true", "collision.thickness=0.01",
                                "colliders.1={\"type\": \"box\", \"half_extents\": [1, 1, 1]}",
                                "colliders.1.keyframes.0={\"time\": 2}", "colliders.0.friction=0.1",
                                "cloths.0.velocity=[0, 5, 0]"};
    cvk_scene* scene = PARSE_OK_SET("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'radius': 1}]}", sets);
    if (scene) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        CHECK(d->collision.self);
        CHECK_FLOAT(d->collision.thickness, 0.01f);
        CHECK_INT(d->collider_count, 2);
        CHECK_FLOAT(d->colliders[0].radius, 0.3f);
        CHECK_FLOAT(d->colliders[0].friction, 0.1f);
        CHECK_INT(d->colliders[1].type, CVK_COLLIDER_BOX);
        CHECK_FLOAT(d->colliders[1].half_extents[0], 1.0f);
        CHECK_INT(d->colliders[1].motion.keyframe_count, 1);
        CHECK_FLOAT(d->colliders[1].motion.keyframes[0].time, 2.0f);
        CHECK_FLOAT(d->cloths[0].velocity[1], 5.0f);
    }
    cvk_scene_destroy(scene);

    const char* base = "{'cloths': [{}]}";
    const char* sphere = "{'cloths': [{}], 'colliders': [{'type': 'sphere'}]}";
    EXPECT_SET_ERROR(base, "collision.thickness=NaN",
                     "t.json: collision.thickness (from --set): must be a finite number, got NaN");
    EXPECT_SET_ERROR(base, "collision.self=yes",
                     "t.json: collision.self (from --set): expected true or false, got the string \"yes\"");
    EXPECT_SET_ERROR(sphere, "colliders.0.radius=-1",
                     "t.json: colliders.0.radius (from --set): must be greater than 0, got -1");
    EXPECT_SET_ERROR(sphere, "colliders.0.friction=-0.2",
                     "t.json: colliders.0.friction (from --set): must be at least 0, got -0.2 (leave it out for "
                     "collision.friction)");
    /* A new collider made by a path alone has no type (the missing key is not the one set). */
    EXPECT_SET_ERROR(base, "colliders.0.radius=0.3",
                     "t.json: colliders.0.type: missing; a collider needs its type: plane, sphere, box, "
                     "capsule, funnel or mesh");
    /* Changing the type leaves the old type's keys behind, which the new type does not take:
       the file's key is named, with the type it now has. */
    EXPECT_SET_ERROR("{'cloths': [{}], 'colliders': [{'type': 'sphere', 'radius': 1}]}", "colliders.0.type=box",
                     "t.json: colliders.0.radius: unknown key for a box collider (expected one of: type, "
                     "name, friction, static_friction, color, keyframes, loop, material, center, half_extents, rotation)");
    EXPECT_SET_ERROR(sphere, "colliders.0.keyframes.1={\"time\": 1}",
                     "t.json: --set colliders.0.keyframes.1: index 1 is out of range (colliders.0.keyframes has 0 "
                     "elements)");
}

/* ---- files ---- */

/* A mesh collider's relative file is relative to the scene file's folder, as a cloth's mesh
   is; so is one set with an override. */
static void test_mesh_file_path(void)
{
    char dir[] = "/tmp/clothvk-test-collide-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp worked");
        return;
    }
    char path[128], expected[512];
    snprintf(path, sizeof path, "%s/scene.json", dir);
    CHECK(write_file(path, "{\"cloths\": [{}], \"colliders\": [{\"type\": \"mesh\", \"file\": \"meshes/chair.obj\"},"
                           " {\"type\": \"mesh\", \"file\": \"/abs/table.obj\"}]}\n"));
    const char* const sets[] = {"colliders.2={\"type\": \"mesh\", \"file\": \"stool.obj\"}"};
    cvk_scene* scene = NULL;
    cvk_error err = {0};
    CHECK_INT(cvk_scene_load(path, sets, 1, &scene, &err), CVK_SUCCESS);
    if (scene) {
        const cvk_collider_desc* c = cvk_scene_get_desc(scene)->colliders;
        snprintf(expected, sizeof expected, "%s/meshes/chair.obj", dir);
        CHECK_STR(c[0].file, expected);
        CHECK_STR(c[1].file, "/abs/table.obj");
        snprintf(expected, sizeof expected, "%s/stool.obj", dir);
        CHECK_STR(c[2].file, expected);
    }
    cvk_scene_destroy(scene);
    CHECK(remove(path) == 0);
    CHECK(rmdir(dir) == 0);
}

int main(void)
{
    test_defaults();
    test_names();
    test_validate_collision();
    test_validate_radius();
    test_validate_detection_interval();
    test_keys_without_effect();
    test_validate_collider_list();
    test_validate_shapes();
    test_validate_friction();
    test_validate_keyframes();
    test_validate_velocity();
    test_json();
    test_json_types();
    test_json_values();
    test_json_friction();
    test_json_keyframes();
    test_overrides();
    test_mesh_file_path();
    printf("%d checks, %d failed\n", T.checks, T.failures);
    return T.failures ? 1 : 0;
}
