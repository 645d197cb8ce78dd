/* Images checked by what they must show, not by their bytes:
   - every pixel outside the cloth's projected bounds is the background, and the middle of
     the cloth is the cloth's colour;
   - a cloth seen from behind, lit from the viewer's side, is as bright as its front face lit
     the same way, and a face turned away from the light is darker (each face is lit with its
     own normal);
   - on the ground, pixels inside a pinned cloth's shadow are darker than ground far from it,
     also at the end of a long shadow under a low light, beyond the depth the cloth spans;
   - two cloths keep their own colours;
   - no frame has a pure-black pixel (what a NaN turns into) or is one flat colour;
   - two renderers of one scene give the same bytes, and frames recorded into the caller's
     command buffer with the simulation match cvk_renderer_draw;
   - a PNG written and read back holds the same pixels; bad arguments get their messages. */
#include "render_fixture.h"

#include <errno.h>
#include <sys/stat.h>
#include <unistd.h>

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_image.h>
#pragma GCC diagnostic pop

#include "core/gpu.h"

enum { W = 160, H = 120 };

static const float background[3] = {0.1f, 0.2f, 0.45f};
static const float red[3] = {0.8f, 0.1f, 0.08f};

/* ---- scenes: static cloths (no integration, no gravity) so images are exact ---- */

static cvk_render_desc small_view(const float eye[3], const float target[3], const float key[3])
{
    cvk_render_desc r = fixture_view(W, H, eye, target, key);
    memcpy(r.background, background, sizeof r.background);
    r.shadow_map_size = 512;
    return r;
}

/* ---- pixels ---- */

/* Mean luminance of the 5 x 5 pixels around (x, y). */
static double patch_luminance(const cvk_image* im, int x, int y)
{
    double sum = 0.0;
    for (int dy = -2; dy <= 2; dy++)
        for (int dx = -2; dx <= 2; dx++)
            sum += luminance(pixel(im, x + dx, y + dy));
    return sum / 25.0;
}

static uint8_t srgb8(float linear)
{
    double s = linear <= 0.0031308 ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
    return (uint8_t)lround(s * 255.0);
}

static bool near_color(const uint8_t* p, const float linear[3], int tolerance)
{
    for (int k = 0; k < 3; k++)
        if (abs((int)p[k] - (int)srgb8(linear[k])) > tolerance)
            return false;
    return true;
}

static void project(const cvk_renderer* r, const float p[3], double out[2])
{
    cvk_render_view v = cvk_renderer_get_view(r);
    project_point(&v, (const double[3]){p[0], p[1], p[2]}, W, H, out);
}

/* No pure-black pixel (a NaN in the shading comes out black) and not one flat colour. */
static void check_sane(const cvk_image* im, const char* what)
{
    uint32_t black = 0, differing = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const uint8_t* p = pixel(im, x, y);
            black += p[0] == 0 && p[1] == 0 && p[2] == 0;
            differing += memcmp(p, pixel(im, 0, 0), 3) != 0;
        }
    CHECK(black == 0, "%s: %u pure-black pixels", what, black);
    CHECK(differing > 0, "%s: the whole frame is one colour", what);
}

static cvk_image draw(setup* s)
{
    cvk_error err;
    REQUIRE_OK(cvk_renderer_draw(s->renderer, &err), err);
    return cvk_renderer_get_image(s->renderer);
}

/* ---- the facts ---- */

/* A vertical cloth in the plane z = 0, its normal (u × v) towards −z. */
static const float wall_origin[3] = {-0.5f, 1.5f, 0.0f};
static const float wall_u[3] = {1, 0, 0};
static const float wall_v[3] = {0, -1, 0};

