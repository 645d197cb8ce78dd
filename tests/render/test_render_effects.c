/* The renderer's effects, each checked by what the image must show with it on and off:
   - ambient occlusion (render.ao): the ground at the foot of an upright cloth hanging 1 cm
     above it, lit from the front (no shadow there), is darker with it than without, and open
     ground 40 cm away keeps its brightness;
   - soft shadows (render.soft_shadows, render.key_angle): across the edge of the shadow a
     cloth 0.6 m up casts on the ground, more pixels lie between lit and shadowed with an 8°
     light than with the fixed filter, and the shadow and the open ground away from the edge
     are the same in both;
   - the highlights' roll-off (render.tone_map): a white cloth under a key light twice full
     white clips to 255 without it, and stays below 255, brighter where the light falls more
     squarely, with it;
   - sky light (render.sky_light): with no key or fill light, under a blue sky over red ground,
     a white cloth's face turned up is bluer than one turned down by more than 30 levels of
     red - blue; with the flat ambient they differ by at most 4;
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

/* Pixels between the shadow's level and the open ground's, by more than 10 % of the step, along
   the image row through (x0 .. x1, 0, z) on the ground. */
static int penumbra_pixels(cvk_context* ctx, const cvk_render_desc* r, double* dark, double* lit)
{
    static uint8_t im[W * H * 4];
    setup s = {0};
    s.cloths[0] = square_cloth((const float[3]){-0.5f, 0.6f, -0.5f}, flat_u, (const float[3]){0, 0, 1}, grey);
    double a[2], b[2];
    setup_scene(&s, ctx, 1, r);
    project(s.renderer, (const float[3]){-0.9f, 0.0f, 0.2f}, a);
    project(s.renderer, (const float[3]){-0.1f, 0.0f, 0.2f}, b);
    cvk_image got = cvk_renderer_get_image(s.renderer);
    for (int y = 0; y < H; y++)
        memcpy(im + (size_t)y * W * 4, pixel(&got, 0, y), (size_t)W * 4);
    teardown(&s);
    cvk_image c = {im, W, H, 4 * W};
    keep(&c, r->soft_shadows ? "penumbra-soft" : "penumbra-fixed");
    int y = (int)a[1], x0 = (int)a[0], x1 = (int)b[0];
    *lit = luminance(pixel(&c, x0, y));
    *dark = luminance(pixel(&c, x1, y));
    double step = *lit - *dark;
    int between = 0;
    for (int x = x0; x <= x1; x++) {
        double l = luminance(pixel(&c, x, y));
        between += l > *dark + 0.1 * step && l < *lit - 0.1 * step;
    }
    return between;
}
static void soft_shadows_widen(cvk_context* ctx)
{
    /* A 1 m cloth 0.6 m up, the key light from straight above (its shadow under it), seen from
       below the cloth's height: the shadow's left edge crosses the row at x = -0.5. */
    cvk_render_desc r = view((const float[3]){0.0f, 0.35f, 1.6f}, (const float[3]){-0.5f, 0.0f, 0.0f},
                             (const float[3]){0.0f, 1.0f, 0.05f});
    r.key_angle = 8.0f;
    double dark_soft, lit_soft, dark_fixed, lit_fixed;
    int soft = penumbra_pixels(ctx, &r, &dark_soft, &lit_soft);
    r.soft_shadows = false;
    int fixed = penumbra_pixels(ctx, &r, &dark_fixed, &lit_fixed);
    CHECK(soft >= fixed + 4, "%d pixels across the penumbra of an 8° light, %d with the fixed filter", soft, fixed);
    CHECK(fabs(dark_soft - dark_fixed) < 2.0 && fabs(lit_soft - lit_fixed) < 2.0,
          "shadow %.1f and open ground %.1f with soft shadows, %.1f and %.1f without", dark_soft, lit_soft,
          dark_fixed, lit_fixed);
    printf("penumbra: %d pixels with an 8° light, %d with the fixed filter (shadow %.1f, open ground %.1f)\n", soft,
           fixed, dark_soft, lit_soft);
}

static void highlights_roll_off(cvk_context* ctx)
{
    /* A white cloth facing the eye and the key light, the light twice full white. */
    cvk_render_desc r = view((const float[3]){0.0f, 1.0f, 2.0f}, (const float[3]){0.0f, 1.0f, 0.0f},
                             (const float[3]){0.3f, 0.3f, 1.0f});
    r.ground = false;
    r.key.color[0] = r.key.color[1] = r.key.color[2] = 2.0f;
    static uint8_t on[W * H * 4], off[W * H * 4];
    double centre[2];
    const float white[3] = {0.9f, 0.9f, 0.9f};
    setup s = {0};
    for (int pass = 0; pass < 2; pass++) {
        s.cloths[0] = square_cloth((const float[3]){-0.5f, 1.5f, 0.0f}, flat_u, (const float[3]){0, -1, 0}, white);
        r.tone_map = pass == 0;
        render_once(ctx, &s, 1, &r, pass == 0 ? on : off, (const float[3]){0.0f, 1.0f, 0.0f}, centre);
    }
    cvk_image a = {on, W, H, 4 * W}, b = {off, W, H, 4 * W};
    int x = (int)centre[0], y = (int)centre[1];
    double rolled = luminance(pixel(&a, x, y)), clipped = luminance(pixel(&b, x, y));
    CHECK(clipped > 254.0, "without the roll-off the overexposed cloth is %.1f, not clipped", clipped);
    CHECK(rolled < 254.0 && rolled > 200.0, "with the roll-off the overexposed cloth is %.1f", rolled);
    printf("a cloth lit at twice white: %.1f with the roll-off, %.1f clipped\n", rolled, clipped);
}

