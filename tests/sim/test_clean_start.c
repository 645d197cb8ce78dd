/* What cvk_sim_create makes of the collision block once the scene is built:
   - the clean start: two cloths crossing each other are refused with one sentence naming the
     cloths, the first pair of triangles and where; a cloth through itself likewise; with
     collision.allow_intersecting_start, or without self-contact, the scene is made;
   - a start inside a collider, with or without self-contact: a free particle more than the
     thickness inside is refused with one sentence naming the cloth, the collider, the particle,
     how deep and where; within the thickness, pinned, or allowed, the scene is made;
   - a contact radius given with a default thickness, against the thickness resolved;
   - the notes: one sentence for each key that no longer has an effect, in the order of the
     scene format, and none for a scene that sets none. */
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>
#include <unistd.h>

#include "harness.h"

/* An 11 x 11 cloth, 1 m square, level at y = 1 ("a"), and one standing across it ("b"). */
static void crossing_scene(cvk_scene_desc* scene, cvk_cloth_desc cloths[2])
{
    *scene = cvk_default_scene_desc();
    for (int i = 0; i < 2; i++) {
        cloths[i] = cvk_default_cloth_desc();
        cloths[i].grid[0] = cloths[i].grid[1] = 11;
        cloths[i].mass = 0.1f;
    }
    cloths[0].name = "a";
    cloths[1].name = "b";
    const float origin[3] = {-0.45f, 0.55f, 0.55f}, up[3] = {0.0f, 1.0f, 0.0f};
    memcpy(cloths[1].origin, origin, sizeof origin);
    memcpy(cloths[1].v_axis, up, sizeof up);
    scene->cloths = cloths;
    scene->cloth_count = 2;
    scene->collision.self = true;
}

/* Creates the simulation; on failure checks the result and the message, and that no
   simulation came back. */
static cvk_sim* create(cvk_context* ctx, const cvk_scene_desc* scene, const char* message)
{
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = scene;
    cvk_sim* sim = (cvk_sim*)&desc; /* not NULL: a failure must clear it */
    cvk_error err;
    cvk_result r = cvk_sim_create(ctx, &desc, &sim, &err);
    if (message) {
        CHECK(r == CVK_ERROR_INVALID_ARGUMENT, "%s, expected CVK_ERROR_INVALID_ARGUMENT",
              cvk_result_name(r));
        CHECK(r == CVK_SUCCESS || strcmp(err.message, message) == 0,
              "the message is\n    %s\nexpected\n    %s", err.message, message);
        CHECK(r == CVK_SUCCESS || sim == NULL, "a failed creation returned a simulation");
        if (r == CVK_SUCCESS)
            cvk_sim_destroy(sim);
        return NULL;
    }
    CHECK(r == CVK_SUCCESS, "creation failed: %s", err.message);
    return r == CVK_SUCCESS ? sim : NULL;
}

static void crossing_cloths(cvk_context* ctx)
{
    cvk_scene_desc scene;
    cvk_cloth_desc cloths[2];
    crossing_scene(&scene, cloths);
    create(ctx, &scene,
           "collision: cloths \"a\" and \"b\" intersect at the start (triangle 101 of \"a\" and "
           "triangle 80 of \"b\", near (-0.425, 0.992, 0.558)); set "
           "collision.allow_intersecting_start to simulate anyway");
    /* The pair found does not depend on the scene's order: "b" first names its own triangle
       first. */
    cvk_cloth_desc swapped[2] = {cloths[1], cloths[0]};
    scene.cloths = swapped;
    create(ctx, &scene,
           "collision: cloths \"b\" and \"a\" intersect at the start (triangle 80 of \"b\" and "
           "triangle 101 of \"a\", near (-0.425, 0.992, 0.558)); set "
           "collision.allow_intersecting_start to simulate anyway");
    scene.cloths = cloths;

    scene.collision.allow_intersecting_start = true;
    cvk_sim* sim = create(ctx, &scene, NULL);
    uint64_t pairs = 0;
    cvk_error err;
    if (sim) {
        REQUIRE_OK(cvk_sim_count_intersections(sim, &pairs, &err), err);
        CHECK(pairs > 0, "allowed to start crossing, the cloths do not cross");
        CHECK(cvk_sim_note_count(sim) == 0, "%u notes for a scene that sets no old key",
              cvk_sim_note_count(sim));
    }
    cvk_sim_destroy(sim);

    scene.collision.allow_intersecting_start = false;
    scene.collision.self = false; /* no cloth contact: nothing to keep apart */
    cvk_sim_destroy(create(ctx, &scene, NULL));
}