static void cloth_inside_its_bounds(cvk_context* ctx)
{
    cvk_render_desc r = small_view((const float[3]){0.6f, 1.4f, 2.6f}, (const float[3]){0, 1, 0},
                                   (const float[3]){0.3f, 0.5f, 1.0f});
    r.ground = false;
    setup s = {0};
    s.cloths[0] = square_cloth(wall_origin, wall_u, wall_v, red);
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s);
    check_sane(&im, "cloth alone");
    double lo[2] = {1e9, 1e9}, hi[2] = {-1e9, -1e9};
    for (int c = 0; c < 4; c++) {
        float corner[3] = {wall_origin[0] + (c & 1), wall_origin[1] - (c >> 1), 0.0f};
        double px[2];
        project(s.renderer, corner, px);
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], px[k]);
            hi[k] = fmax(hi[k], px[k]);
        }
    }
    uint32_t outside_not_background = 0, inside_cloth = 0, inside = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const uint8_t* p = pixel(&im, x, y);
            bool out = x + 1 < lo[0] - 1 || x > hi[0] + 1 || y + 1 < lo[1] - 1 || y > hi[1] + 1;
            if (out)
                outside_not_background += !near_color(p, background, 1);
            else {
                inside++;
                inside_cloth += !near_color(p, background, 1);
            }
        }
    CHECK(outside_not_background == 0, "%u pixels outside the cloth's bounds [%.1f, %.1f] x [%.1f, %.1f] are not "
          "the background", outside_not_background, lo[0], hi[0], lo[1], hi[1]);
    CHECK(inside_cloth > inside / 2, "only %u of %u pixels inside the cloth's bounds show cloth", inside_cloth, inside);
    double centre[2];
    project(s.renderer, (const float[3]){0.0f, 1.0f, 0.0f}, centre);
    const uint8_t* mid = pixel(&im, (int)centre[0], (int)centre[1]);
    CHECK(mid[0] > 2 * mid[1] && mid[0] > 2 * mid[2], "the middle of a red cloth is (%u, %u, %u)", mid[0], mid[1],
          mid[2]);
    printf("cloth bounds [%.0f, %.0f] x [%.0f, %.0f] px: %u of %u pixels inside are cloth, none outside\n", lo[0],
           hi[0], lo[1], hi[1], inside_cloth, inside);
    teardown(&s);
}

/* Brightness of the middle of the wall, seen from `eye` with the key light towards `key`. */
static double wall_brightness(cvk_context* ctx, const float eye[3], const float key[3])
{
    cvk_render_desc r = small_view(eye, (const float[3]){0, 1, 0}, key);
    r.ground = false;
    r.fill.color[0] = r.fill.color[1] = r.fill.color[2] = 0.0f;
    setup s = {0};
    s.cloths[0] = square_cloth(wall_origin, wall_u, wall_v, (const float[3]){0.7f, 0.7f, 0.7f});
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s);
    check_sane(&im, "wall");
    double centre[2];
    project(s.renderer, (const float[3]){0.0f, 1.0f, 0.0f}, centre);
    double b = patch_luminance(&im, (int)centre[0], (int)centre[1]);
    teardown(&s);
    return b;
}

static void both_faces_lit(cvk_context* ctx)
{
    const float front_eye[3] = {0.3f, 1.2f, -2.5f}, back_eye[3] = {0.3f, 1.2f, 2.5f};
    const float from_front[3] = {0.2f, 0.3f, -1.0f}, from_back[3] = {0.2f, 0.3f, 1.0f};
    double front = wall_brightness(ctx, front_eye, from_front);
    double back = wall_brightness(ctx, back_eye, from_back);
    double back_unlit = wall_brightness(ctx, back_eye, from_front);
    CHECK(back > 0.85 * front && back < 1.15 * front,
          "seen from behind and lit from the viewer's side the cloth has luminance %.1f; its front face lit the "
          "same way has %.1f", back, front);
    CHECK(back > 60.0, "the back face lit from the viewer's side is dark: luminance %.1f", back);
    CHECK(back_unlit < 0.6 * back, "the face turned away from the light (luminance %.1f) is not darker than the "
          "lit one (%.1f)", back_unlit, back);
    printf("front face lit %.1f, back face lit %.1f, face away from the light %.1f\n", front, back, back_unlit);
}

