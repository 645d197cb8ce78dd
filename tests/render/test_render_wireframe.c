/* render.wireframe, checked in the image: a flat 12 x 12 cloth seen obliquely, drawn with and
   without the wireframe.
   - at the middle of every projected row and column edge, the wireframe image has a pixel far
     darker than the shaded cloth there: every edge is drawn, none lost to z-fighting (without
     the pipeline's depth bias 125 of the 220 edges lose to their own triangles here);
   - the same places in the plain image are the cloth's shading, not dark;
   - inside the triangles, away from every edge, both images agree. */
#include "harness.h"

#include "core/context.h"

enum { W = 320, H = 240, N = 12 };

static const float red[3] = {0.8f, 0.1f, 0.08f};
static const float origin[3] = {-0.5f, 1.5f, 0.0f};

typedef struct setup {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    cvk_sim* sim;
    cvk_mesh* mesh;
    cvk_renderer* renderer;
} setup;

/* A static vertical cloth in z = 0, 1 m square, N x N particles, seen from above and the side:
   the depth varies across every triangle. */
static void setup_scene(setup* s, cvk_context* ctx, bool wireframe)
{
    s->cloth = cvk_default_cloth_desc();
    s->cloth.grid[0] = s->cloth.grid[1] = N;
    memcpy(s->cloth.origin, origin, sizeof origin);
    memcpy(s->cloth.u_axis, (const float[3]){1, 0, 0}, 3 * sizeof(float));
    memcpy(s->cloth.v_axis, (const float[3]){0, -1, 0}, 3 * sizeof(float));
    memcpy(s->cloth.color, red, sizeof red);
    s->scene = cvk_default_scene_desc();
    s->scene.integrate = false;
    memset(s->scene.gravity, 0, sizeof s->scene.gravity);
    s->scene.cloths = &s->cloth;
    s->scene.cloth_count = 1;
    cvk_render_desc* r = &s->scene.render;
    r->size[0] = W;
    r->size[1] = H;
    r->auto_eye = r->auto_target = false;
    memcpy(r->eye, (const float[3]){1.3f, 1.7f, 1.9f}, 3 * sizeof(float));
    memcpy(r->target, (const float[3]){0.0f, 1.0f, 0.0f}, 3 * sizeof(float));
    memcpy(r->key.direction, (const float[3]){0.3f, 0.5f, 1.0f}, 3 * sizeof(float));
    r->ground = false;
    r->shadow_map_size = 512;
    r->wireframe = wireframe;
    cvk_error err;
    REQUIRE_OK(harness_sim_create(ctx, &s->scene, &s->sim, &err), err);
    REQUIRE_OK(cvk_mesh_create(s->sim, NULL, &s->mesh, &err), err);
    REQUIRE_OK(cvk_renderer_create(s->mesh, &s->scene.render, &s->renderer, &err), err);
    REQUIRE_OK(cvk_renderer_draw(s->renderer, &err), err);
}

static void teardown(setup* s)
{
    cvk_renderer_destroy(s->renderer);
    cvk_mesh_destroy(s->mesh);
    cvk_sim_destroy(s->sim);
}

static double luminance_at(const cvk_image* im, int x, int y)
{
    const uint8_t* p = im->pixels + (size_t)y * im->row_bytes + 4 * (size_t)x;
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

/* The darkest pixel within one pixel of (x, y): a one-pixel line may fall on either side of a
   projected point. */
static double darkest_near(const cvk_image* im, double x, double y)
{
    int cx = (int)floor(x), cy = (int)floor(y);
    double d = 1e9;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++)
            d = fmin(d, luminance_at(im, cx + dx, cy + dy));
    return d;
}

/* The cloth's point at grid coordinates (i, j) in pixels. */
static void project(const cvk_renderer* r, double i, double j, double out[2])
{
    float p[3] = {origin[0] + (float)(i / (N - 1)), origin[1] - (float)(j / (N - 1)), 0.0f};
    cvk_render_view v = cvk_renderer_get_view(r);
    const float* m = v.view_proj;
    double clip[4];
    for (int k = 0; k < 4; k++)
        clip[k] = m[k] * p[0] + m[4 + k] * p[1] + m[8 + k] * p[2] + m[12 + k];
    out[0] = (clip[0] / clip[3] * 0.5 + 0.5) * W;
    out[1] = (clip[1] / clip[3] * 0.5 + 0.5) * H;
}

static void edges_drawn(cvk_context* ctx)
{
    setup plain = {0}, wired = {0};
    setup_scene(&plain, ctx, false);
    setup_scene(&wired, ctx, true);
    cvk_image a = cvk_renderer_get_image(plain.renderer), b = cvk_renderer_get_image(wired.renderer);
    /* Interior row and column edges, at their middles: (i + 0.5, j) and (i, j + 0.5). */
    int edges = 0, drawn = 0, dark_without = 0;
    double worst = 0.0;
    for (int j = 1; j < N - 1; j++)
        for (int i = 0; i < N - 1; i++)
            for (int dir = 0; dir < 2; dir++) {
                double px[2];
                project(wired.renderer, dir ? j : i + 0.5, dir ? i + 0.5 : j, px);
                double shade = darkest_near(&a, px[0], px[1]), line = darkest_near(&b, px[0], px[1]);
                edges++;
                drawn += line < 0.65 * shade;
                dark_without += shade < 40.0;
                worst = fmax(worst, line / shade);
            }
    CHECK(drawn == edges, "%d of %d projected edge middles have a wireframe pixel (darkest near one at %.2f of "
          "the shading)", drawn, edges, worst);
    CHECK(dark_without == 0, "%d edge middles are dark without the wireframe", dark_without);
    /* Points inside the triangles, at least 0.14 cells (2 pixels) from every edge whichever way
       a cell's diagonal runs: unchanged. */
    int cells = 0, changed = 0;
    for (int j = 0; j < N - 1; j++)
        for (int i = 0; i < N - 1; i++)
            for (int side = 0; side < 2; side++) {
                double px[2];
                project(wired.renderer, i + (side ? 0.3 : 0.7), j + 0.5, px);
                int x = (int)floor(px[0]), y = (int)floor(px[1]);
                cells++;
                changed += fabs(luminance_at(&a, x, y) - luminance_at(&b, x, y)) > 2.0;
            }
    CHECK(changed == 0, "%d of %d points inside the triangles changed with the wireframe", changed, cells);
    teardown(&plain);
    teardown(&wired);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    CHECK(ctx->fill_mode_non_solid, "the device draws triangles as lines (lavapipe does)");
    edges_drawn(ctx);
    return harness_finish(ctx);
}
