/* Colliders in the rendered image, checked by what they must show:
   - a sphere under a cloth shows its own colour, its side towards the key light brighter than
     its side away from it, and its shadow darkens the ground on the side away from the light
     (and not the side towards it);
   - the cloth above the sphere shadows it, and a sphere above a cloth shadows the cloth,
     when the light comes from above;
   - a rotated box shows its colour, its top face (towards the light) brighter than a side face;
   - a keyframed sphere is drawn where the simulation's own recorded work moved it, by one
     command buffer (a simulated frame and its image) recorded once and submitted again and
     again, and where a snapshot of that state loaded into a new simulation puts it;
   - a static plane facing up becomes the ground (its height), as does one at the height the
     scene gives the ground, but not one above it; the automatic camera frames
     a collider near the cloths but not a far box or a 100 m plane.
   Scenes without colliders are covered by test_render (their images are unchanged). Set
   CLOTHVK_TEST_IMAGES to a folder to keep the images. */
#include "render_fixture.h"

#include "core/gpu.h"

enum { W = 240, H = 180 };

static const float green[3] = {0.1f, 0.6f, 0.12f};
static const float red[3] = {0.8f, 0.1f, 0.08f};

/* A horizontal 1 m cloth at height y, centred on (x, z). */
static cvk_cloth_desc flat_cloth(float x, float y, float z)
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = c.grid[1] = 16;
    float origin[3] = {x - 0.5f, y, z - 0.5f}, u[3] = {1, 0, 0}, v[3] = {0, 0, 1};
    memcpy(c.origin, origin, sizeof origin);
    memcpy(c.u_axis, u, sizeof u);
    memcpy(c.v_axis, v, sizeof v);
    memcpy(c.color, red, sizeof red);
    return c;
}

static cvk_collider_desc sphere(float x, float y, float z, float radius)
{
    cvk_collider_desc c = cvk_default_collider_desc();
    c.type = CVK_COLLIDER_SPHERE;
    c.center[0] = x, c.center[1] = y, c.center[2] = z;
    c.radius = radius;
    memcpy(c.color, green, sizeof green);
    return c;
}

static cvk_render_desc view(const float eye[3], const float target[3], const float key[3])
{
    return grounded_view(W, H, eye, target, key);
}

static cvk_image draw(setup* s, const char* name)
{
    cvk_error err;
    REQUIRE_OK(cvk_renderer_draw(s->renderer, &err), err);
    cvk_image im = cvk_renderer_get_image(s->renderer);
    const char* folder = getenv("CLOTHVK_TEST_IMAGES");
    if (folder) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s.png", folder, name);
        REQUIRE_OK(cvk_image_write_png(&im, path, &err), err);
    }
    return im;
}

/* ---- pixels ---- */

static void project(const cvk_renderer* r, const float p[3], int out[2])
{
    cvk_render_view v = cvk_renderer_get_view(r);
    const float* m = v.view_proj;
    double clip[4];
    for (int k = 0; k < 4; k++)
        clip[k] = m[k] * p[0] + m[4 + k] * p[1] + m[8 + k] * p[2] + m[12 + k];
    out[0] = (int)floor((clip[0] / clip[3] * 0.5 + 0.5) * W);
    out[1] = (int)floor((clip[1] / clip[3] * 0.5 + 0.5) * H);
}

/* Mean luminance of the 3 x 3 pixels around the projection of p. */
static double brightness_at(const cvk_image* im, const cvk_renderer* r, const float p[3])
{
    int c[2];
    project(r, p, c);
    double sum = 0.0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++)
            sum += luminance(pixel(im, c[0] + dx, c[1] + dy));
    return sum / 9.0;
}

/* The pixel at p is mostly green (the sphere's colour). */
static bool greenish_at(const cvk_image* im, const cvk_renderer* r, const float p[3])
{
    int c[2];
    project(r, p, c);
    const uint8_t* px = pixel(im, c[0], c[1]);
    return px[1] > 2 * px[0] && px[1] > 2 * px[2];
}