static void shadow_on_ground(cvk_context* ctx)
{
    /* A horizontal cloth at y = 1 over x, z in [-0.5, 0.5]; light from +x and above: its
       shadow falls on the ground at y = 0 over x in [-1, 0], left of what is under it. */
    const float key[3] = {1.0f, 2.0f, 0.0f};
    cvk_render_desc r = small_view((const float[3]){0.3f, 2.6f, 3.4f}, (const float[3]){-0.2f, 0.3f, 0.0f}, key);
    r.auto_ground_height = false;
    r.ground_height = 0.0f;
    r.shadow_map_size = 1024;
    setup s = {0};
    s.cloths[0] = square_cloth((const float[3]){-0.5f, 1.0f, -0.5f}, (const float[3]){1, 0, 0},
                               (const float[3]){0, 0, 1}, red);
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s);
    check_sane(&im, "shadow scene");
    double in_shadow[2], far_away[2];
    project(s.renderer, (const float[3]){-0.75f, 0.0f, 0.0f}, in_shadow);
    project(s.renderer, (const float[3]){1.4f, 0.0f, 0.3f}, far_away);
    const uint8_t* shadow_px = pixel(&im, (int)in_shadow[0], (int)in_shadow[1]);
    CHECK(!(shadow_px[0] > 2 * shadow_px[1]), "the shadow's sample point shows the (red) cloth, not the ground");
    double dark = patch_luminance(&im, (int)in_shadow[0], (int)in_shadow[1]);
    double lit = patch_luminance(&im, (int)far_away[0], (int)far_away[1]);
    CHECK(dark < 0.7 * lit, "ground in the cloth's shadow has luminance %.1f, ground far from it %.1f", dark, lit);
    printf("ground in the shadow %.1f, far from it %.1f\n", dark, lit);
    teardown(&s);
}

static void long_shadow(cvk_context* ctx)
{
    /* A wall from y = 0.1 to 1.1 in the plane z = 0, the key light 16.7° above the horizon from
       +z: its shadow reaches z = -1.1 / 0.3 = -3.67 on the ground, about twice as far from the
       eye as the wall. Near that end the ground is still shadowed, and lit beside it. */
    const float key[3] = {0.0f, 0.3f, 1.0f};
    cvk_render_desc r = small_view((const float[3]){2.2f, 1.8f, 1.2f}, (const float[3]){0.0f, 0.2f, -1.4f}, key);
    r.auto_ground_height = false;
    r.ground_height = 0.0f;
    r.shadow_map_size = 1024;
    setup s = {0};
    s.cloths[0] = square_cloth((const float[3]){-0.5f, 1.1f, 0.0f}, wall_u, wall_v, red);
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s);
    check_sane(&im, "long shadow");
    double tip[2], beside[2];
    project(s.renderer, (const float[3]){0.0f, 0.0f, -3.3f}, tip);
    project(s.renderer, (const float[3]){1.0f, 0.0f, -3.3f}, beside);
    double dark = patch_luminance(&im, (int)tip[0], (int)tip[1]);
    double lit = patch_luminance(&im, (int)beside[0], (int)beside[1]);
    CHECK(dark < 0.8 * lit, "ground near the end of a long shadow has luminance %.1f, beside it %.1f", dark, lit);
    printf("end of a long shadow %.1f, beside it %.1f\n", dark, lit);
    teardown(&s);
}

static void cloths_keep_their_colours(cvk_context* ctx)
{
    cvk_render_desc r = small_view((const float[3]){0.0f, 1.2f, 3.0f}, (const float[3]){0, 1, 0},
                                   (const float[3]){0.2f, 0.5f, 1.0f});
    setup s = {0};
    s.cloths[0] = square_cloth((const float[3]){-1.1f, 1.5f, 0}, wall_u, wall_v, red);
    s.cloths[1] = square_cloth((const float[3]){0.1f, 1.5f, 0}, wall_u, wall_v, (const float[3]){0.1f, 0.7f, 0.1f});
    setup_scene(&s, ctx, 2, &r);
    cvk_image im = draw(&s);
    check_sane(&im, "two cloths");
    double a[2], b[2];
    project(s.renderer, (const float[3]){-0.6f, 1.0f, 0.0f}, a);
    project(s.renderer, (const float[3]){0.6f, 1.0f, 0.0f}, b);
    const uint8_t* pa = pixel(&im, (int)a[0], (int)a[1]);
    const uint8_t* pb = pixel(&im, (int)b[0], (int)b[1]);
    CHECK(pa[0] > 2 * pa[1], "the red cloth shows (%u, %u, %u)", pa[0], pa[1], pa[2]);
    CHECK(pb[1] > 2 * pb[0], "the green cloth shows (%u, %u, %u)", pb[0], pb[1], pb[2]);
    teardown(&s);
}

