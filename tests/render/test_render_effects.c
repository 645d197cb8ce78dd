/* The renderer's effects, each checked by what the image must show with it on and off:
   - ambient occlusion (render.ao): the ground at the foot of an upright cloth hanging 1 cm
     above it, lit from the front (no shadow there), is darker with it than without, and open
     ground 40 cm away keeps its brightness; on a cloth folded into creases the darkening is
     smooth, not speckled (its mean |Laplacian| under half its mean);
   - soft shadows (render.soft_shadows, render.key_angle): across the edge of the shadow a
     cloth 0.6 m up casts on the ground, more pixels lie between lit and shadowed with an 8°
     light than with the fixed filter, and the shadow and the open ground away from the edge
     are the same in both;
   - the highlights' roll-off (render.tone_map): a white cloth under a key light 1.6 times full
     white clips to 255 without it and stays below 253 with it;
   - sky light (render.sky_light): with no key or fill light, under a blue sky over red ground,
     a white cloth's face turned up is bluer than one turned down by more than 30 levels of
     red - blue; with the flat ambient they differ by at most 4;
   - the same bytes from two renderers of one scene with every effect on;
   - fabric: a cloth lit from the front and seen from behind shows 35 to 75 % of its lit face's
     luminance (the light through it), a back_color shows on the back face only (with flat and
     with curved triangles), and sheen adds
     a rim at grazing angles (more than 15 levels) and less than half that head-on;
   - a texture of 1-texel stripes far finer than the pixels: the mean over a region moves by
     less than 2 levels when the camera moves by a third of a pixel, and the region is an even
     grey (its pixels within 8 levels, standard deviation), not stripes or moiré;
   - lighting at the vertices (render.vertex_lighting): a 96 x 96 cloth a pixel a triangle,
     half in a smaller cloth's shadow, is drawn otherwise than when lit at every pixel, but
     within 1.5 levels of luminance on average over the cloth, and its shadow as dark; a 16 x 16
     cloth whose triangles span some 15 pixels keeps the same bytes (lit at every pixel);
   - curved triangles (render.smooth): the top outline of an arch of 6 flat strips lies less than
     half as far from the true circle with them as without, and the inside of a trough of 6
     strips lit from above is as bright with them as without (within 10 %). */
#include "render_fixture.h"

#include <unistd.h>

enum { W = 200, H = 150 };

/* ---- scenes: static cloths ---- */

static cvk_render_desc view(const float eye[3], const float target[3], const float key[3])
{
    return grounded_view(W, H, eye, target, key);
}

/* ---- pixels ---- */