/* ---- the facts ---- */

static const float sphere_eye[3] = {0.0f, 2.0f, 3.0f}, sphere_target[3] = {0.0f, 0.3f, 0.0f};

/* The sphere (radius 0.3 at (0, 0.4, 0)) under a cloth at y = 1.5, lit from +x and 45° up:
   the cloth's shadow falls beyond x < -1, the sphere's on the ground around (-0.4, 0, 0). */
static void sphere_under_cloth(cvk_context* ctx)
{
    setup s = {.cloths = {flat_cloth(0.0f, 1.5f, 0.0f)}, .collider_count = 1};
    s.colliders[0] = sphere(0.0f, 0.4f, 0.0f, 0.3f);
    cvk_render_desc r = view(sphere_eye, sphere_target, (const float[3]){1.0f, 1.0f, 0.0f});
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s, "sphere");
    const float middle[3] = {0.0f, 0.4f, 0.3f};
    CHECK(greenish_at(&im, s.renderer, middle), "the middle of the green sphere is not green");
    /* Points on the surface seen from the eye: one facing the light, one facing away. */
    float lit[3], dark[3];
    const float towards[3] = {0.7f, 0.3f, 0.65f}, away[3] = {-0.7f, -0.1f, 0.7f};
    double nt = sqrt(0.49 + 0.09 + 0.4225), na = sqrt(0.49 + 0.01 + 0.49);
    for (int k = 0; k < 3; k++) {
        lit[k] = s.colliders[0].center[k] + 0.28f * (float)(towards[k] / nt);
        dark[k] = s.colliders[0].center[k] + 0.28f * (float)(away[k] / na);
    }
    double b_lit = brightness_at(&im, s.renderer, lit), b_dark = brightness_at(&im, s.renderer, dark);
    CHECK(greenish_at(&im, s.renderer, lit), "the sphere's lit side is not its colour");
    CHECK(b_lit > 1.25 * b_dark, "the sphere's side towards the light (luminance %.1f) is not brighter than its "
          "side away from it (%.1f)", b_lit, b_dark);
    /* On the ground: in the sphere's shadow, on the sphere's lit side, and far from both. */
    const float shadowed[3] = {-0.5f, 0.0f, 0.1f}, beside[3] = {0.5f, 0.0f, 0.1f}, open[3] = {0.9f, 0.0f, 0.1f};
    double b_shadow = brightness_at(&im, s.renderer, shadowed), b_beside = brightness_at(&im, s.renderer, beside);
    double b_open = brightness_at(&im, s.renderer, open);
    CHECK(b_shadow < 0.75 * b_open, "the ground in the sphere's shadow (luminance %.1f) is not darker than open "
          "ground (%.1f)", b_shadow, b_open);
    CHECK(b_beside > 0.9 * b_open, "the ground on the sphere's lit side (luminance %.1f) is darker than open "
          "ground (%.1f): the shadow is on the wrong side", b_beside, b_open);
    printf("sphere: lit side %.1f, side away %.1f; ground in its shadow %.1f, beside it %.1f, open %.1f\n", b_lit,
           b_dark, b_shadow, b_beside, b_open);
    teardown(&s);
}

/* The top of the sphere, with the light from above, under the cloth and with the cloth away. */
static double sphere_top(cvk_context* ctx, float cloth_x, const char* name)
{
    setup s = {.cloths = {flat_cloth(cloth_x, 1.5f, 0.0f)}, .collider_count = 1};
    s.colliders[0] = sphere(0.0f, 0.4f, 0.0f, 0.3f);
    cvk_render_desc r = view(sphere_eye, sphere_target, (const float[3]){0.05f, 1.0f, 0.05f});
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s, name);
    const float top[3] = {0.0f, 0.4f + 0.28f * 0.9f, 0.28f * 0.436f};
    double b = brightness_at(&im, s.renderer, top);
    teardown(&s);
    return b;
}