/* Default (automatic) framing of a falling, hanging cloth: sane frames all the way. */
static void default_view_frames(cvk_context* ctx)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = 24;
    static const uint32_t pins[2][2] = {{0, 0}, {23, 0}};
    cloth.pins = pins;
    cloth.pin_count = 2;
    memcpy(cloth.color, red, sizeof cloth.color); /* told from ground and sky as elsewhere here */
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.render.size[0] = W;
    scene.render.size[1] = H;
    cvk_error err;
    cvk_sim* sim;
    cvk_mesh* mesh;
    cvk_renderer* renderer;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    REQUIRE_OK(cvk_renderer_create(mesh, &scene.render, &renderer, &err), err);
    cvk_render_view v = cvk_renderer_get_view(renderer);
    CHECK(v.ground_height < v.reach_min[1], "the automatic ground (%g) is not below the reach (%g)",
          v.ground_height, v.reach_min[1]);
    for (int frame = 0; frame < 4; frame++) {
        REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
        REQUIRE_OK(cvk_renderer_draw(renderer, &err), err);
        cvk_image im = cvk_renderer_get_image(renderer);
        check_sane(&im, "default view");
        /* The cloth, hanging from its pins, stays in the frame: each pin (the cloth's corners
           (0, 0) and (1, 0) m along u, v: pinned particles do not move) projects inside the
           image with cloth-red pixels (red over twice green and blue) within 5 px of it (the
           pin's own pixel is a corner, partly covered, and the swinging cloth turns edge-on
           near it: the nearest is up to 3.7 px off), and no cloth pixel is on the image's
           border (nothing of the cloth is cut off). */
        for (int k = 0; k < 2; k++) {
            double pin[2], nearest = 1e9;
            const float corner[3] = {cloth.origin[0] + k, cloth.origin[1], cloth.origin[2]};
            project(renderer, corner, pin);
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    const uint8_t* p = pixel(&im, x, y);
                    if (p[0] > 2 * p[1] && p[0] > 2 * p[2])
                        nearest = fmin(nearest, hypot(x + 0.5 - pin[0], y + 0.5 - pin[1]));
                }
            CHECK(pin[0] > 0 && pin[0] < W && pin[1] > 0 && pin[1] < H && nearest <= 5.0,
                  "frame %d: pin %d projects to (%.1f, %.1f), the nearest cloth pixel %.1f px away",
                  frame, k, pin[0], pin[1], nearest);
        }
        uint32_t cut = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                const uint8_t* p = pixel(&im, x, y);
                bool border = x == 0 || y == 0 || x == W - 1 || y == H - 1;
                cut += border && p[0] > 2 * p[1] && p[0] > 2 * p[2];
            }
        CHECK(cut == 0, "frame %d: %u cloth pixels on the image's border", frame, cut);
    }
    cvk_render_timing t = cvk_renderer_get_timing(renderer);
    CHECK(t.total_ms > 0.0 && t.mesh_ms >= 0.0 && t.lit_ms > 0.0, "timing: total %g, mesh %g, lit %g ms", t.total_ms,
          t.mesh_ms, t.lit_ms);
    cvk_renderer_destroy(renderer);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
}

/* The same falling cloth twice: drawn with cvk_renderer_draw after cvk_sim_step, and recorded
   with cvk_sim_record + cvk_renderer_record into one command buffer of the caller's. */