/* Two triangles of one mesh cloth that share no vertex, one through the other. */
static void cloth_through_itself(cvk_context* ctx)
{
    char folder[] = "/tmp/clothvk-clean-start-XXXXXX";
    CHECK(mkdtemp(folder) != NULL, "cannot make a folder under /tmp for the mesh file");
    char path[sizeof folder + 16];
    snprintf(path, sizeof path, "%s/fold.obj", folder);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    CHECK(fd >= 0, "cannot make %s", path);
    if (fd < 0)
        return;
    static const char obj[] = "v 0 0 0\nv 1 0 0\nv 0 0 1\n"
                              "v 0.2 -0.5 0.2\nv 0.2 0.5 0.2\nv 0.6 0 -0.3\n"
                              "f 1 2 3\nf 4 5 6\n";
    bool written = write(fd, obj, sizeof obj - 1) == (ssize_t)(sizeof obj - 1);
    close(fd);
    CHECK(written, "cannot write %s", path);
    cvk_scene_desc scene = cvk_default_scene_desc();
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.mesh = path;
    cloth.mass = 0.01f;
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.collision.self = true;
    create(ctx, &scene,
           "collision: cloth \"cloth0\" intersects itself at the start (triangles 0 and 1, near "
           "(0.333, 0.000, 0.183)); set collision.allow_intersecting_start to simulate anyway");
    scene.collision.allow_intersecting_start = true;
    cvk_sim_destroy(create(ctx, &scene, NULL));
    unlink(path);
    rmdir(folder);
}

/* A 1 m cloth of 11 x 11 particles: springs 0.1 m, so the default thickness is 0.05 m. */
static void radius_against_default_thickness(cvk_context* ctx)
{
    cvk_scene_desc scene;
    cvk_cloth_desc cloths[2];
    crossing_scene(&scene, cloths);
    scene.cloth_count = 1;
    scene.collision.radius = 0.04f;
    create(ctx, &scene,
           "collision.radius: 0.04 is not more than the thickness 0.05, half the shortest "
           "structural rest length (contact acts between the thickness and the radius)");
    scene.collision.radius = 0.06f;
    cvk_sim_destroy(create(ctx, &scene, NULL));
}

static void notes(cvk_context* ctx)
{
    static const char* const expected[] = {
        "collision.detect_every has no effect: contact searches again when a particle's "
        "displacement reaches its bound",
        "collision.exclusion has no effect: no pair of cloth primitives that shares no particle "
        "is left out of contact",
        "collision.edges has no effect: edge-edge contact is always on",
    };
    cvk_scene_desc scene;
    cvk_cloth_desc cloths[2];
    crossing_scene(&scene, cloths);
    scene.cloth_count = 1;
    scene.collision.edges = true;
    cvk_sim* sim = create(ctx, &scene, NULL);
    if (sim) {
        CHECK(cvk_sim_note_count(sim) == 1, "%u notes for collision.edges, expected 1",
              cvk_sim_note_count(sim));
        const char* note = cvk_sim_note(sim, 0);
        CHECK(note && strcmp(note, expected[2]) == 0, "the note is %s", note ? note : "NULL");
        CHECK(cvk_sim_note(sim, 1) == NULL, "a note past the count");
    }
    cvk_sim_destroy(sim);
    scene.collision.exclusion = 0.1f;
    scene.collision.detect_every = 2;
    scene.collision.self = false; /* noted with or without self-contact */
    sim = create(ctx, &scene, NULL);
    if (sim) {
        CHECK(cvk_sim_note_count(sim) == 3, "%u notes for three keys", cvk_sim_note_count(sim));
        for (uint32_t i = 0; i < 3 && i < cvk_sim_note_count(sim); i++)
            CHECK(strcmp(cvk_sim_note(sim, i), expected[i]) == 0, "note %u is %s, expected %s", i,
                  cvk_sim_note(sim, i), expected[i]);
    }
    cvk_sim_destroy(sim);
    CHECK(cvk_sim_note_count(NULL) == 0 && cvk_sim_note(NULL, 0) == NULL,
          "a NULL simulation has notes");
}