static void cloth_shadows_sphere(cvk_context* ctx)
{
    double under = sphere_top(ctx, 0.0f, "sphere-under-cloth"), open = sphere_top(ctx, 3.0f, "sphere-open");
    CHECK(under < 0.7 * open, "the sphere's top under the cloth (luminance %.1f) is not darker than with the cloth "
          "away (%.1f)", under, open);
    printf("sphere top: under the cloth %.1f, cloth away %.1f\n", under, open);
}

/* A sphere above a cloth, lit from above: the cloth under it is in its shadow. */
static void sphere_shadows_cloth(cvk_context* ctx)
{
    setup s = {.cloths = {flat_cloth(0.0f, 0.5f, 0.0f)}, .collider_count = 1};
    s.colliders[0] = sphere(0.0f, 1.2f, 0.0f, 0.2f);
    cvk_render_desc r = view(sphere_eye, (const float[3]){0.0f, 0.5f, 0.0f}, (const float[3]){0.05f, 1.0f, 0.05f});
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s, "sphere-over-cloth");
    const float under[3] = {-0.035f, 0.5f, -0.035f}, open[3] = {0.35f, 0.5f, 0.3f};
    double b_under = brightness_at(&im, s.renderer, under), b_open = brightness_at(&im, s.renderer, open);
    CHECK(b_under < 0.7 * b_open, "the cloth under the sphere (luminance %.1f) is not darker than the cloth beside "
          "its shadow (%.1f)", b_under, b_open);
    printf("cloth: in the sphere's shadow %.1f, beside it %.1f\n", b_under, b_open);
    teardown(&s);
}

/* A box turned 30° about y, lit from above: its top is brighter than its front face. */
static void box_visible(cvk_context* ctx)
{
    const float blue[3] = {0.12f, 0.25f, 0.75f};
    setup s = {.cloths = {flat_cloth(-3.0f, 1.5f, -2.0f)}, .collider_count = 1};
    cvk_collider_desc* b = &s.colliders[0];
    *b = cvk_default_collider_desc();
    b->type = CVK_COLLIDER_BOX;
    b->center[1] = 0.3f;
    b->half_extents[0] = b->half_extents[1] = b->half_extents[2] = 0.3f;
    b->rotation[0] = (float)cos(15.0 * 3.14159265358979 / 180.0);
    b->rotation[2] = (float)sin(15.0 * 3.14159265358979 / 180.0);
    memcpy(b->color, blue, sizeof blue);
    cvk_render_desc r = view((const float[3]){0.8f, 1.8f, 2.8f}, (const float[3]){0.0f, 0.3f, 0.0f},
                             (const float[3]){0.3f, 1.0f, 0.2f});
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s, "box");
    const float top[3] = {0.0f, 0.6f, 0.0f}, front[3] = {0.15f, 0.3f, 0.26f};
    int c[2];
    project(s.renderer, top, c);
    const uint8_t* p = pixel(&im, c[0], c[1]);
    CHECK(p[2] > 2 * p[0] && p[2] > p[1], "the top of the blue box is (%u, %u, %u)", p[0], p[1], p[2]);
    double b_top = brightness_at(&im, s.renderer, top), b_front = brightness_at(&im, s.renderer, front);
    CHECK(b_top > 1.3 * b_front, "the box's top (luminance %.1f), towards the light, is not brighter than its "
          "front face (%.1f)", b_top, b_front);
    printf("box: top %.1f, front face %.1f\n", b_top, b_front);
    teardown(&s);
}

/* A sphere keyframed 1 m along +x over 0.2 s: drawn where the simulation's recorded frames
   moved it (the renderer reads the device's poses; nothing is written from the host). */
