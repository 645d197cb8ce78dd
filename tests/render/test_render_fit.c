/* render.fit and render.overlay, checked in the image:
   - fit: a cloth 1.5 m up and a sphere beside it below are both in the picture (red and green
     pixels), every pixel that is not the background lies inside the margin, and the projected
     points that are framed (the cloth's corners and the sphere's box's) lie inside it too,
     reaching it within 2 pixels on both sides along one axis (the picture is centred and as
     large as the margin allows); a wider margin gives a smaller picture;
   - an infinite plane collider changes nothing of the view; the view looks along the given
     eye − target; cvk_renderer_fit(NULL, NULL) frames what creation framed, a given box frames
     that box, and without render.fit the call is refused with its sentence;
   - render.fit "yes" in a scene file is refused with its one-line message;
   - overlay: the image with the frame and time differs from the one without only in the
     lower left corner (the bottom quarter's left three quarters), the same bytes twice, and another time gives other text. */
#include "render_fixture.h"

enum { W = 240, H = 180 };

static const float background[3] = {0.1f, 0.2f, 0.45f};
static const float red[3] = {0.8f, 0.1f, 0.08f};
static const float green[3] = {0.1f, 0.6f, 0.12f};

/* A 1 m cloth at height 1.5 m, flat, and a sphere of radius 0.3 m below and beside it. */
static void fill_scene(setup* s, bool plane)
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = c.grid[1] = 12;
    memcpy(c.origin, (const float[3]){-0.5f, 1.5f, -0.5f}, sizeof c.origin);
    memcpy(c.u_axis, (const float[3]){1, 0, 0}, sizeof c.u_axis);
    memcpy(c.v_axis, (const float[3]){0, 0, 1}, sizeof c.v_axis);
    memcpy(c.color, red, sizeof c.color);
    s->cloths[0] = c;
    cvk_collider_desc sp = cvk_default_collider_desc();
    sp.type = CVK_COLLIDER_SPHERE;
    memcpy(sp.center, (const float[3]){1.2f, 0.6f, 0.2f}, sizeof sp.center);
    sp.radius = 0.3f;
    memcpy(sp.color, green, sizeof sp.color);
    s->colliders[0] = sp;
    s->collider_count = 1;
    if (plane) {
        cvk_collider_desc p = cvk_default_collider_desc();
        p.type = CVK_COLLIDER_PLANE;
        memcpy(p.normal, (const float[3]){0, 1, 0}, sizeof p.normal);
        memcpy(p.point, (const float[3]){0, -3, 0}, sizeof p.point);
        s->colliders[1] = p;
        s->collider_count = 2;
    }
}

static cvk_render_desc fit_view(float margin)
{
    cvk_render_desc r = cvk_default_render_desc();
    r.size[0] = W;
    r.size[1] = H;
    r.ground = false;
    r.shadow_map_size = 512;
    memcpy(r.background, background, sizeof r.background);
    r.fit = true;
    r.fit_margin = margin;
    return r;
}

typedef struct extent {
    double lo[2], hi[2];
} extent;

/* Where the framed points land: the flat cloth's four corners (its particles' outline) and
   the corners of the sphere's box. */
static extent framed_corners(const cvk_render_view* v)
{
    const double lo[3] = {0.9, 0.3, -0.1}, hi[3] = {1.5, 0.9, 0.5};
    double points[12][3] = {{-0.5, 1.5, -0.5}, {0.5, 1.5, -0.5}, {-0.5, 1.5, 0.5}, {0.5, 1.5, 0.5}};
    for (int c = 0; c < 8; c++)
        for (int k = 0; k < 3; k++)
            points[4 + c][k] = c & (1 << k) ? hi[k] : lo[k];
    extent e = {{INFINITY, INFINITY}, {-INFINITY, -INFINITY}};
    for (int i = 0; i < 12; i++) {
        double q[2];
        project_point(v, points[i], W, H, q);
        for (int k = 0; k < 2; k++) {
            e.lo[k] = fmin(e.lo[k], q[k]);
            e.hi[k] = fmax(e.hi[k], q[k]);
        }
    }
    return e;
}