static void project(const cvk_renderer* r, const float p[3], double out[2])
{
    cvk_render_view v = cvk_renderer_get_view(r);
    project_point(&v, (const double[3]){p[0], p[1], p[2]}, W, H, out);
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
    /* A white cloth facing the eye and the key light, the light 1.6 times full white. */
    cvk_render_desc r = view((const float[3]){0.0f, 1.0f, 2.0f}, (const float[3]){0.0f, 1.0f, 0.0f},
                             (const float[3]){0.3f, 0.3f, 1.0f});
    r.ground = false;
    r.key.color[0] = r.key.color[1] = r.key.color[2] = 1.6f;
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
    CHECK(rolled < 253.0 && rolled > 200.0, "with the roll-off the overexposed cloth is %.1f", rolled);
    printf("a cloth lit at 1.6 times white: %.1f with the roll-off, %.1f clipped\n", rolled, clipped);
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

/* A horizontal cloth of n x n particles, 1 m, at 0.3 m under a 0.5 m square 0.3 m above its
   middle, lit from above, drawn with render.vertex_lighting `pixels`, into `out`; `lit` and
   `shade` get the projections of a point of the lower cloth in the light and one in the shadow,
   `outline` those of the lower cloth's corners, in order around it. */
static void shaded_cloth(cvk_context* ctx, uint32_t n, float pixels, uint8_t* out, double lit[2],
                         double shade[2], double outline[4][2])
{
    cvk_render_desc r = view((const float[3]){0.0f, 2.2f, 1.2f}, (const float[3]){0.0f, 0.3f, 0.0f},
                             (const float[3]){0.0f, 1.0f, 0.15f});
    r.vertex_lighting = pixels;
    setup s = {0};
    s.cloths[0] = square_cloth((const float[3]){-0.5f, 0.3f, -0.5f}, flat_u, (const float[3]){0, 0, 1}, grey);
    s.cloths[0].grid[0] = s.cloths[0].grid[1] = n;
    s.cloths[1] = square_cloth((const float[3]){-0.25f, 0.6f, -0.25f}, flat_u, (const float[3]){0, 0, 1}, grey);
    s.cloths[1].size[0] = s.cloths[1].size[1] = 0.5f;
    s.cloths[1].size[0] = 0.4f;
    render_once(ctx, &s, 2, &r, out, (const float[3]){0.4f, 0.3f, 0.4f}, lit);
    setup_scene(&s, ctx, 2, &r);
    project(s.renderer, (const float[3]){0.0f, 0.3f, 0.15f}, shade);
    for (int k = 0; k < 4; k++) {
        const float corner[3] = {(k == 1 || k == 2) ? 0.5f : -0.5f, 0.3f, k < 2 ? -0.5f : 0.5f};
        project(s.renderer, corner, outline[k]);
    }
    teardown(&s);
}

/* Whether the pixel (x, y)'s centre lies inside the convex quadrilateral `q` (either winding). */
static bool inside_quad(const double q[4][2], int x, int y)
{
    int positive = 0, negative = 0;
    for (int k = 0; k < 4; k++) {
        const double* a = q[k];
        const double* b = q[(k + 1) % 4];
        double cross = (b[0] - a[0]) * (y + 0.5 - a[1]) - (b[1] - a[1]) * (x + 0.5 - a[0]);
        positive += cross > 0.0;
        negative += cross < 0.0;
    }
    return positive == 0 || negative == 0;
}

static void vertex_lighting(cvk_context* ctx)
{
    static uint8_t vertex[W * H * 4], pixel_lit[W * H * 4];
    double lit[2], shade[2], outline[4][2];
    shaded_cloth(ctx, 96, 12.0f, vertex, lit, shade, outline);
    shaded_cloth(ctx, 96, 0.0f, pixel_lit, lit, shade, outline);
    cvk_image a = {vertex, W, H, 4 * W}, b = {pixel_lit, W, H, 4 * W};
    keep(&a, "vertex-lit");
    keep(&b, "pixel-lit");
    double sum = 0.0;
    int count = 0, cloth = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const uint8_t *p = pixel(&a, x, y), *q = pixel(&b, x, y);
            cloth += inside_quad((const double(*)[2])outline, x, y);
            if (abs(p[0] - q[0]) + abs(p[1] - q[1]) + abs(p[2] - q[2]) == 0)
                continue;
            sum += fabs(luminance(p) - luminance(q));
            count++;
        }
    double lit_a = region_luminance(&a, (int)lit[0] - 2, (int)lit[1] - 2, (int)lit[0] + 3, (int)lit[1] + 3);
    double shade_a = region_luminance(&a, (int)shade[0] - 2, (int)shade[1] - 2, (int)shade[0] + 3, (int)shade[1] + 3);
    double shade_b = region_luminance(&b, (int)shade[0] - 2, (int)shade[1] - 2, (int)shade[0] + 3, (int)shade[1] + 3);
    printf("96 x 96 cloth lit at its vertices: %d pixels differ from lighting at every pixel, by "
           "%.2f levels on average, %.2f over the cloth's %d pixels; shadow %.1f (%.1f per pixel), "
           "light %.1f\n", count, count ? sum / count : 0.0, sum / cloth, cloth, shade_a, shade_b,
           lit_a);
    CHECK(count > 100, "lighting at the vertices changed %d pixels of a fine cloth: not used", count);
    /* On average over the whole cloth, not only the pixels that changed: every change (wherever
       it is) over the pixels inside the lower cloth's projected outline (about a third of the
       image; the upper cloth, lit the same way, covers part of it). */
    CHECK(sum / cloth < 1.5, "lighting at the vertices is off by %.2f levels on average over the "
          "cloth's %d pixels", sum / cloth, cloth);
    CHECK(shade_a < 0.8 * lit_a && fabs(shade_a - shade_b) < 3.0,
          "the shadow on the cloth is %.1f lit at the vertices, %.1f at every pixel, in the light %.1f", shade_a,
          shade_b, lit_a);
    shaded_cloth(ctx, 16, 12.0f, vertex, lit, shade, outline);
    shaded_cloth(ctx, 16, 0.0f, pixel_lit, lit, shade, outline);
    CHECK(memcmp(vertex, pixel_lit, sizeof vertex) == 0, "a 16 x 16 cloth (triangles of some 15 pixels) was lit at "
          "its vertices");
}