static void moving_sphere(cvk_context* ctx)
{
    static const cvk_keyframe keys[2] = {
        {.time = 0.0f, .rotation = {1, 0, 0, 0}},
        {.time = 0.2f, .translation = {1.0f, 0.0f, 0.0f}, .rotation = {1, 0, 0, 0}},
    };
    setup s = {.cloths = {flat_cloth(-3.0f, 1.5f, -2.0f)}, .collider_count = 1};
    s.colliders[0] = sphere(-0.5f, 0.4f, 0.0f, 0.25f);
    s.colliders[0].motion = (cvk_motion){.keyframes = keys, .keyframe_count = 2};
    cvk_render_desc r = view(sphere_eye, sphere_target, (const float[3]){0.3f, 1.0f, 0.2f});
    setup_scene(&s, ctx, 1, &r);
    const float start[3] = {-0.5f, 0.4f, 0.25f}, end[3] = {0.5f, 0.4f, 0.25f};
    cvk_image im = draw(&s, "moving-start");
    CHECK(greenish_at(&im, s.renderer, start) && !greenish_at(&im, s.renderer, end),
          "before any step the sphere is not drawn at its first keyframe alone");
    /* One command buffer of the caller's, recorded once: a simulated frame, then its image;
       submitted again and again. */
    cvk_error err;
    cvk_submitter sub;
    VkCommandBuffer cmd;
    REQUIRE_OK(cvk_submitter_create(ctx, &sub, &err), err);
    REQUIRE_OK(cvk_command_buffer_allocate(ctx, &sub, &cmd, &err), err);
    REQUIRE_OK(cvk_command_buffer_begin(cmd, 0, &err), err);
    REQUIRE_OK(cvk_sim_record(s.sim, cmd, 1, &err), err);
    REQUIRE_OK(cvk_renderer_record(s.renderer, cmd, &err), err);
    REQUIRE_OK(cvk_command_buffer_end(cmd, &err), err);
    uint32_t frames = (uint32_t)ceil(0.2 / (s.scene.dt * s.scene.substeps)) + 1;
    for (uint32_t f = 0; f < frames; f++)
        REQUIRE_OK(cvk_submit_and_wait(ctx, &sub, &cmd, 1, &err), err);
    cvk_submitter_destroy(ctx, &sub);
    im = cvk_renderer_get_image(s.renderer);
    CHECK(greenish_at(&im, s.renderer, end) && !greenish_at(&im, s.renderer, start),
          "after %u recorded frames (past the last keyframe) the sphere is not drawn 1 m along +x alone", frames);
    im = draw(&s, "moving-end");
    CHECK(greenish_at(&im, s.renderer, end) && !greenish_at(&im, s.renderer, start),
          "cvk_renderer_draw after the recorded frames does not draw the sphere 1 m along +x alone");
    teardown(&s);
    /* The same frames stepped by cvk_sim_step, as clothvk-sim bakes them, saved as a snapshot
       and loaded into a new simulation (as clothvk-render --from draws a bake): the sphere is
       drawn where the snapshot's clock puts it, not at its first keyframe. */
    setup_scene(&s, ctx, 1, &r);
    REQUIRE_OK(cvk_sim_step(s.sim, frames, &err), err);
    uint64_t size = cvk_sim_snapshot_size(s.sim);
    void* snapshot = malloc(size);
    if (!snapshot)
        exit(1);
    REQUIRE_OK(cvk_sim_save_snapshot(s.sim, snapshot, size, &err), err);
    teardown(&s);
    setup_scene(&s, ctx, 1, &r);
    REQUIRE_OK(cvk_sim_load_snapshot(s.sim, snapshot, size, &err), err);
    free(snapshot);
    im = draw(&s, "moving-loaded");
    CHECK(greenish_at(&im, s.renderer, end) && !greenish_at(&im, s.renderer, start),
          "a snapshot taken after the last keyframe, loaded into a new simulation, does not draw the sphere 1 m "
          "along +x alone");
    teardown(&s);
}

static cvk_render_view framed(cvk_context* ctx, const cvk_collider_desc* colliders, uint32_t count)
{
    setup s = {.cloths = {flat_cloth(0.0f, 1.0f, 0.0f)}, .collider_count = count};
    if (count)
        memcpy(s.colliders, colliders, count * sizeof *colliders);
    cvk_render_desc r = cvk_default_render_desc();
    r.size[0] = 64;
    r.size[1] = 48;
    r.shadow_map_size = 64;
    setup_scene(&s, ctx, 1, &r);
    cvk_render_view v = cvk_renderer_get_view(s.renderer);
    teardown(&s);
    return v;
}