/* Where the corners of the box [lo, hi] land. */
static extent box_corners(const cvk_render_view* v, const float lo[3], const float hi[3])
{
    extent e = {{INFINITY, INFINITY}, {-INFINITY, -INFINITY}};
    for (int c = 0; c < 8; c++) {
        double point[3], q[2];
        for (int k = 0; k < 3; k++)
            point[k] = c & (1 << k) ? hi[k] : lo[k];
        project_point(v, point, W, H, q);
        for (int k = 0; k < 2; k++) {
            e.lo[k] = fmin(e.lo[k], q[k]);
            e.hi[k] = fmax(e.hi[k], q[k]);
        }
    }
    return e;
}

/* The framed points within the margin, reaching it within 2 pixels on both sides along one
   axis (centred, as large as the margin allows). */
static void check_framed(extent corners, float margin, const char* what)
{
    double mx = margin * W, my = margin * H;
    CHECK(corners.lo[0] >= mx - 0.5 && corners.hi[0] <= W - mx + 0.5 && corners.lo[1] >= my - 0.5 &&
              corners.hi[1] <= H - my + 0.5,
          "%s, margin %g: the framed corners span x %.1f..%.1f, y %.1f..%.1f, outside %.1f px from the edges",
          what, margin, corners.lo[0], corners.hi[0], corners.lo[1], corners.hi[1], mx);
    bool tight_x = fabs(corners.lo[0] - mx) < 2.0 && fabs(W - corners.hi[0] - mx) < 2.0;
    bool tight_y = fabs(corners.lo[1] - my) < 2.0 && fabs(H - corners.hi[1] - my) < 2.0;
    CHECK(tight_x || tight_y, "%s, margin %g: the framed corners (x %.1f..%.1f, y %.1f..%.1f) reach the "
          "margin on neither axis", what, margin, corners.lo[0], corners.hi[0], corners.lo[1], corners.hi[1]);
}

static bool is_background(const uint8_t* p)
{
    /* The background's sRGB bytes: 89, 124, 180. */
    static const int bg[3] = {89, 124, 180};
    for (int k = 0; k < 3; k++)
        if (abs((int)p[k] - bg[k]) > 3)
            return false;
    return true;
}

/* The pixels that are not the background, and how many are the cloth's red and the sphere's
   green. */
static extent drawn_pixels(const cvk_image* im, int* reds, int* greens)
{
    extent e = {{INFINITY, INFINITY}, {-INFINITY, -INFINITY}};
    *reds = *greens = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const uint8_t* p = pixel(im, x, y);
            if (is_background(p))
                continue;
            e.lo[0] = fmin(e.lo[0], x), e.hi[0] = fmax(e.hi[0], x + 1);
            e.lo[1] = fmin(e.lo[1], y), e.hi[1] = fmax(e.hi[1], y + 1);
            *reds += p[0] > p[1] + 40 && p[0] > p[2] + 40;
            *greens += p[1] > p[0] + 30 && p[1] > p[2] + 30;
        }
    return e;
}

static cvk_image draw(setup* s)
{
    cvk_error err;
    REQUIRE_OK(cvk_renderer_draw(s->renderer, &err), err);
    return cvk_renderer_get_image(s->renderer);
}