/* Positions after `frames` frames (NULL on failure, checked); the simulation's last note, or
   "" with none, in note (size bytes, cut to fit). */
static float* run(cvk_context* ctx, const cvk_scene_desc* scene, uint32_t frames, char* note, size_t size)
{
    note[0] = '\0';
    cvk_sim* sim = create(ctx, scene, NULL);
    if (!sim)
        return NULL;
    cvk_error err;
    uint64_t n = cvk_sim_particle_count(sim);
    float* xyz = malloc(3 * n * sizeof *xyz);
    CHECK(xyz && cvk_sim_step(sim, frames, &err) == CVK_SUCCESS &&
          cvk_sim_read_positions(sim, xyz, n, &err) == CVK_SUCCESS, "stepping failed");
    if (cvk_sim_note_count(sim) > 0)
        snprintf(note, size, "%s", cvk_sim_note(sim, cvk_sim_note_count(sim) - 1));
    cvk_sim_destroy(sim);
    return xyz;
}

/* With self-contact, a substep in which a collider's surface moves more than 0.35 thicknesses
   is split: a ball at 10 m/s past the 1 m cloth (thickness 0.05 m) with substeps of 2 ms moves
   0.4 thicknesses a substep, so each runs as two of 1 ms with the damping over the frame kept,
   the same bits as the scene written with those substeps; at 8 m/s (0.32) nothing is split. A
   With implicit Euler the limit is half (0.175): the ball at 8 m/s splits them, and a switch
   to implicit from pd's unsplit substeps is refused. A
   box centred at (1, -0.5, 0) turning a quarter turn a second about the origin counts its
   bounding sphere's reach (1.12 + 0.17 m): 2.03 m/s, 0.41 thicknesses in a 10 ms substep. */
static void split_for_fast_colliders(cvk_context* ctx)
{
    cvk_scene_desc scene;
    cvk_cloth_desc cloths[2];
    crossing_scene(&scene, cloths);
    scene.cloth_count = 1;
    scene.dt = 0.002f;
    scene.substeps = 8;
    scene.damping = 0.004f;
    cvk_keyframe keys[2] = {{.time = 0.0f, .translation = {-1.0f, 0.0f, 0.0f}, .rotation = {1, 0, 0, 0}},
                            {.time = 0.2f, .translation = {1.0f, 0.0f, 0.0f}, .rotation = {1, 0, 0, 0}}};
    cvk_collider_desc ball = cvk_default_collider_desc();
    ball.type = CVK_COLLIDER_SPHERE;
    ball.name = "ball";
    ball.center[1] = -0.5f;
    ball.radius = 0.2f;
    ball.motion.keyframes = keys;
    ball.motion.keyframe_count = 2;
    scene.colliders = &ball;
    scene.collider_count = 1;
    char note[256];
    float* split = run(ctx, &scene, 3, note, sizeof note);
    CHECK(strcmp(note, "substeps split: 8 substeps of 2 ms a frame run as 16 of 1 ms, so that "
                       "collider 0 \"ball\" (10 m/s) moves at most 0.2 of the thickness a "
                       "substep") == 0, "the note is %s", note);
    cvk_scene_desc fine = scene;
    fine.dt = 0.001f;
    fine.substeps = 16;
    fine.damping = (float)(1.0 - sqrt(1.0 - (double)0.004f));
    float* direct = run(ctx, &fine, 3, note, sizeof note);
    CHECK(note[0] == '\0', "a note without a split: %s", note);
    CHECK(split && direct && memcmp(split, direct, 3 * 121 * sizeof(float)) == 0,
          "the split substeps are not the scene written with them");
    free(split);
    free(direct);
    keys[1].time = 0.25f; /* 8 m/s */
    free(run(ctx, &scene, 1, note, sizeof note));
    CHECK(note[0] == '\0', "a ball at 0.32 thicknesses a substep split them: %s", note);
    /* Implicit Euler keeps the bounds after its solve only: half pd's limit. */
    cvk_scene_desc implicit = scene;
    implicit.solver.method = CVK_METHOD_IMPLICIT;
    implicit.solver.linear = CVK_LINEAR_CG;
    free(run(ctx, &implicit, 1, note, sizeof note));
    CHECK(strcmp(note, "substeps split: 8 substeps of 2 ms a frame run as 16 of 1 ms, so that "
                       "collider 0 \"ball\" (8 m/s) moves at most 0.16 of the thickness a "
                       "substep") == 0, "implicit: the note is %s", note);
    cvk_error err;
    cvk_sim* sim = NULL;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    CHECK(cvk_sim_set_solver(sim, &implicit.solver, &err) == CVK_ERROR_UNSUPPORTED &&
              strcmp(err.message, "solver.method: implicit with self-contact needs substeps in "
                                  "which no collider moves more than 0.175 of the thickness (one "
                                  "moves 0.32 here); make the simulation with implicit, which "
                                  "splits them") == 0,
          "a switch to implicit with pd's substeps: %s", err.message);
    cvk_sim_destroy(sim);

    cvk_keyframe turn[2] = {{.time = 0.0f, .rotation = {1, 0, 0, 0}},
                            {.time = 1.0f, .rotation = {0.7071068f, 0, 0.7071068f, 0}}};
    cvk_collider_desc box = cvk_default_collider_desc();
    box.type = CVK_COLLIDER_BOX;
    box.center[0] = 1.0f;
    box.center[1] = -0.5f;
    box.half_extents[0] = box.half_extents[1] = box.half_extents[2] = 0.1f;
    box.motion.keyframes = turn;
    box.motion.keyframe_count = 2;
    scene.colliders = &box;
    scene.dt = 0.01f;
    scene.substeps = 1;
    free(run(ctx, &scene, 1, note, sizeof note));
    CHECK(strcmp(note, "substeps split: 1 substeps of 10 ms a frame run as 2 of 5 ms, so that "
                       "collider 0 (2.03 m/s) moves at most 0.2 of the thickness a substep") == 0,
          "the note is %s", note);
}