static void deterministic_and_recordable(cvk_context* ctx)
{
    cvk_render_desc r = small_view((const float[3]){1.5f, 1.8f, 2.5f}, (const float[3]){0, 0.6f, 0},
                                   (const float[3]){0.4f, 1.0f, 0.5f});
    setup a = {.falling = true}, b = {.falling = true};
    a.cloths[0] = b.cloths[0] = square_cloth((const float[3]){-0.5f, 1.0f, -0.5f}, (const float[3]){1, 0, 0},
                                             (const float[3]){0, 0, 1}, red);
    static const uint32_t pins[2][2] = {{0, 0}, {15, 0}};
    a.cloths[0].pins = b.cloths[0].pins = pins;
    a.cloths[0].pin_count = b.cloths[0].pin_count = 2;
    setup_scene(&a, ctx, 1, &r);
    setup_scene(&b, ctx, 1, &r);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(a.sim, 5, &err), err);
    cvk_image ia = draw(&a);
    uint8_t* first = malloc((size_t)W * H * 4);
    if (!first)
        exit(1);
    memcpy(first, ia.pixels, (size_t)W * H * 4);

    cvk_submitter sub;
    VkCommandBuffer cmd;
    REQUIRE_OK(cvk_submitter_create(ctx, &sub, &err), err);
    REQUIRE_OK(cvk_command_buffer_allocate(ctx, &sub, &cmd, &err), err);
    REQUIRE_OK(cvk_command_buffer_begin(cmd, 0, &err), err);
    REQUIRE_OK(cvk_sim_record(b.sim, cmd, 5, &err), err);
    REQUIRE_OK(cvk_renderer_record(b.renderer, cmd, &err), err);
    REQUIRE_OK(cvk_command_buffer_end(cmd, &err), err);
    REQUIRE_OK(cvk_submit_and_wait(ctx, &sub, &cmd, 1, &err), err);
    cvk_submitter_destroy(ctx, &sub);
    cvk_image ib = cvk_renderer_get_image(b.renderer);
    check_sane(&ib, "recorded frame");
    uint32_t differing = 0;
    for (size_t i = 0; i < (size_t)W * H * 4; i++)
        differing += first[i] != ib.pixels[i];
    CHECK(differing == 0, "recorded and drawn frames of the same simulation differ in %u bytes", differing);

    /* The second frame is not the first: the cloth fell. */
    REQUIRE_OK(cvk_sim_step(a.sim, 5, &err), err);
    ia = draw(&a);
    differing = 0;
    for (size_t i = 0; i < (size_t)W * H * 4; i++)
        differing += first[i] != ia.pixels[i];
    CHECK(differing > 100, "5 more frames of a falling cloth changed only %u bytes of the image", differing);
    printf("recorded frame identical to the drawn one; 5 frames later %u bytes differ\n", differing);
    free(first);
    teardown(&a);
    teardown(&b);
}

static void png_round_trip(cvk_context* ctx)
{
    cvk_render_desc r = small_view((const float[3]){0.6f, 1.4f, 2.6f}, (const float[3]){0, 1, 0},
                                   (const float[3]){0.3f, 0.5f, 1.0f});
    setup s = {0};
    s.cloths[0] = square_cloth(wall_origin, wall_u, wall_v, red);
    setup_scene(&s, ctx, 1, &r);
    cvk_image im = draw(&s);
    char dir[] = "/tmp/clothvk-png-XXXXXX";
    CHECK(mkdtemp(dir) != NULL, "mkdtemp failed");
    char path[128];
    snprintf(path, sizeof path, "%s/frame.png", dir);
    cvk_error err;
    REQUIRE_OK(cvk_image_write_png(&im, path, &err), err);
    int w = 0, h = 0, n = 0;
    unsigned char* back = stbi_load(path, &w, &h, &n, 4);
    CHECK(back && w == W && h == H, "the PNG reads back as %d x %d", w, h);
    uint32_t differing = 0;
    for (int y = 0; back && y < H; y++)
        differing += memcmp(back + (size_t)y * W * 4, pixel(&im, 0, y), (size_t)W * 4) != 0;
    CHECK(differing == 0, "%u rows of the PNG differ from the image", differing);
    stbi_image_free(back);
    unlink(path);

    /* Each failure names the file and the reason; nothing half-written is left (checked
       after the last one: no frame.png, and the folder is empty). */
    char missing[160];
    snprintf(missing, sizeof missing, "%s/no-such-dir/frame.png", dir);
    cvk_error bad = {0};
    cvk_result res = cvk_image_write_png(&im, missing, &bad);
    char expected[256];
    snprintf(expected, sizeof expected, "%s: cannot create: No such file or directory", missing);
    CHECK(res == CVK_ERROR_IO && strcmp(bad.message, expected) == 0, "writing into a missing folder: %s: %s",
          cvk_result_name(res), bad.message);
    /* A FIFO (or device, folder, link) at the path is refused, not replaced by a file. */
    char fifo[160];
    snprintf(fifo, sizeof fifo, "%s/fifo.png", dir);
    if (mkfifo(fifo, 0600) == 0) {
        res = cvk_image_write_png(&im, fifo, &bad);
        snprintf(expected, sizeof expected, "%s: exists and is not a regular file; it is not "
                 "replaced", fifo);
        struct stat st;
        CHECK(res == CVK_ERROR_IO && strcmp(bad.message, expected) == 0 && stat(fifo, &st) == 0 &&
                  S_ISFIFO(st.st_mode),
              "writing over a FIFO: %s: %s", cvk_result_name(res), bad.message);
        unlink(fifo);
    }
    cvk_image empty = im;
    empty.row_bytes = 3;
    res = cvk_image_write_png(&empty, path, &bad);
    snprintf(expected, sizeof expected, "%s: cannot encode a %d x %d image with 3 bytes per row", path, W, H);
    CHECK(res == CVK_ERROR_INVALID_ARGUMENT && strcmp(bad.message, expected) == 0, "bad stride: %s", bad.message);
    CHECK(access(path, F_OK) != 0, "%s exists after the bad-stride write failed", path);
    CHECK(rmdir(dir) == 0, "%s is not empty after the failed writes (%s)", dir, strerror(errno));
    teardown(&s);
}