/* The margin of the picture's corners, and of its pixels; returns the corners' extent. */
static extent fitted(cvk_context* ctx, float margin)
{
    setup s = {0};
    fill_scene(&s, false);
    cvk_render_desc r = fit_view(margin);
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s);
    cvk_render_view v = cvk_renderer_get_view(s.renderer);
    extent corners = framed_corners(&v);
    double mx = margin * W, my = margin * H;
    check_framed(corners, margin, "the cloth and the sphere");
    int reds, greens;
    extent e = drawn_pixels(&im, &reds, &greens);
    CHECK(reds > 200 && greens > 100, "margin %g: %d red (cloth) and %d green (sphere) pixels", margin, reds, greens);
    CHECK(e.lo[0] >= floor(mx) && e.hi[0] <= ceil(W - mx) && e.lo[1] >= floor(my) && e.hi[1] <= ceil(H - my),
          "margin %g: drawn pixels span x %.0f..%.0f, y %.0f..%.0f of %d x %d", margin, e.lo[0], e.hi[0], e.lo[1],
          e.hi[1], W, H);
    CHECK(e.lo[0] >= corners.lo[0] - 1 && e.hi[0] <= corners.hi[0] + 1 && e.lo[1] >= corners.lo[1] - 1 &&
              e.hi[1] <= corners.hi[1] + 1,
          "margin %g: drawn pixels outside the framed corners' picture", margin);
    teardown(&s);
    return corners;
}

static void fit_frames_cloth_and_collider(cvk_context* ctx)
{
    extent near = fitted(ctx, 0.06f), far = fitted(ctx, 0.25f);
    CHECK(far.hi[0] - far.lo[0] < 0.8 * (near.hi[0] - near.lo[0]),
          "a margin of 0.25 draws %.1f px wide, 0.06 %.1f px", far.hi[0] - far.lo[0], near.hi[0] - near.lo[0]);
}

static cvk_render_view view_of(cvk_context* ctx, bool plane, const cvk_render_desc* r)
{
    setup s = {0};
    fill_scene(&s, plane);
    setup_scene(&s, ctx, 1, r);
    cvk_render_view v = cvk_renderer_get_view(s.renderer);
    teardown(&s);
    return v;
}

static double distance3(const float a[3], const float b[3])
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

static void fit_view_rules(cvk_context* ctx)
{
    cvk_render_desc r = fit_view(0.06f);
    cvk_render_view without = view_of(ctx, false, &r), with = view_of(ctx, true, &r);
    CHECK(distance3(without.eye, with.eye) < 1e-5 && distance3(without.target, with.target) < 1e-5,
          "an infinite plane moved the fitted eye by %g m", distance3(without.eye, with.eye));

    /* From the side given: eye − target's direction, whatever their distance. */
    r.auto_eye = r.auto_target = false;
    memcpy(r.eye, (const float[3]){-4.0f, 3.0f, 0.5f}, sizeof r.eye);
    memcpy(r.target, (const float[3]){0.0f, 1.0f, 0.5f}, sizeof r.target);
    cvk_render_view side = view_of(ctx, false, &r);
    double d[3], n = 0.0, g[3] = {-4.0, 2.0, 0.0}, gn = sqrt(20.0), along = 0.0;
    for (int k = 0; k < 3; k++) {
        d[k] = side.eye[k] - side.target[k];
        n += d[k] * d[k];
    }
    for (int k = 0; k < 3; k++)
        along += d[k] / sqrt(n) * g[k] / gn;
    CHECK(along > 1.0 - 1e-6, "the fitted view looks along %g of the given direction", along);

    /* cvk_renderer_fit: the particles again, a larger box, refused without render.fit. */
    setup s = {0};
    fill_scene(&s, false);
    r = fit_view(0.06f);
    setup_scene(&s, ctx, 1, &r);
    cvk_render_view first = cvk_renderer_get_view(s.renderer);
    cvk_error err;
    REQUIRE_OK(cvk_renderer_fit(s.renderer, NULL, NULL, &err), err);
    cvk_render_view again = cvk_renderer_get_view(s.renderer);
    CHECK(memcmp(&first, &again, sizeof first) == 0, "fitting the same particles again moved the view");
    const float box_lo[3] = {-3, 0, -3}, box_hi[3] = {3, 4, 3};
    REQUIRE_OK(cvk_renderer_fit(s.renderer, box_lo, box_hi, &err), err);
    cvk_render_view wide = cvk_renderer_get_view(s.renderer);
    check_framed(box_corners(&wide, box_lo, box_hi), 0.06f, "a given 6 x 4 x 6 m box");
    CHECK(distance3(wide.eye, wide.target) > 2.0 * distance3(first.eye, first.target),
          "a 6 m box is framed from %g m, the 2 m scene from %g m", distance3(wide.eye, wide.target),
          distance3(first.eye, first.target));
    cvk_result res = cvk_renderer_fit(s.renderer, (const float[3]){1, 0, 0}, (const float[3]){0, 1, 1}, &err);
    CHECK(res == CVK_ERROR_INVALID_ARGUMENT && strcmp(err.message, "cvk_renderer_fit: the box must be finite with "
                                                      "lo <= hi, got [1, 0] along axis 0") == 0,
          "an inverted box: %s: %s", cvk_result_name(res), err.message);
    teardown(&s);

    setup plain = {0};
    fill_scene(&plain, false);
    r.fit = false;
    setup_scene(&plain, ctx, 1, &r);
    res = cvk_renderer_fit(plain.renderer, NULL, NULL, &err);
    CHECK(res == CVK_ERROR_INVALID_ARGUMENT &&
              strcmp(err.message, "cvk_renderer_fit: the renderer's description has render.fit off") == 0,
          "fit without render.fit: %s: %s", cvk_result_name(res), err.message);
    teardown(&plain);
}

