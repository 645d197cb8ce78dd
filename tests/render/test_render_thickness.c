/* A cloth's material thickness t, checked by what the image must show:
   - the rim: a flat red 1 m square cloth (green back_color) seen edge-on, the eye in its plane,
     covers no pixel rows across its near border without thickness; with t = 3 cm it covers as
     many rows as the projection of the border's ±t/2 spans (within 1.5 rows), the row through
     the cloth's plane included (only the rim covers it), and that rim shows the front's red,
     lit when the key light faces it and darker when the light comes from behind;
   - the faces' offset: a thin blue cloth 0.3 t above the red one's middle plane (inside the
     slab) hides it from above without thickness and is hidden by it with t; seen from below,
     a blue cloth 0.3 t under the middle plane is hidden by the slab's back face, which shows
     the back_color (green);
   - thickness 0 draws the same bytes as a slab far thinner than a pixel (0.01 mm), and other
     bytes than a 1 mm one. */
#include "render_fixture.h"

enum { W = 160, H = 160 };

static const float red[3] = {0.8f, 0.1f, 0.08f}, green[3] = {0.1f, 0.7f, 0.1f}, blue[3] = {0.05f, 0.1f, 0.8f};
static const float along_x[3] = {1, 0, 0}, along_z[3] = {0, 0, 1};
static uint8_t image[W * H * 4];

/* The red cloth: 1 m square in the plane y = 1 centred on the y axis, u × v = x × z = −y, so its
   front faces down; back_color green. */
static cvk_cloth_desc slab_cloth(float thickness)
{
    cvk_cloth_desc c = square_cloth((const float[3]){-0.5f, 1.0f, -0.5f}, along_x, along_z, red);
    memcpy(c.back_color, green, sizeof c.back_color);
    c.thickness = thickness;
    return c;
}

/* Draws s's cloths with `render` into `image` and projects `point` (pixels) into `at`. */
static void draw(cvk_context* ctx, setup* s, uint32_t cloth_count, const cvk_render_desc* render,
                 const double point[3], double at[2])
{
    setup_scene(s, ctx, cloth_count, render);
    cvk_image im = cvk_renderer_get_image(s->renderer);
    for (int y = 0; y < H; y++)
        memcpy(image + (size_t)y * W * 4, pixel(&im, 0, y), (size_t)W * 4);
    if (point) {
        cvk_render_view v = cvk_renderer_get_view(s->renderer);
        project_point(&v, point, W, H, at);
    }
    teardown(s);
}

static const uint8_t* at_pixel(int x, int y)
{
    cvk_image im = {image, W, H, 4 * W};
    return pixel(&im, x, y);
}

/* Red well above green and blue: the front of the red cloth (the sky is bluish grey). */
static bool is_red(const uint8_t* p)
{
    return p[0] > p[1] + 20 && p[0] > p[2] + 20;
}

/* The edge-on view: the eye at the cloth's height, 2 m in front of its near border (z = 0.5). */
static cvk_render_desc edge_on(const float key[3])
{
    cvk_render_desc r = fixture_view(W, H, (const float[3]){0.0f, 1.0f, 2.5f}, (const float[3]){0.0f, 1.0f, 0.0f}, key);
    r.ground = false;
    return r;
}

static void rim(cvk_context* ctx)
{
    const float t = 0.03f;
    const float from_front[3] = {0.1f, 0.2f, 1.0f}, from_behind[3] = {0.1f, 0.2f, -1.0f};
    double near_top[2], near_bottom[2], centre[2];
    int rows[2] = {0, 0};
    double lit = 0.0, unlit = 0.0;
    bool middle = false, rim_red = true;
    for (int pass = 0; pass < 3; pass++) {
        /* 0: no thickness; 1: t, key from the front; 2: t, key from behind */
        setup s = {0};
        s.cloths[0] = slab_cloth(pass == 0 ? 0.0f : t);
        cvk_render_desc r = edge_on(pass == 2 ? from_behind : from_front);
        draw(ctx, &s, 1, &r, (const double[3]){0.0, 1.0, 0.5}, centre);
        if (pass == 0) {
            setup p = {0};
            p.cloths[0] = slab_cloth(0.0f);
            setup_scene(&p, ctx, 1, &r);
            cvk_render_view v = cvk_renderer_get_view(p.renderer);
            project_point(&v, (const double[3]){0.0, 1.0 + 0.5 * t, 0.5}, W, H, near_top);
            project_point(&v, (const double[3]){0.0, 1.0 - 0.5 * t, 0.5}, W, H, near_bottom);
            teardown(&p);
        }
        int x = (int)centre[0];
        if (pass < 2)
            for (int y = 0; y < H; y++)
                rows[pass] += is_red(at_pixel(x, y)) || at_pixel(x, y)[1] > at_pixel(x, y)[0] + 20;
        const uint8_t* c = at_pixel(x, (int)centre[1]);
        if (pass == 1) {
            middle = is_red(c);
            lit = luminance(c);
            for (int y = (int)(near_top[1] + 1.0); y < (int)near_bottom[1]; y++)
                rim_red = rim_red && is_red(at_pixel(x, y));
        }
        if (pass == 2)
            unlit = luminance(c);
    }
    double expected = fabs(near_bottom[1] - near_top[1]);
    CHECK(rows[0] <= 1, "a cloth seen edge-on covers %d rows without thickness", rows[0]);
    CHECK(fabs(rows[1] - expected) <= 1.5, "with %.0f mm it covers %d rows; its border's ±t/2 project %.1f rows "
          "apart", 1000.0 * t, rows[1], expected);
    CHECK(middle, "the row through the cloth's plane at its near border is not the rim's red");
    CHECK(rim_red, "the rim between the projections of ±t/2 is not all the front's red");
    CHECK(lit > 1.5 * unlit, "the rim lit from the front has luminance %.1f, from behind %.1f", lit, unlit);
    printf("rim: edge-on rows %d without thickness, %d with %.0f mm (projection %.1f); rim luminance %.1f lit, "
           "%.1f from behind\n", rows[0], rows[1], 1000.0 * t, expected, lit, unlit);
}