static void expect_failure(cvk_mesh* mesh, const cvk_render_desc* r, cvk_result result, const char* message)
{
    cvk_error err = {0};
    cvk_renderer* renderer = (cvk_renderer*)mesh;
    cvk_result got = cvk_renderer_create(mesh, r, &renderer, &err);
    CHECK(got == result && err.result == result, "expected %s, got %s (%s)", cvk_result_name(result),
          cvk_result_name(got), err.message);
    CHECK(strcmp(err.message, message) == 0, "message \"%s\", expected \"%s\"", err.message, message);
    CHECK(renderer == NULL, "a renderer came back from a failure");
}

static void refusals(cvk_context* ctx)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = 8;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    cvk_error err;
    cvk_sim* sim;
    cvk_mesh* mesh;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    const char* device = cvk_context_get_info(ctx).device_name;
    uint32_t max = cvk_context_get_info(ctx).max_image_size;
    char message[512];

    cvk_render_desc r = cvk_default_render_desc();
    r.size[0] = max + 1;
    snprintf(message, sizeof message, "render.size: %u x 720 pixels is more than %s allows (%u x %u)", max + 1,
             device, max, max);
    expect_failure(mesh, &r, CVK_ERROR_DEVICE_LIMIT, message);

    r = cvk_default_render_desc();
    r.size[1] = 0;
    expect_failure(mesh, &r, CVK_ERROR_INVALID_ARGUMENT, "render.size: each dimension must be at least 1, got [1280, 0]");

    if (strstr(device, "llvmpipe")) {
        r = cvk_default_render_desc();
        r.samples = 8;
        snprintf(message, sizeof message, "render.samples: %s draws 1 or 4 samples per pixel, not 8", device);
        expect_failure(mesh, &r, CVK_ERROR_DEVICE_LIMIT, message);
    }

    /* An adopted compute-only queue: the mesh works there, the renderer says why it cannot. */
    ctx->graphics = false;
    r = cvk_default_render_desc();
    snprintf(message, sizeof message,
             "rendering needs a queue that can draw; queue family %u of %s supports compute only (cvk_mesh works "
             "there: draw its buffers on a graphics queue)", ctx->queue_family, device);
    expect_failure(mesh, &r, CVK_ERROR_UNSUPPORTED, message);
    ctx->graphics = true;

    /* A NULL mesh: refused with the library's exact message, the output pointer cleared. */
    cvk_renderer* renderer = (cvk_renderer*)&r;
    cvk_error null_err = {0};
    cvk_result null_res = cvk_renderer_create(NULL, &r, &renderer, &null_err);
    const char* null_message =
        "cvk_renderer_create needs a mesh, a render description and an output pointer";
    CHECK(null_res == CVK_ERROR_INVALID_ARGUMENT && strcmp(null_err.message, null_message) == 0,
          "a NULL mesh: %s: %s", cvk_result_name(null_res), null_err.message);
    CHECK(renderer == NULL, "a NULL mesh: the output pointer was left set");
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    cloth_inside_its_bounds(ctx);
    both_faces_lit(ctx);
    shadow_on_ground(ctx);
    long_shadow(ctx);
    cloths_keep_their_colours(ctx);
    default_view_frames(ctx);
    deterministic_and_recordable(ctx);
    png_round_trip(ctx);
    refusals(ctx);
    return harness_finish(ctx);
}
