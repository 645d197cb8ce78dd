/* render.camera_keyframes, checked in the image: a static 1 m cloth and a camera that moves
   and turns sideways from t = 0 to 1 s, then rises and tilts down until 2 s.
   - at 0.5 s, 1.5 s and 3 s (held after the last keyframe) the image is byte for byte the
     image of a fixed camera at the eye and target the keyframe rules give (lines between
     keyframes, the last one held);
   - with camera_loop, 2.5 s draws what 0.5 s draws;
   - the cloth's pixels are centred where the view's projection of its outline is centred, at
     0 s and at 1 s, and that place moves by more than a tenth of the image between them;
   - cvk_renderer_get_view reports the interpolated eye and target. */
#include "harness.h"

enum { W = 200, H = 150 };

static const float background[3] = {0.1f, 0.2f, 0.45f};
static const float origin[3] = {-0.5f, 1.5f, 0.0f};

/* Eyes and targets chosen so the interpolated ones are exact in float. */
static const cvk_camera_keyframe path[3] = {
    {0.0f, {1.0f, 1.0f, 2.5f}, {0.5f, 1.0f, 0.0f}},
    {1.0f, {-1.0f, 1.0f, 2.5f}, {-0.5f, 1.0f, 0.0f}},
    {2.0f, {-1.0f, 2.0f, 2.5f}, {0.0f, 0.5f, 0.0f}},
};

typedef struct setup {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    cvk_sim* sim;
    cvk_mesh* mesh;
    cvk_renderer* renderer;
} setup;

/* The camera: keyframes (moving) or the fixed eye and target given. */
static void setup_scene(setup* s, cvk_context* ctx, bool moving, bool loop, const float eye[3], const float target[3])
{
    s->cloth = cvk_default_cloth_desc();
    s->cloth.grid[0] = s->cloth.grid[1] = 8;
    memcpy(s->cloth.origin, origin, sizeof origin);
    memcpy(s->cloth.u_axis, (const float[3]){1, 0, 0}, 3 * sizeof(float));
    memcpy(s->cloth.v_axis, (const float[3]){0, -1, 0}, 3 * sizeof(float));
    s->scene = cvk_default_scene_desc();
    s->scene.integrate = false;
    memset(s->scene.gravity, 0, sizeof s->scene.gravity);
    s->scene.cloths = &s->cloth;
    s->scene.cloth_count = 1;
    cvk_render_desc* r = &s->scene.render;
    r->size[0] = W;
    r->size[1] = H;
    r->ground = false;
    r->shadow_map_size = 256;
    memcpy(r->background, background, sizeof background);
    r->auto_eye = r->auto_target = false;
    if (moving) {
        r->camera_keyframes = path;
        r->camera_keyframe_count = 3;
        r->camera_loop = loop;
    } else {
        memcpy(r->eye, eye, 3 * sizeof(float));
        memcpy(r->target, target, 3 * sizeof(float));
    }
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

static cvk_image draw_at(setup* s, double seconds)
{
    cvk_error err;
    cvk_renderer_set_time(s->renderer, seconds);
    REQUIRE_OK(cvk_renderer_draw(s->renderer, &err), err);
    return cvk_renderer_get_image(s->renderer);
}

static uint32_t differing_pixels(const cvk_image* a, const cvk_image* b)
{
    uint32_t n = 0;
    for (uint32_t y = 0; y < H; y++)
        n += memcmp(a->pixels + y * a->row_bytes, b->pixels + y * b->row_bytes, 4u * W) != 0;
    return n;
}

/* The image of a fixed camera at (eye, target) equals the moving camera's at `seconds`. */
static void same_as_fixed(cvk_context* ctx, setup* moving, double seconds, const float eye[3], const float target[3])
{
    setup fixed = {0};
    setup_scene(&fixed, ctx, false, false, eye, target);
    cvk_image want = draw_at(&fixed, 0.0);
    cvk_image got = draw_at(moving, seconds);
    CHECK(differing_pixels(&got, &want) == 0, "at %g s: %u rows differ from a fixed camera at [%g, %g, %g] looking at "
          "[%g, %g, %g]", seconds, differing_pixels(&got, &want), eye[0], eye[1], eye[2], target[0], target[1],
          target[2]);
    cvk_render_view v = cvk_renderer_get_view(moving->renderer);
    CHECK(memcmp(v.eye, eye, sizeof v.eye) == 0 && memcmp(v.target, target, sizeof v.target) == 0,
          "at %g s the view's eye is [%g, %g, %g] and target [%g, %g, %g]", seconds, v.eye[0], v.eye[1], v.eye[2],
          v.target[0], v.target[1], v.target[2]);
    teardown(&fixed);
}

/* The mean position of the pixels that are not the background. */
static void cloth_centroid(const cvk_image* im, double out[2])
{
    double sx = 0.0, sy = 0.0, n = 0.0;
    uint8_t bg[3];
    for (int k = 0; k < 3; k++) {
        double l = background[k];
        bg[k] = (uint8_t)lround(255.0 * (l <= 0.0031308 ? 12.92 * l : 1.055 * pow(l, 1.0 / 2.4) - 0.055));
    }
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            const uint8_t* p = im->pixels + y * im->row_bytes + 4 * x;
            if (abs(p[0] - bg[0]) + abs(p[1] - bg[1]) + abs(p[2] - bg[2]) > 6) {
                sx += x + 0.5;
                sy += y + 0.5;
                n += 1.0;
            }
        }
    out[0] = n > 0 ? sx / n : -1.0;
    out[1] = n > 0 ? sy / n : -1.0;
}