static double reach_gap(const cvk_render_view* a, const cvk_render_view* b)
{
    double gap = 0.0;
    for (int k = 0; k < 3; k++)
        gap = fmax(gap, fmax(fabs(a->reach_min[k] - b->reach_min[k]), fabs(a->reach_max[k] - b->reach_max[k])));
    return gap;
}

/* The automatic view: a plane facing up is the ground; a far box and a tilted 100 m plane do
   not change the reach; a sphere beside the cloth joins it. */
static void framing(cvk_context* ctx)
{
    cvk_render_view alone = framed(ctx, NULL, 0);
    cvk_collider_desc c[3];
    c[0] = cvk_default_collider_desc(); /* a plane through the origin, +y up */
    c[0].point[1] = 0.25f;
    cvk_render_view ground = framed(ctx, c, 1);
    CHECK(fabs(ground.ground_height - 0.25) < 1e-6, "a plane facing up at y = 0.25 left the ground at %g m",
          ground.ground_height);
    c[0].normal[0] = 1.0f; /* tilted 45°: drawn as a square, not the ground */
    c[1] = cvk_default_collider_desc();
    c[1].type = CVK_COLLIDER_BOX;
    c[1].center[0] = 40.0f;
    cvk_render_view far = framed(ctx, c, 2);
    CHECK(reach_gap(&far, &alone) < 1e-6, "a far box and a tilted plane moved the reach by %g m",
          reach_gap(&far, &alone));
    c[2] = sphere(1.2f, 0.3f, 0.0f, 0.3f);
    cvk_render_view near = framed(ctx, c, 3);
    CHECK(near.reach_max[0] >= 1.5f - 1e-5 && near.reach_min[1] <= 1e-5,
          "a sphere beside the cloth (to x = 1.5, down to y = 0) is outside the reach [%g, %g] x [%g, %g]",
          near.reach_min[0], near.reach_max[0], near.reach_min[1], near.reach_max[1]);
}

/* A static plane facing up at the ground height the scene gives is the ground: not drawn
   again on top of it (in its own colour) on either side of the middle, while the same plane
   0.2 m higher is, on both. Returns on how many of the two sides the plane's green shows. */
static int plane_sides_drawn(cvk_context* ctx, float height)
{
    setup s = {.cloths = {flat_cloth(0.0f, 1.0f, 0.0f)}, .collider_count = 1};
    s.colliders[0] = cvk_default_collider_desc();
    s.colliders[0].point[1] = height;
    memcpy(s.colliders[0].color, green, sizeof green);
    cvk_render_desc r = view(sphere_eye, sphere_target, (const float[3]){0.3f, 1.0f, 0.4f});
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s, height == 0.0f ? "plane-at-ground" : "plane-above-ground");
    /* Ground in front of the cloth's shadow, on either side of the middle. */
    bool green_left = greenish_at(&im, s.renderer, (const float[3]){-0.8f, height, 1.2f});
    bool green_right = greenish_at(&im, s.renderer, (const float[3]){0.8f, height, 1.2f});
    teardown(&s);
    return (int)green_left + (int)green_right;
}

static void plane_at_ground_height(cvk_context* ctx)
{
    int at_ground = plane_sides_drawn(ctx, 0.0f), above = plane_sides_drawn(ctx, 0.2f);
    CHECK(at_ground == 0, "a green plane at the given ground height (0 m) is drawn over the ground "
          "on %d of 2 sides", at_ground);
    CHECK(above == 2, "a green plane 0.2 m above the given ground height is drawn on %d of 2 sides",
          above);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    sphere_under_cloth(ctx);
    cloth_shadows_sphere(ctx);
    sphere_shadows_cloth(ctx);
    box_visible(ctx);
    moving_sphere(ctx);
    framing(ctx);
    plane_at_ground_height(ctx);
    return harness_finish(ctx);
}