/* Luminance of a 5 x 5 patch at the projection of the point (0, 1, 0): the middle of a wall. */
static double wall_middle(cvk_context* ctx, const float eye[3], const float key[3], const float back[3],
                          const float color[3], float sheen)
{
    cvk_render_desc r = view(eye, (const float[3]){0.0f, 1.0f, 0.0f}, key);
    r.ground = false;
    memset(r.fill.color, 0, sizeof r.fill.color);
    static uint8_t im[W * H * 4];
    double at[2];
    setup s = {0};
    /* A wall in the plane z = 0, its front face (u x v) towards -z. */
    s.cloths[0] = square_cloth((const float[3]){-0.5f, 1.5f, 0.0f}, flat_u, (const float[3]){0, -1, 0}, color);
    if (back)
        memcpy(s.cloths[0].back_color, back, sizeof s.cloths[0].back_color);
    s.cloths[0].sheen = sheen;
    render_once(ctx, &s, 1, &r, im, (const float[3]){0.0f, 1.0f, 0.0f}, at);
    cvk_image c = {im, W, H, 4 * W};
    return region_luminance(&c, (int)at[0] - 2, (int)at[1] - 2, (int)at[0] + 3, (int)at[1] + 3);
}

static void fabric(cvk_context* ctx)
{
    const float front_eye[3] = {0.3f, 1.2f, -2.5f}, back_eye[3] = {0.3f, 1.2f, 2.5f};
    const float from_front[3] = {0.2f, 0.3f, -1.0f};
    const float red[3] = {0.8f, 0.1f, 0.08f}, blue[3] = {0.05f, 0.1f, 0.8f};
    /* Lit from the front, seen from behind: the light through the cloth, not near black. */
    double lit = wall_middle(ctx, front_eye, from_front, NULL, grey, 0.0f);
    double through = wall_middle(ctx, back_eye, from_front, NULL, grey, 0.0f);
    CHECK(through > 0.35 * lit && through < 0.75 * lit, "a cloth lit from the front and seen from behind has "
          "luminance %.1f, its lit face %.1f", through, lit);
    /* A back colour: seen from behind, blue; from the front, still red. */
    cvk_render_desc r = view(back_eye, (const float[3]){0.0f, 1.0f, 0.0f}, from_front);
    r.ground = false;
    static uint8_t im[W * H * 4];
    double at[2];
    setup s = {0};
    for (int side = 0; side < 4; side++) {
        /* Flat, then curved triangles (their pieces must keep the triangles' faces). */
        r.smooth = side < 2 ? 0 : 3;
        memcpy(r.eye, side % 2 == 0 ? front_eye : back_eye, sizeof r.eye);
        s.cloths[0] = square_cloth((const float[3]){-0.5f, 1.5f, 0.0f}, flat_u, (const float[3]){0, -1, 0}, red);
        memcpy(s.cloths[0].back_color, blue, sizeof blue);
        render_once(ctx, &s, 1, &r, im, (const float[3]){0.0f, 1.0f, 0.0f}, at);
        const uint8_t* q = im + 4 * ((size_t)(int)at[1] * W + (size_t)(int)at[0]);
        if (side % 2 == 0)
            CHECK(q[0] > 2 * q[2], "the front of a red cloth with a blue back shows (%u, %u, %u), render.smooth %u",
                  q[0], q[1], q[2], r.smooth);
        else
            CHECK(q[2] > 2 * q[0], "the back of a red cloth with a blue back shows (%u, %u, %u), render.smooth %u",
                  q[0], q[1], q[2], r.smooth);
    }
    /* Sheen: a rim of light at grazing angles, seen and lit nearly edge-on from the same side
       (both about 75° off the normal), little change head-on. */
    const float grazing_eye[3] = {2.6f, 1.0f, -0.7f}, grazing_key[3] = {1.0f, 0.3f, -0.3f};
    double dull = wall_middle(ctx, grazing_eye, grazing_key, NULL, grey, 0.0f);
    double shiny = wall_middle(ctx, grazing_eye, grazing_key, NULL, grey, 1.0f);
    double dull_ahead = wall_middle(ctx, front_eye, from_front, NULL, grey, 0.0f);
    double shiny_ahead = wall_middle(ctx, front_eye, from_front, NULL, grey, 1.0f);
    CHECK(shiny > dull + 15.0, "at grazing angles a cloth with sheen 1 has luminance %.1f, with none %.1f", shiny,
          dull);
    CHECK(shiny_ahead - dull_ahead < 0.5 * (shiny - dull), "head-on, sheen adds %.1f; at grazing angles %.1f",
          shiny_ahead - dull_ahead, shiny - dull);
    printf("fabric: seen from behind %.1f, lit face %.1f; sheen at grazing angles %.1f against %.1f, head-on %.1f "
           "against %.1f\n", through, lit, shiny, dull, shiny_ahead, dull_ahead);
}

