/* Picking and dragging — a scripted mouse drag, rendered to PNGs.

   What an interactive application does when the user clicks on the cloth and pulls, with the
   mouse replaced by a script:

       once, at the click:   a ray from the camera through the clicked pixel
                             cvk_sim_pick   the nearest particle on it (computed on the device)
       every frame:          cvk_sim_grab   where the mouse has dragged it to (a host write the
                                            frame reads: no re-recording, no round trip)
                             cvk_sim_step   the frame
                             draw, write frame_NNNN.png
       at the end:           cvk_sim_release, and the cloth swings free

   The "click" lands on the pixel where the middle of the cloth's bottom edge is seen; the drag
   pulls that particle 0.9 m out of the cloth's plane and 0.45 m down over 1.3 s, holds it,
   eases it back part of the way (a stretched elastic sheet let go at full stretch snaps up over
   its pins) and lets go. The top edge is pinned, so the cloth is stretched far past its rest
   lengths near the grabbed particle, and the scene's cloth tears (its "tearing" block) where
   a spring passes half again its rest length.

       drag OUT_DIR [FRAMES] [SCENE]

   SCENE defaults to assets/scenes/drag.json in the source tree; FRAMES to the scene's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothvk.h>

#ifndef DRAG_SCENE
#define DRAG_SCENE "assets/scenes/drag.json"
#endif

#define DRAG_START 10   /* frame the click happens at */
#define DRAG_FRAMES 80  /* frames the pull takes */
#define HOLD_FRAMES 10  /* frames it is held still */
#define BACK_FRAMES 20  /* frames it is eased back to BACK_TO of the pull, then released */
#define BACK_TO 0.4f
#define HAND_RADIUS 0.1f /* m: the particles within it of the picked one are held with it */
#define RELEASE (DRAG_START + DRAG_FRAMES + HOLD_FRAMES + BACK_FRAMES)

static const float pull[3] = {0.15f, -0.45f, 0.9f}; /* m, from where the particle was picked */

/* The pixel where a world point is seen (view_proj: column-major, Vulkan clip space). */
static void project(const cvk_render_view* v, const float p[3], float w, float h, float px[2])
{
    const float* m = v->view_proj;
    float clip[4];
    for (int r = 0; r < 4; r++)
        clip[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    px[0] = (clip[0] / clip[3] + 1.0f) * 0.5f * w;
    px[1] = (clip[1] / clip[3] + 1.0f) * 0.5f * h; /* Vulkan's y points down, as rows do */
}

static void normalize(float v[3])
{
    float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++)
        v[k] /= l;
}