static void fit_refused_in_file(void)
{
    static const char text[] = "{\"cloths\": [{\"grid\": [4, 4]}], \"render\": {\"fit\": \"yes\"}}";
    cvk_scene* scene = NULL;
    cvk_error err;
    cvk_result r = cvk_scene_parse(text, "fit.json", NULL, 0, &scene, &err);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT && scene == NULL &&
              strcmp(err.message, "fit.json: render.fit: expected true, false or an object such as "
                                  "{\"margin\": 0.1}, got the string \"yes\"") == 0,
          "render.fit \"yes\": %s: %s", cvk_result_name(r), err.message);
    cvk_scene_destroy(scene);
}

/* ---- the overlay ---- */

static void overlay_in_corner(cvk_context* ctx)
{
    static uint8_t plain[W * H * 4], text[W * H * 4];
    setup a = {0}, b = {0};
    fill_scene(&a, false);
    fill_scene(&b, false);
    cvk_render_desc r = fit_view(0.06f);
    setup_scene(&a, ctx, 1, &r);
    r.overlay = true;
    setup_scene(&b, ctx, 1, &r);
    cvk_renderer_set_time(a.renderer, 0.25);
    cvk_renderer_set_time(b.renderer, 0.25);
    cvk_image im = draw(&a);
    memcpy(plain, im.pixels, sizeof plain);
    im = draw(&b);
    memcpy(text, im.pixels, sizeof text);
    int inside = 0, outside = 0, white = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            size_t i = ((size_t)y * W + (size_t)x) * 4;
            bool differs = memcmp(plain + i, text + i, 4) != 0;
            bool corner = x < 3 * W / 4 && y >= 3 * H / 4;
            inside += differs && corner;
            outside += differs && !corner;
            white += differs && text[i] == 255 && text[i + 1] == 255 && text[i + 2] == 255;
        }
    CHECK(inside > 500 && white > 100, "the overlay changed %d pixels of the lower left corner, %d to white", inside,
          white);
    CHECK(outside == 0, "the overlay changed %d pixels outside the lower left corner", outside);
    im = draw(&b);
    CHECK(memcmp(im.pixels, text, sizeof text) == 0, "the overlay's image differs the second time");
    cvk_renderer_set_time(b.renderer, 1.5);
    im = draw(&b);
    CHECK(memcmp(im.pixels, text, sizeof text) != 0, "the overlay at 1.5 s is the one at 0.25 s");
    cvk_render_timing t = cvk_renderer_get_timing(b.renderer);
    CHECK(t.overlay_ms >= 0.0, "overlay time %g ms", t.overlay_ms);
    teardown(&a);
    teardown(&b);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    fit_frames_cloth_and_collider(ctx);
    fit_view_rules(ctx);
    fit_refused_in_file();
    overlay_in_corner(ctx);
    return harness_finish(ctx);
}