/* A striped texture (1-texel black and white stripes, repeated 16 times across a 1 m cloth) seen
   from 3 m, far too fine for the pixels: the mean over a region stays put when the camera moves
   by a third of a pixel (the mip levels average the stripes instead of sampling them). */
static void stripes_settle(cvk_context* ctx)
{
    enum { T = 64 };
    static uint8_t texels[T * T * 4];
    for (int y = 0; y < T; y++)
        for (int x = 0; x < T; x++) {
            uint8_t v = (x & 1) ? 240 : 15;
            uint8_t* p = &texels[4 * (y * T + x)];
            p[0] = p[1] = p[2] = v;
            p[3] = 255;
        }
    char dir[] = "/tmp/clothvk-stripes-XXXXXX";
    CHECK(mkdtemp(dir) != NULL, "mkdtemp failed");
    char path[64];
    snprintf(path, sizeof path, "%s/stripes.png", dir);
    cvk_image tex = {texels, T, T, 4 * T};
    cvk_error err;
    REQUIRE_OK(cvk_image_write_png(&tex, path, &err), err);
    static uint8_t im[2][W * H * 4];
    double at[2];
    double means[2], spread[2];
    for (int pass = 0; pass < 2; pass++) {
        /* The second eye 1 mm to the right: about a third of a pixel at the cloth. */
        cvk_render_desc r = view((const float[3]){pass * 0.001f, 1.0f, 3.0f}, (const float[3]){pass * 0.001f, 1.0f, 0.0f},
                                 (const float[3]){0.2f, 0.5f, 1.0f});
        r.ground = false;
        r.ao = false;
        setup s = {0};
        s.cloths[0] = square_cloth((const float[3]){-0.5f, 1.5f, 0.0f}, flat_u, (const float[3]){0, -1, 0}, grey);
        s.cloths[0].texture = path;
        s.cloths[0].texture_scale[0] = s.cloths[0].texture_scale[1] = 16.0f;
        s.cloths[0].grid[0] = s.cloths[0].grid[1] = 8;
        render_once(ctx, &s, 1, &r, im[pass], (const float[3]){0.0f, 1.0f, 0.0f}, at);
        cvk_image c = {im[pass], W, H, 4 * W};
        int x = (int)at[0], y = (int)at[1];
        means[pass] = region_luminance(&c, x - 10, y - 10, x + 10, y + 10);
        double sq = 0.0;
        for (int yy = y - 10; yy < y + 10; yy++)
            for (int xx = x - 10; xx < x + 10; xx++) {
                double d = luminance(pixel(&c, xx, yy)) - means[pass];
                sq += d * d;
            }
        spread[pass] = sqrt(sq / 400.0);
    }
    remove(path);
    rmdir(dir);
    CHECK(fabs(means[0] - means[1]) < 2.0, "the striped cloth's mean moves from %.1f to %.1f with the camera",
          means[0], means[1]);
    CHECK(spread[0] < 8.0 && spread[1] < 8.0, "the striped cloth's pixels spread by %.1f and %.1f (no even grey)",
          spread[0], spread[1]);
    printf("stripes: mean %.1f and %.1f, spread %.1f and %.1f\n", means[0], means[1], spread[0], spread[1]);
}