static void cross(const float a[3], const float b[3], float out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* The ray from the eye through pixel (x, y): what a click there means. */
static void pixel_ray(const cvk_render_view* v, float x, float y, float w, float h, float dir[3])
{
    float forward[3], right[3], up[3];
    for (int k = 0; k < 3; k++)
        forward[k] = v->target[k] - v->eye[k];
    normalize(forward);
    cross(forward, v->up, right);
    normalize(right);
    cross(right, forward, up);
    float t = tanf(v->fov_y * 0.5f * 3.14159265f / 180.0f);
    float sx = (2.0f * x / w - 1.0f) * t * w / h, sy = (1.0f - 2.0f * y / h) * t;
    for (int k = 0; k < 3; k++)
        dir[k] = forward[k] + sx * right[k] + sy * up[k];
}

static float smoothstep(float s)
{
    s = s < 0.0f ? 0.0f : s > 1.0f ? 1.0f : s;
    return s * s * (3.0f - 2.0f * s);
}

/* How far along the pull the hand is at the end of frame f (0 at the click, 1 fully out). */
static float hand(uint32_t f)
{
    float out = smoothstep((float)(f + 1 - DRAG_START) / DRAG_FRAMES);
    float back = smoothstep((float)(f + 1 - (RELEASE - BACK_FRAMES)) / BACK_FRAMES);
    return out - back * (1.0f - BACK_TO);
}

static int fail(const char* what, const cvk_error* err)
{
    fprintf(stderr, "drag: %s: %s\n", what, err->message);
    return 1;
}

/* What the frames of the script share. */
typedef struct drag {
    cvk_sim* sim;
    cvk_renderer* renderer;
    cvk_render_view view;   /* the camera the click is made with */
    float w, h;             /* image size, pixels */
    cvk_pick_result picked;
    float start[3];         /* m: where the picked particle was at the click */
} drag;

/* The click: on the pixel where the middle of the bottom edge is seen now. */
static bool click(drag* d, cvk_error* err)
{
    cvk_cloth_info cloth = cvk_sim_get_cloth(d->sim, 0);
    uint64_t n = cvk_sim_particle_count(d->sim);
    float* xyz = malloc(3 * n * sizeof(float));
    if (!xyz || cvk_sim_read_positions(d->sim, xyz, n, err) != CVK_SUCCESS) {
        free(xyz);
        fail("read", err);
        return false;
    }
    uint32_t side = (uint32_t)sqrt((double)cloth.particle_count); /* a square grid */
    const float* aim = &xyz[3 * (cloth.first_particle + side * (side - 1) + side / 2)];
    float px[2], dir[3];
    project(&d->view, aim, d->w, d->h, px);
    free(xyz);
    pixel_ray(&d->view, px[0], px[1], d->w, d->h, dir);
    if (cvk_sim_pick(d->sim, d->view.eye, dir, 0.01f, &d->picked, err) != CVK_SUCCESS) {
        fail("pick", err);
        return false;
    }
    cvk_pick_result* picked = &d->picked;
    printf("click at pixel (%.0f, %.0f): %s", px[0], px[1], picked->hit ? "" : "missed\n");
    if (picked->hit)
        printf("cloth %u particle %u, %.3f m from the eye, at [%.3f, %.3f, %.3f]\n",
               picked->particle.cloth, picked->particle.index, picked->distance,
               picked->position[0], picked->position[1], picked->position[2]);
    memcpy(d->start, picked->position, sizeof d->start);
    return true;
}

static bool get_stats(const drag* d, cvk_sim_stats* stats, cvk_error* err)
{
    if (cvk_sim_get_stats(d->sim, stats, err) == CVK_SUCCESS)
        return true;
    fail("stats", err);
    return false;
}

/* The hand in frame f: the click, the pull along the script, the release. */
static bool move_hand(drag* d, uint32_t f, cvk_error* err)
{
    if (f == DRAG_START && !click(d, err))
        return false;
    cvk_sim_stats held;
    if (d->picked.hit && f >= DRAG_START && f < RELEASE) {
        float s = hand(f), target[3];
        for (int k = 0; k < 3; k++)
            target[k] = d->start[k] + s * pull[k];
        if (cvk_sim_grab_within(d->sim, d->picked.particle, HAND_RADIUS, target, err) != CVK_SUCCESS) {
            fail("grab", err);
            return false;
        }
    } else if (d->picked.hit && f == RELEASE) {
        if (!get_stats(d, &held, err))
            return false;
        cvk_sim_release(d->sim);
        printf("released at frame %u; the largest spring stretch then was %.0f%% (99th "
               "percentile %.0f%%), %llu springs torn\n", f, 100.0 * held.max_stretch,
               100.0 * held.p99_stretch, (unsigned long long)held.torn_springs);
    }
    if (d->picked.hit && f == DRAG_START + DRAG_FRAMES + HOLD_FRAMES) {
        if (!get_stats(d, &held, err))
            return false;
        printf("fully pulled (frame %u): the largest spring stretch is %.0f%% (99th "
               "percentile %.0f%%), %llu springs torn\n", f, 100.0 * held.max_stretch,
               100.0 * held.p99_stretch, (unsigned long long)held.torn_springs);
    }
    return true;
}

/* The frame stepped and drawn, written as OUT_DIR/frame_NNNN.png. */
static bool step_and_draw(drag* d, const char* out_dir, uint32_t f, cvk_error* err)
{
    if (cvk_sim_step(d->sim, 1, err) != CVK_SUCCESS ||
        cvk_renderer_draw(d->renderer, err) != CVK_SUCCESS) {
        fail("frame", err);
        return false;
    }
    cvk_image image = cvk_renderer_get_image(d->renderer);
    char path[4096];
    snprintf(path, sizeof path, "%s/frame_%04u.png", out_dir, f);
    if (cvk_image_write_png(&image, path, err) != CVK_SUCCESS) {
        fail("png", err);
        return false;
    }
    return true;
}

int main(int argc, char** argv)
{
    if (argc < 2 || argc > 4) {
        fprintf(stderr, "usage: drag OUT_DIR [FRAMES] [SCENE]\n");
        return 2;
    }
    const char* out_dir = argv[1];
    const char* scene_path = argc > 3 ? argv[3] : DRAG_SCENE;
    cvk_error err;
    cvk_context* ctx = NULL;
    cvk_scene* scene = NULL;
    cvk_mesh* mesh = NULL;
    drag d = {0};
    int status = 1;
    cvk_context_desc ctx_desc = cvk_default_context_desc();
    if (cvk_context_create(&ctx_desc, &ctx, &err) != CVK_SUCCESS)
        return fail("context", &err);
    if (cvk_scene_load(scene_path, NULL, 0, &scene, &err) != CVK_SUCCESS) {
        fprintf(stderr, "drag: %s\n", err.message);
        cvk_context_destroy(ctx);
        return 2;
    }
    const cvk_scene_desc* desc = cvk_scene_get_desc(scene);
    uint32_t frames = argc > 2 ? (uint32_t)strtoul(argv[2], NULL, 10) : desc->frames;
    /* .grab: the frame has the grab pass from the start (cvk_sim_grab would add it otherwise). */
    cvk_sim_desc sim_desc = cvk_default_sim_desc();
    sim_desc.scene = desc;
    sim_desc.grab = true;
    if (cvk_sim_create(ctx, &sim_desc, &d.sim, &err) != CVK_SUCCESS ||
        cvk_mesh_create(d.sim, NULL, &mesh, &err) != CVK_SUCCESS ||
        cvk_renderer_create(mesh, &desc->render, &d.renderer, &err) != CVK_SUCCESS) {
        fail("setup", &err);
        goto done;
    }
    d.view = cvk_renderer_get_view(d.renderer);
    d.w = (float)desc->render.size[0];
    d.h = (float)desc->render.size[1];
    for (uint32_t f = 0; f < frames; f++)
        if (!move_hand(&d, f, &err) || !step_and_draw(&d, out_dir, f, &err))
            goto done;
    cvk_sim_stats stats;
    if (!get_stats(&d, &stats, &err))
        goto done;
    printf("%u frames in %s; at the end: largest spring stretch %.0f%%, %llu NaN\n", frames,
           out_dir, 100.0 * stats.max_stretch, (unsigned long long)stats.nan_count);
    status = 0;
done:
    cvk_renderer_destroy(d.renderer);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(d.sim);
    cvk_scene_destroy(scene);
    if (status == 0 && cvk_context_validation_message_count(ctx) > 0) {
        fprintf(stderr, "drag: %u validation messages\n",
                cvk_context_validation_message_count(ctx));
        status = 1;
    }
    cvk_context_destroy(ctx);
    return status;
}