/* Cloth "a" of crossing_scene alone (level at y = 1, thickness 0.05 m) and one collider. */
static void inside_colliders(cvk_context* ctx)
{
    cvk_scene_desc scene;
    cvk_cloth_desc cloths[2];
    crossing_scene(&scene, cloths);
    scene.cloth_count = 1;
    scene.collision.self = false; /* the rule holds without self-contact too */
    cvk_collider_desc plane = cvk_default_collider_desc();
    plane.type = CVK_COLLIDER_PLANE;
    plane.point[1] = 1.2f; /* the ground 0.2 m above the cloth */
    scene.colliders = &plane;
    scene.collider_count = 1;
    create(ctx, &scene,
           "collision: cloth \"a\" starts inside colliders.0: its particle [0, 0] is 0.2 m "
           "inside, at (-0.500, 1.000, 0.000); set collision.allow_intersecting_start to "
           "simulate anyway");
    scene.collision.allow_intersecting_start = true;
    cvk_sim_destroy(create(ctx, &scene, NULL));
    scene.collision.allow_intersecting_start = false;
    plane.point[1] = 1.04f; /* 0.04 m inside: within the thickness */
    cvk_sim_destroy(create(ctx, &scene, NULL));

    /* A ball of 0.08 m about the corner [10, 0]: the corner alone is inside, 0.08 m deep. */
    cvk_collider_desc ball = cvk_default_collider_desc();
    ball.type = CVK_COLLIDER_SPHERE;
    ball.name = "ball";
    ball.center[0] = 0.5f;
    ball.center[1] = 1.0f;
    ball.center[2] = 0.0f;
    ball.radius = 0.08f;
    scene.colliders = &ball;
    scene.collision.self = true;
    create(ctx, &scene,
           "collision: cloth \"a\" starts inside colliders.0 (\"ball\"): its particle [10, 0] is "
           "0.08 m inside, at (0.500, 1.000, 0.000); set collision.allow_intersecting_start to "
           "simulate anyway");
    const uint32_t pins[1][2] = {{10, 0}}; /* pinned, it does not move: nothing to refuse */
    cloths[0].pins = pins;
    cloths[0].pin_count = 1;
    cvk_sim_destroy(create(ctx, &scene, NULL));
}

int main(void)
{
    cvk_context* ctx = harness_context();
    crossing_cloths(ctx);
    cloth_through_itself(ctx);
    inside_colliders(ctx);
    radius_against_default_thickness(ctx);
    notes(ctx);
    split_for_fast_colliders(ctx);
    return harness_finish(ctx);
}