/* Draws a coarse half-cylinder of 6 flat strips (radius 0.5 m, axis along z through
   (0, 1, 0)) with `r` into s: an arch with `up` 1, a trough with -1. */
static void draw_half_cylinder(cvk_context* ctx, setup* s, const cvk_render_desc* r, double up,
                               const float color[3])
{
    enum { NU = 7, NV = 2 };
    const double radius = 0.5, pi = 3.14159265358979;
    s->cloths[0] = square_cloth((const float[3]){-0.5f, 1.0f, -0.5f}, flat_u, (const float[3]){0, 0, 1},
                                color);
    s->cloths[0].grid[0] = NU;
    s->cloths[0].grid[1] = NV;
    setup_scene(s, ctx, 1, r);
    float xyz[NU * NV * 3], v[NU * NV * 3] = {0};
    for (int j = 0; j < NV; j++)
        for (int i = 0; i < NU; i++) {
            double a = pi * i / (NU - 1);
            float* q = &xyz[3 * (j * NU + i)];
            q[0] = (float)(radius * cos(a));
            q[1] = (float)(1.0 + up * radius * sin(a));
            q[2] = (float)(-0.5 + j);
        }
    cvk_error err;
    REQUIRE_OK(cvk_sim_write_state(s->sim, xyz, v, NU * NV, &err), err);
    REQUIRE_OK(cvk_renderer_draw(s->renderer, &err), err);
}

/* The view of the half-cylinder tests: no ground, no occlusion, render.smooth `smooth`. */
static cvk_render_desc cylinder_view(const float eye[3], const float target[3], const float key[3], float fov_y,
                                     uint32_t smooth)
{
    cvk_render_desc r = view(eye, target, key);
    r.fov_y = fov_y;
    r.ground = false;
    r.ao = false;
    r.smooth = smooth;
    return r;
}

/* Mean distance in pixels between the top outline of a coarse half-cylinder (an arch of 6 flat
   strips, radius 0.5 m, seen along its axis) and the true circle's, drawn with render.smooth
   `smooth`. */
static double arch_outline_error(cvk_context* ctx, uint32_t smooth)
{
    const double radius = 0.5, pi = 3.14159265358979;
    cvk_render_desc r = cylinder_view((const float[3]){0.0f, 1.25f, 8.0f}, (const float[3]){0.0f, 1.25f, 0.0f},
                                      (const float[3]){0.2f, 1.0f, 0.6f}, 9.0f, smooth);
    setup s = {0};
    draw_half_cylinder(ctx, &s, &r, 1.0, (const float[3]){0.8f, 0.1f, 0.08f});
    cvk_image im = cvk_renderer_get_image(s.renderer);
    keep(&im, smooth > 1 ? "arch-smooth" : "arch-flat");
    /* The true outline: the front rim (z = 0.5, nearest the eye) projected, row per column. */
    double top[W];
    for (int x = 0; x < W; x++)
        top[x] = 1e9;
    for (int k = 0; k <= 4000; k++) {
        double a = pi * k / 4000.0, at[2];
        project(s.renderer, (const float[3]){(float)(radius * cos(a)), (float)(1.0 + radius * sin(a)), 0.5f}, at);
        int x = (int)floor(at[0]);
        if (x >= 0 && x < W)
            top[x] = fmin(top[x], at[1]);
    }
    const uint8_t* sky = pixel(&im, 0, 0);
    double sum = 0.0;
    int columns = 0;
    double left[2], right[2];
    project(s.renderer, (const float[3]){-0.4f, 1.0f, 0.5f}, left);
    project(s.renderer, (const float[3]){0.4f, 1.0f, 0.5f}, right);
    for (int x = (int)left[0]; x <= (int)right[0]; x++) {
        int y = 0;
        while (y < H && abs(pixel(&im, x, y)[0] - sky[0]) + abs(pixel(&im, x, y)[1] - sky[1]) +
                                abs(pixel(&im, x, y)[2] - sky[2]) < 40)
            y++;
        sum += fabs(y - top[x]);
        columns++;
    }
    teardown(&s);
    return sum / columns;
}