/* Red minus blue of the pixel at `p`'s projection. */
static int red_minus_blue(const cvk_image* im, const double at[2])
{
    const uint8_t* q = pixel(im, (int)at[0], (int)at[1]);
    return (int)q[0] - (int)q[2];
}

static void sky_light_tints(cvk_context* ctx)
{
    /* Two white cloths, one seen from above (its lit face up), one from below (down); no key or
       fill light: only the light from all around. Blue sky, red ground. */
    static uint8_t im[W * H * 4];
    int up[2], down[2];
    for (int pass = 0; pass < 2; pass++) {
        cvk_render_desc r = view((const float[3]){0.0f, 1.0f, 2.5f}, (const float[3]){0.0f, 1.0f, 0.0f},
                                 (const float[3]){0.3f, 1.0f, 0.3f});
        r.ground = false;
        memset(r.key.color, 0, sizeof r.key.color);
        memset(r.fill.color, 0, sizeof r.fill.color);
        r.ao = false;
        r.sky_light = pass == 0;
        const float sky[3] = {0.1f, 0.2f, 0.9f}, ground[3] = {0.9f, 0.3f, 0.1f};
        memcpy(r.background, sky, sizeof sky);
        memcpy(r.ground_color, ground, sizeof ground);
        const float white[3] = {0.9f, 0.9f, 0.9f};
        setup s = {0};
        /* Left: 0.3 m below the eye (seen from above); right: 0.3 m above it (from below). */
        s.cloths[0] = square_cloth((const float[3]){-1.1f, 0.7f, -0.5f}, flat_u, (const float[3]){0, 0, 1}, white);
        s.cloths[1] = square_cloth((const float[3]){0.1f, 1.3f, -0.5f}, flat_u, (const float[3]){0, 0, 1}, white);
        double a[2], b[2];
        setup_scene(&s, ctx, 2, &r);
        project(s.renderer, (const float[3]){-0.6f, 0.7f, 0.3f}, a);
        project(s.renderer, (const float[3]){0.6f, 1.3f, 0.3f}, b);
        cvk_image got = cvk_renderer_get_image(s.renderer);
        for (int y = 0; y < H; y++)
            memcpy(im + (size_t)y * W * 4, pixel(&got, 0, y), (size_t)W * 4);
        teardown(&s);
        cvk_image c = {im, W, H, 4 * W};
        keep(&c, pass == 0 ? "sky-light" : "flat-ambient");
        up[pass] = red_minus_blue(&c, a);
        down[pass] = red_minus_blue(&c, b);
    }
    CHECK(down[0] - up[0] > 30, "with sky light, red - blue is %d on the face up (blue sky) and %d on the face "
          "down (red ground)", up[0], down[0]);
    CHECK(abs(down[1] - up[1]) <= 4, "with the flat ambient, red - blue is %d up and %d down", up[1], down[1]);
    printf("red - blue: sky light %d up, %d down; flat ambient %d up, %d down\n", up[0], down[0], up[1], down[1]);
}

/* Every effect on: two renderers of one scene give the same bytes. */
static void same_bytes(cvk_context* ctx)
{
    cvk_render_desc r = view((const float[3]){0.8f, 0.9f, 1.4f}, (const float[3]){0.0f, 0.2f, 0.0f},
                             (const float[3]){0.4f, 1.0f, 0.3f});
    static uint8_t first[W * H * 4], second[W * H * 4];
    double unused[2];
    setup s = {0};
    for (int pass = 0; pass < 2; pass++) {
        s.cloths[0] = square_cloth((const float[3]){-0.5f, 0.3f, -0.5f}, flat_u, (const float[3]){0, 0, 1}, grey);
        s.cloths[1] = square_cloth((const float[3]){-0.3f, 0.6f, 0.0f}, flat_u, (const float[3]){0, -1, 0}, grey);
        render_once(ctx, &s, 2, &r, pass == 0 ? first : second, NULL, unused);
    }
    CHECK(memcmp(first, second, sizeof first) == 0, "two renderers of one scene differ with every effect on");
}

int main(void)
{
    cvk_context* ctx = harness_context();
    occlusion_at_foot(ctx);
    soft_shadows_widen(ctx);
    highlights_roll_off(ctx);
    sky_light_tints(ctx);
    same_bytes(ctx);
    return harness_finish(ctx);
}