static void project(const cvk_render_view* v, const float p[3], double out[2])
{
    const float* m = v->view_proj;
    double clip[4];
    for (int k = 0; k < 4; k++)
        clip[k] = m[k] * p[0] + m[4 + k] * p[1] + m[8 + k] * p[2] + m[12 + k];
    out[0] = (clip[0] / clip[3] * 0.5 + 0.5) * W;
    out[1] = (clip[1] / clip[3] * 0.5 + 0.5) * H;
}

/* The area centroid of the cloth's image as the view's projection predicts it: the
   quadrilateral of its projected corners (a flat square stays a quadrilateral). */
static void projected_centroid(const cvk_renderer* r, double out[2])
{
    cvk_render_view v = cvk_renderer_get_view(r);
    double q[4][2];
    for (int c = 0; c < 4; c++) { /* around the square */
        float u = (c == 1 || c == 2) ? 1.0f : 0.0f, w = c >= 2 ? 1.0f : 0.0f;
        const float p[3] = {origin[0] + u, origin[1] - w, 0.0f};
        project(&v, p, q[c]);
    }
    double area = 0.0, cx = 0.0, cy = 0.0;
    for (int c = 0; c < 4; c++) {
        const double* a = q[c];
        const double* b = q[(c + 1) % 4];
        double cross = a[0] * b[1] - b[0] * a[1];
        area += cross;
        cx += (a[0] + b[0]) * cross;
        cy += (a[1] + b[1]) * cross;
    }
    out[0] = cx / (3.0 * area);
    out[1] = cy / (3.0 * area);
}

static void follows_projection(setup* moving)
{
    double seen[2][2], predicted[2][2];
    for (int i = 0; i < 2; i++) {
        cvk_image im = draw_at(moving, (double)i);
        cloth_centroid(&im, seen[i]);
        projected_centroid(moving->renderer, predicted[i]);
        CHECK(fabs(seen[i][0] - predicted[i][0]) < 2.0 && fabs(seen[i][1] - predicted[i][1]) < 2.0,
              "at %d s the cloth's pixels are centred at (%.1f, %.1f); its projected outline at (%.1f, %.1f)",
              i, seen[i][0], seen[i][1], predicted[i][0], predicted[i][1]);
    }
    CHECK(fabs(predicted[1][0] - predicted[0][0]) > 0.1 * W, "the projected cloth moves %.1f pixels from 0 to 1 s",
          fabs(predicted[1][0] - predicted[0][0]));
}

int main(void)
{
    cvk_context* ctx = harness_context();
    setup moving = {0}, looping = {0};
    setup_scene(&moving, ctx, true, false, NULL, NULL);
    same_as_fixed(ctx, &moving, 0.5, (const float[3]){0.0f, 1.0f, 2.5f}, (const float[3]){0.0f, 1.0f, 0.0f});
    same_as_fixed(ctx, &moving, 1.5, (const float[3]){-1.0f, 1.5f, 2.5f}, (const float[3]){-0.25f, 0.75f, 0.0f});
    same_as_fixed(ctx, &moving, 3.0, path[2].eye, path[2].target);
    follows_projection(&moving);
    setup_scene(&looping, ctx, true, true, NULL, NULL);
    same_as_fixed(ctx, &looping, 2.5, (const float[3]){0.0f, 1.0f, 2.5f}, (const float[3]){0.0f, 1.0f, 0.0f});
    teardown(&looping);
    teardown(&moving);
    return harness_finish(ctx);
}