static void curved_triangles(cvk_context* ctx)
{
    double flat = arch_outline_error(ctx, 0), curved = arch_outline_error(ctx, 4);
    CHECK(curved < 0.5 * flat, "the arch's outline is %.2f px from the circle with curved triangles, %.2f flat",
          curved, flat);
    printf("arch outline off the circle: %.2f px with curved triangles, %.2f px flat\n", curved, flat);
}

/* The mean luminance over the inside of a coarse trough (the arch upside down: 6 flat strips,
   radius 0.5 m) lit from above and seen from above, drawn with render.smooth `smooth`. The
   curved surface sags below the flat strips the shadow pass draws. */
static double trough_light(cvk_context* ctx, uint32_t smooth)
{
    const double radius = 0.5, pi = 3.14159265358979;
    cvk_render_desc r = cylinder_view((const float[3]){0.0f, 4.0f, 2.5f}, (const float[3]){0.0f, 0.6f, 0.0f},
                                      (const float[3]){0.1f, 1.0f, 0.2f}, 18.0f, smooth);
    setup s = {0};
    draw_half_cylinder(ctx, &s, &r, -1.0, (const float[3]){0.7f, 0.7f, 0.7f});
    cvk_image im = cvk_renderer_get_image(s.renderer);
    keep(&im, smooth > 1 ? "trough-smooth" : "trough-flat");
    double sum = 0.0;
    int count = 0;
    for (int k = -4; k <= 4; k++)
        for (int m = -3; m <= 3; m++) {
            double a = pi * (0.5 + 0.08 * k), at[2];
            project(s.renderer, (const float[3]){(float)(radius * cos(a)), (float)(1.0 - radius * sin(a)),
                                                 (float)(0.1 * m)}, at);
            const uint8_t* q = pixel(&im, (int)at[0], (int)at[1]);
            sum += 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
            count++;
        }
    teardown(&s);
    return sum / count;
}

/* A 1 m cloth of 48 x 48 particles folded into ridges and creases (8 cm deep, 4 a metre,
   crossed by a wave of 3 cm), seen from above and lit from above, with ambient
   occlusion `ao` or without, into `out` (W x H x 4 bytes); `lo` and `hi` get the corners of its
   middle in the image. */
static void draw_folds(cvk_context* ctx, bool ao, uint8_t* out, double lo[2], double hi[2])
{
    enum { N = 48 };
    const double pi = 3.14159265358979;
    cvk_render_desc r = view((const float[3]){0.0f, 1.6f, 1.0f}, (const float[3]){0.0f, 0.3f, 0.0f},
                             (const float[3]){0.1f, 1.0f, 0.2f});
    r.ground = false;
    r.ao = ao;
    r.ao_radius = 0.1f;
    setup s = {0};
    s.cloths[0] = square_cloth((const float[3]){-0.5f, 0.3f, -0.5f}, flat_u, (const float[3]){0, 0, 1}, grey);
    s.cloths[0].grid[0] = s.cloths[0].grid[1] = N;
    setup_scene(&s, ctx, 1, &r);
    static float xyz[N * N * 3], v[N * N * 3];
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            double u = (double)i / (N - 1), w = (double)j / (N - 1);
            float* q = &xyz[3 * (j * N + i)];
            q[0] = (float)(u - 0.5);
            q[1] = (float)(0.3 + 0.08 * fabs(sin(4.0 * pi * u)) + 0.03 * sin(2.0 * pi * (u + 2.0 * w)));
            q[2] = (float)(w - 0.5);
        }
    cvk_error err;
    REQUIRE_OK(cvk_sim_write_state(s.sim, xyz, v, N * N, &err), err);
    REQUIRE_OK(cvk_renderer_draw(s.renderer, &err), err);
    cvk_image im = cvk_renderer_get_image(s.renderer);
    keep(&im, ao ? "folds-occlusion" : "folds-plain");
    for (int y = 0; y < H; y++)
        memcpy(out + (size_t)y * W * 4, pixel(&im, 0, y), (size_t)W * 4);
    project(s.renderer, (const float[3]){-0.3f, 0.3f, -0.3f}, lo);
    project(s.renderer, (const float[3]){0.3f, 0.3f, 0.3f}, hi);
    teardown(&s);
}

