/* The renderer's effects, each checked by what the image must show with it on and off:
   - ambient occlusion (render.ao): the ground at the foot of an upright cloth hanging 1 cm
     above it, lit from the front (no shadow there), is darker with it than without, and open
     ground 40 cm away keeps its brightness;
   - soft shadows (render.soft_shadows, render.key_angle): across the edge of the shadow a
     cloth 0.6 m up casts on the ground, more pixels lie between lit and shadowed with a wide
     light than with the fixed filter, and the middle of the shadow and the open ground are the
     same in both;
   - the highlights' roll-off (render.tone_map): a white cloth under a key light twice full
     white clips to 255 without it, and stays below 255, brighter where the light falls more
     squarely, with it;
   - sky light (render.sky_light): in the key light's shadow, a cloth facing up (towards the
     sky) is brighter than one facing down (towards the ground), and without it they match to
     within the flat ambient's small tilt;
   - the same bytes from two renderers of one scene with every effect on. */
#include "harness.h"

enum { W = 200, H = 150 };

/* ---- scenes: static cloths ---- */

typedef struct setup {
    cvk_cloth_desc cloths[2];
    cvk_scene_desc scene;
    cvk_sim* sim;
    cvk_mesh* mesh;
    cvk_renderer* renderer;
} setup;

static cvk_cloth_desc square_cloth(const float origin[3], const float u[3], const float v[3], const float color[3])
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = c.grid[1] = 16;
    memcpy(c.origin, origin, sizeof c.origin);
    memcpy(c.u_axis, u, sizeof c.u_axis);
    memcpy(c.v_axis, v, sizeof c.v_axis);
    memcpy(c.color, color, sizeof c.color);
    return c;
}

static cvk_render_desc view(const float eye[3], const float target[3], const float key[3])
{
    cvk_render_desc r = cvk_default_render_desc();
    r.size[0] = W;
    r.size[1] = H;
    r.auto_eye = r.auto_target = false;
    memcpy(r.eye, eye, sizeof r.eye);
    memcpy(r.target, target, sizeof r.target);
    memcpy(r.key.direction, key, sizeof r.key.direction);
    r.auto_ground_height = false;
    r.ground_height = 0.0f;
    r.shadow_map_size = 1024;
    return r;
}

static void setup_scene(setup* s, cvk_context* ctx, uint32_t cloth_count, const cvk_render_desc* render)
{
    s->scene = cvk_default_scene_desc();
    s->scene.integrate = false;
    memset(s->scene.gravity, 0, sizeof s->scene.gravity);
    s->scene.cloths = s->cloths;
    s->scene.cloth_count = cloth_count;
    s->scene.render = *render;
    cvk_error err;
    REQUIRE_OK(harness_sim_create(ctx, &s->scene, &s->sim, &err), err);
    REQUIRE_OK(cvk_mesh_create(s->sim, NULL, &s->mesh, &err), err);
    REQUIRE_OK(cvk_renderer_create(s->mesh, &s->scene.render, &s->renderer, &err), err);
}

static void teardown(setup* s)
{
    cvk_renderer_destroy(s->renderer);
    cvk_mesh_destroy(s->mesh);
    cvk_sim_destroy(s->sim);
}

/* ---- pixels ---- */

static const uint8_t* pixel(const cvk_image* im, int x, int y)
{
    return im->pixels + (size_t)y * im->row_bytes + 4 * (size_t)x;
}

static double luminance(const uint8_t* p)
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

/* Mean luminance over the pixels of [x0, x1) x [y0, y1). */
static double region_luminance(const cvk_image* im, int x0, int y0, int x1, int y1)
{
    double sum = 0.0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++)
            sum += luminance(pixel(im, x, y));
    return sum / ((double)(x1 - x0) * (y1 - y0));
}

static void project(const cvk_renderer* r, const float p[3], double out[2])
{
    cvk_render_view v = cvk_renderer_get_view(r);
    const float* m = v.view_proj;
    double clip[4];
    for (int k = 0; k < 4; k++)
        clip[k] = m[k] * p[0] + m[4 + k] * p[1] + m[8 + k] * p[2] + m[12 + k];
    out[0] = (clip[0] / clip[3] * 0.5 + 0.5) * W;
    out[1] = (clip[1] / clip[3] * 0.5 + 0.5) * H;
}

/* Draws the scene of `s` (its cloths set) with `render`, copies the image into `out` (W x H x 4
   bytes) and projects `point` into `at`. */