/* The blue cloth: a 0.6 m square centred on the y axis at height y. */
static cvk_cloth_desc blue_cloth(float y)
{
    cvk_cloth_desc c = square_cloth((const float[3]){-0.3f, y, -0.3f}, along_x, along_z, blue);
    c.grid[0] = c.grid[1] = 4;
    c.size[0] = c.size[1] = 0.6f;
    return c;
}

static void offset(cvk_context* ctx)
{
    const float t = 0.05f;
    /* From above (the back face, y = 1 + t/2) and from below (the front, y = 1 − t/2), a little
       off the vertical so the view has an up direction. */
    const float eyes[2][3] = {{0.0f, 3.0f, 0.3f}, {0.0f, -1.0f, 0.3f}};
    const uint8_t* p;
    for (int side = 0; side < 2; side++)
        for (int thick = 0; thick < 2; thick++) {
            setup s = {0};
            s.cloths[0] = slab_cloth(thick ? t : 0.0f);
            s.cloths[1] = blue_cloth(side == 0 ? 1.0f + 0.3f * t : 1.0f - 0.3f * t);
            cvk_render_desc r = fixture_view(W, H, eyes[side], (const float[3]){0.0f, 1.0f, 0.0f},
                                             (const float[3]){0.2f, side == 0 ? 1.0f : -1.0f, 0.3f});
            r.ground = false;
            double at[2];
            draw(ctx, &s, 2, &r, (const double[3]){0.0, 1.0, 0.0}, at);
            p = at_pixel((int)at[0], (int)at[1]);
            /* From above the red cloth shows its back (green); from below its front (red). */
            bool slab = side == 0 ? p[1] > p[0] + 20 && p[1] > p[2] + 20 : is_red(p);
            bool thin = p[2] > p[0] + 20 && p[2] > p[1] + 20;
            CHECK(thick ? slab : thin, "seen from %s, %s, the middle shows (%u, %u, %u): expected the %s",
                  side == 0 ? "above" : "below", thick ? "with 5 cm" : "without thickness", p[0], p[1], p[2],
                  thick ? (side == 0 ? "slab's back face (green)" : "slab's front face (red)")
                        : "blue cloth 0.3 t away");
        }
    printf("offset: a cloth 0.3 t from the middle plane shows without thickness, the slab's face with it, from "
           "above and below\n");
}

/* Thickness 0 is one surface drawn by the plain cloth pipeline (render_frame.c); any t > 0 a
   slab: both faces culled, set off ±t/2, and a rim. A cloth 2 m away in a 35° view is about 8 mm
   a pixel; a 0.01 mm slab (a thousandth of that) must draw the very bytes of thickness 0, which
   fails if 0 were drawn as a slab of some default thickness or if the one-surface and slab paths
   shaded a face differently. A 1 mm slab (an eighth of a pixel) must draw other bytes, so this
   view does resolve a thickness that small. (The default cloth's thickness is 0 too: setting
   the key to 0 could not differ from leaving it unset.) */
static void zero_same_bytes(cvk_context* ctx)
{
    static uint8_t zero[W * H * 4], tiny[W * H * 4];
    const float key[3] = {0.3f, 0.8f, 0.4f};
    const float thickness[3] = {0.0f, 1e-5f, 1e-3f};
    for (int pass = 0; pass < 3; pass++) {
        setup s = {0};
        s.cloths[0] = square_cloth((const float[3]){-0.5f, 1.0f, -0.5f}, along_x, along_z, red);
        s.cloths[0].thickness = thickness[pass];
        cvk_render_desc r = grounded_view(W, H, (const float[3]){0.8f, 2.0f, 1.5f},
                                          (const float[3]){0.0f, 1.0f, 0.0f}, key);
        draw(ctx, &s, 1, &r, NULL, NULL);
        if (pass < 2)
            memcpy(pass == 0 ? zero : tiny, image, sizeof zero);
    }
    CHECK(memcmp(zero, tiny, sizeof zero) == 0,
          "thickness 0 draws other bytes than a 0.01 mm slab");
    CHECK(memcmp(zero, image, sizeof zero) != 0, "a 1 mm slab draws the bytes of thickness 0: the "
          "view cannot tell thickness 0 from a thin slab");
}

int main(void)
{
    cvk_context* ctx = harness_context();
    rim(ctx);
    offset(ctx);
    zero_same_bytes(ctx);
    return harness_finish(ctx);
}