/* The ambient occlusion darkens a folded cloth's creases smoothly: over the cloth's middle, the
   darkening it adds (luminance without it less with it) varies from pixel to pixel by less than
   half its own size (mean |Laplacian| of the darkening over its mean: 0.42, much of it the 8-bit
   steps); without the blur (ao_blur.frag) its few taps and turned pattern speckle the creases
   (0.57). */
static void occlusion_smooth(cvk_context* ctx)
{
    static uint8_t plain[W * H * 4], occluded[W * H * 4];
    double lo[2], hi[2];
    draw_folds(ctx, false, plain, lo, hi);
    draw_folds(ctx, true, occluded, lo, hi);
    cvk_image a = {plain, W, H, 4 * W}, b = {occluded, W, H, 4 * W};
    double darkening = 0.0, laplacian = 0.0;
    int count = 0;
    for (int y = (int)fmin(lo[1], hi[1]); y <= (int)fmax(lo[1], hi[1]); y++)
        for (int x = (int)fmin(lo[0], hi[0]); x <= (int)fmax(lo[0], hi[0]); x++) {
            double d[5];
            const int dx[5] = {0, 1, -1, 0, 0}, dy[5] = {0, 0, 0, 1, -1};
            for (int k = 0; k < 5; k++)
                d[k] = luminance(pixel(&a, x + dx[k], y + dy[k])) - luminance(pixel(&b, x + dx[k], y + dy[k]));
            darkening += fabs(d[0]);
            laplacian += fabs(4.0 * d[0] - d[1] - d[2] - d[3] - d[4]);
            count++;
        }
    CHECK(count > 2000 && darkening / count > 1.0, "the folds' middle is %d pixels darkened by %.2f: no test",
          count, count ? darkening / count : 0.0);
    double roughness = darkening > 0.0 ? laplacian / darkening : 0.0;
    printf("folded cloth: ambient occlusion darkens its middle by %.2f levels, its mean |Laplacian| %.2f of that\n",
           darkening / count, roughness);
    CHECK(roughness < 0.5, "ambient occlusion mottles a folded cloth: the darkening's mean |Laplacian| is %.2f "
          "of its mean", roughness);
}

/* Curved triangles look their shadow up where the shadow pass drew the flat ones: the curved
   trough is lit as the flat one is (before, the sagging surface fell into its own strips'
   shadow: dark blotches on crumpled cloth). */
static void curved_shadow_lookup(cvk_context* ctx)
{
    double flat = trough_light(ctx, 0), curved = trough_light(ctx, 4);
    printf("trough lit from above: mean luminance %.1f flat, %.1f with curved triangles\n", flat, curved);
    CHECK(flat > 60.0, "the flat trough is dark (%.1f): no test", flat);
    CHECK(fabs(curved - flat) < 0.1 * flat, "the curved trough's light %.1f is not the flat one's %.1f",
          curved, flat);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    occlusion_at_foot(ctx);
    occlusion_smooth(ctx);
    soft_shadows_widen(ctx);
    highlights_roll_off(ctx);
    sky_light_tints(ctx);
    same_bytes(ctx);
    fabric(ctx);
    stripes_settle(ctx);
    vertex_lighting(ctx);
    curved_triangles(ctx);
    curved_shadow_lookup(ctx);
    return harness_finish(ctx);
}