static void render_once(cvk_context* ctx, setup* s, uint32_t cloth_count, const cvk_render_desc* render,
                        uint8_t* out, const float point[3], double at[2])
{
    setup_scene(s, ctx, cloth_count, render);
    cvk_image im = cvk_renderer_get_image(s->renderer);
    for (int y = 0; y < H; y++)
        memcpy(out + (size_t)y * W * 4, pixel(&im, 0, y), (size_t)W * 4);
    if (point)
        project(s->renderer, point, at);
    teardown(s);
}

/* With CLOTHVK_TEST_IMAGES set to a folder, the image is written there as NAME.png. */
static void keep(const cvk_image* im, const char* name)
{
    const char* folder = getenv("CLOTHVK_TEST_IMAGES");
    if (!folder)
        return;
    char path[512];
    snprintf(path, sizeof path, "%s/%s.png", folder, name);
    cvk_error err;
    REQUIRE_OK(cvk_image_write_png(im, path, &err), err);
}

static const float grey[3] = {0.6f, 0.6f, 0.6f};
static const float flat_u[3] = {1, 0, 0};

/* ---- the facts ---- */

static void occlusion_at_foot(cvk_context* ctx)
{
    /* A 1 m x 0.5 m upright cloth whose lower edge hangs 1 cm above the ground, seen from the
       front and above, lit from the front: nothing shadows the ground in front of it. */
    cvk_render_desc r = view((const float[3]){0.0f, 0.9f, 1.4f}, (const float[3]){0.0f, 0.1f, 0.0f},
                             (const float[3]){0.1f, 0.6f, 1.0f});
    r.ao_radius = 0.1f;
    static uint8_t on[W * H * 4], off[W * H * 4];
    const float origin[3] = {-0.5f, 0.51f, 0.0f};
    const float down[3] = {0.0f, -1.0f, 0.0f};
    double foot[2], near_foot[2];
    setup s = {0};
    for (int pass = 0; pass < 2; pass++) {
        s.cloths[0] = square_cloth(origin, flat_u, down, grey);
        s.cloths[0].size[1] = 0.5f;
        r.ao = pass == 0;
        render_once(ctx, &s, 1, &r, pass == 0 ? on : off, (const float[3]){0.0f, 0.0f, 0.0f}, foot);
    }
    /* The ground's strip from 1 to 4 cm in front of the foot, over the middle half of the cloth. */
    s.cloths[0] = square_cloth(origin, flat_u, down, grey);
    s.cloths[0].size[1] = 0.5f;
    double a0[2], a1[2];
    setup_scene(&s, ctx, 1, &r);
    project(s.renderer, (const float[3]){-0.25f, 0.0f, 0.01f}, a0);
    project(s.renderer, (const float[3]){0.25f, 0.0f, 0.04f}, a1);
    project(s.renderer, (const float[3]){0.0f, 0.0f, 0.4f}, near_foot);
    teardown(&s);
    cvk_image a = {on, W, H, 4 * W}, b = {off, W, H, 4 * W};
    keep(&a, "occlusion-on");
    keep(&b, "occlusion-off");
    int x0 = (int)ceil(a0[0]), x1 = (int)a1[0], y0 = (int)ceil(a0[1]), y1 = (int)a1[1] + 1;
    CHECK(x1 - x0 >= 10 && y1 > y0 && y0 > (int)foot[1], "the strip in front of the foot is [%d, %d) x [%d, %d)",
          x0, x1, y0, y1);
    double dark = region_luminance(&a, x0, y0, x1, y1);
    double plain = region_luminance(&b, x0, y0, x1, y1);
    CHECK(dark < 0.95 * plain, "the ground at the cloth's foot has luminance %.1f with ambient occlusion, %.1f "
          "without", dark, plain);
    /* Open ground 40 cm in front: unchanged. */
    int ox = (int)near_foot[0], oy = (int)near_foot[1];
    double open_on = region_luminance(&a, ox - 5, oy - 2, ox + 5, oy + 3);
    double open_off = region_luminance(&b, ox - 5, oy - 2, ox + 5, oy + 3);
    CHECK(fabs(open_on - open_off) < 1.0, "open ground has luminance %.1f with ambient occlusion, %.1f without",
          open_on, open_off);
    printf("ground at the cloth's foot: %.1f with ambient occlusion, %.1f without; open ground %.1f and %.1f\n",
           dark, plain, open_on, open_off);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    occlusion_at_foot(ctx);
    return harness_finish(ctx);
}
