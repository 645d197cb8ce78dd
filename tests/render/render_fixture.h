/* What the renderer's tests share (test_render.c, test_render_colliders.c,
   test_render_effects.c, test_render_fit.c): a scene of up to two cloths and three colliders
   drawn by its own simulation, mesh and renderer, square cloths and views, pixel reads and the
   view's projection. */
#ifndef RENDER_FIXTURE_H
#define RENDER_FIXTURE_H

#include "harness.h"

typedef struct setup {
    bool falling;                /* gravity on; otherwise the cloths stay where they start */
    cvk_cloth_desc cloths[2];
    cvk_collider_desc colliders[3];
    uint32_t collider_count;
    cvk_scene_desc scene;
    cvk_sim* sim;
    cvk_mesh* mesh;
    cvk_renderer* renderer;
} setup;

/* The scene of s's first cloth_count cloths and collider_count colliders, with `render`:
   static (no integration, no gravity) unless s->falling. */
static inline void setup_scene(setup* s, cvk_context* ctx, uint32_t cloth_count, const cvk_render_desc* render)
{
    s->scene = cvk_default_scene_desc();
    if (!s->falling) {
        s->scene.integrate = false;
        memset(s->scene.gravity, 0, sizeof s->scene.gravity);
    }
    s->scene.cloths = s->cloths;
    s->scene.cloth_count = cloth_count;
    s->scene.colliders = s->collider_count ? s->colliders : NULL;
    s->scene.collider_count = s->collider_count;
    s->scene.render = *render;
    cvk_error err;
    REQUIRE_OK(harness_sim_create(ctx, &s->scene, &s->sim, &err), err);
    REQUIRE_OK(cvk_mesh_create(s->sim, NULL, &s->mesh, &err), err);
    REQUIRE_OK(cvk_renderer_create(s->mesh, &s->scene.render, &s->renderer, &err), err);
}

static inline void teardown(setup* s)
{
    cvk_renderer_destroy(s->renderer);
    cvk_mesh_destroy(s->mesh);
    cvk_sim_destroy(s->sim);
}

/* A 16 x 16 square cloth from `origin` along u and v, in `color`. */
static inline cvk_cloth_desc square_cloth(const float origin[3], const float u[3], const float v[3], const float color[3])
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = c.grid[1] = 16;
    memcpy(c.origin, origin, sizeof c.origin);
    memcpy(c.u_axis, u, sizeof c.u_axis);
    memcpy(c.v_axis, v, sizeof c.v_axis);
    memcpy(c.color, color, sizeof c.color);
    return c;
}

/* A width x height view from eye to target with the key light along `key` (the rest the
   defaults). */
static inline cvk_render_desc fixture_view(uint32_t width, uint32_t height, const float eye[3],
                                           const float target[3], const float key[3])
{
    cvk_render_desc r = cvk_default_render_desc();
    r.size[0] = width;
    r.size[1] = height;
    r.auto_eye = r.auto_target = false;
    memcpy(r.eye, eye, sizeof r.eye);
    memcpy(r.target, target, sizeof r.target);
    memcpy(r.key.direction, key, sizeof r.key.direction);
    return r;
}

/* The same with the ground at height 0 and a 1024-texel shadow map. */
static inline cvk_render_desc grounded_view(uint32_t width, uint32_t height, const float eye[3],
                                            const float target[3], const float key[3])
{
    cvk_render_desc r = fixture_view(width, height, eye, target, key);
    r.auto_ground_height = false;
    r.ground_height = 0.0f;
    r.shadow_map_size = 1024;
    return r;
}

/* The pixel at (x, y), clamped to the image. */
static inline const uint8_t* pixel(const cvk_image* im, int x, int y)
{
    x = x < 0 ? 0 : x >= (int)im->width ? (int)im->width - 1 : x;
    y = y < 0 ? 0 : y >= (int)im->height ? (int)im->height - 1 : y;
    return im->pixels + (size_t)y * im->row_bytes + 4 * (size_t)x;
}

static inline double luminance(const uint8_t* p)
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

/* Mean luminance over the pixels of [x0, x1) x [y0, y1). */
static inline double region_luminance(const cvk_image* im, int x0, int y0, int x1, int y1)
{
    double sum = 0.0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++)
            sum += luminance(pixel(im, x, y));
    return sum / ((double)(x1 - x0) * (y1 - y0));
}

/* Where p lands in a width x height image of the view, pixels from the top left corner. */
static inline void project_point(const cvk_render_view* v, const double p[3], double width, double height, double out[2])
{
    const float* m = v->view_proj;
    double clip[4];
    for (int k = 0; k < 4; k++)
        clip[k] = m[k] * p[0] + m[4 + k] * p[1] + m[8 + k] * p[2] + m[12 + k];
    out[0] = (clip[0] / clip[3] * 0.5 + 0.5) * width;
    out[1] = (clip[1] / clip[3] * 0.5 + 0.5) * height;
}

#endif
