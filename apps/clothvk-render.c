/* clothvk-render: simulates a scene and writes every K-th frame as a PNG image. While the
   device simulates and draws the next image, a second thread encodes and writes the last one,
   so PNG encoding costs little wall time where a core is free. */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bake.h"
#include "clothvk.h"
#include "common.h"
#include "video.h"

static const char tool[] = "clothvk-render";

static void usage(FILE* out)
{
    fprintf(out,
            "usage: clothvk-render SCENE -o DIR [--frames N] [--size WxH] [--every K]\n"
            "                      [--set key.path=value]... [--serial] [--quiet]\n"
            "       clothvk-render SCENE -o DIR --from BAKE [--frames A:B] [--size WxH] ...\n"
            "  -o DIR         folder for frame_0000.png, frame_0001.png, ... (created if missing)\n"
            "  --frames N     frames to simulate (default: the scene's \"frames\")\n"
            "  --from BAKE    draw frames from a bake (clothvk-sim --bake) without simulating:\n"
            "                 --frames A:B draws frames A to B, each named as a direct render\n"
            "                 with --every 1 names it (default: every frame the bake holds)\n"
            "  --every K      draw the state after i*K frames for every i*K <= N: the start,\n"
            "                 then every K-th simulated frame (default 1)\n"
            "  --size WxH     image size in pixels (default: the scene's render.size, 1280x720)\n"
            "  --set k=v      override a scene key by its dotted JSON path, value as JSON\n"
            "  --video FILE   also encode the images into a video with ffmpeg (FILE.mp4, at the\n"
            "                 scene's frame rate over K); -o may then be left out\n"
            "  --serial       write each image before simulating the next (for timing)\n"
            "  --quiet        no progress line and no summary\n"
            "  --version      print the version and exit\n"
            "environment: CLOTHVK_DEVICE (device index or name), CLOTHVK_VALIDATION=1\n");
}

typedef struct options {
    const char* scene;
    const char* out;
    bool frames_set;
    uint32_t frames;
    uint32_t every;
    bool size_set;
    uint32_t size[2];
    const char* size_text;
    app_overrides overrides;
    bool serial;
    bool quiet;
    const char* from;   /* --from BAKE */
    bool range_set;     /* --frames A:B */
    uint32_t range[2];
    bool every_set;
    const char* video;
} options;

/* "A:B", whole numbers with A <= B. */
static bool parse_range(const char* text, uint32_t out[2])
{
    const char* colon = strchr(text, ':');
    char first[16];
    size_t n = colon ? (size_t)(colon - text) : 0;
    if (!colon || n == 0 || n >= sizeof first)
        return false;
    memcpy(first, text, n);
    first[n] = '\0';
    return app_parse_u32(first, 0, 100000000, &out[0]) &&
           app_parse_u32(colon + 1, 0, 100000000, &out[1]) && out[0] <= out[1];
}

/* "1280x720": two whole numbers of at least 1. The upper limit is the device's. */
static bool parse_size(const char* text, uint32_t out[2])
{
    const char* x = strchr(text, 'x');
    if (!x || x == text || strchr(x + 1, 'x'))
        return false;
    char width[16];
    size_t n = (size_t)(x - text);
    if (n >= sizeof width)
        return false;
    memcpy(width, text, n);
    width[n] = '\0';
    return app_parse_u32(width, 1, UINT32_MAX, &out[0]) && app_parse_u32(x + 1, 1, UINT32_MAX, &out[1]);
}

/* --from draws the frames a bake holds: --frames A:B picks them, a count or --every has no
   meaning there. */
static int check_from(const options* o)
{
    if (o->range_set && !o->from) {
        app_error(tool, "--frames A:B needs --from BAKE (without it --frames is a count)");
        return APP_EXIT_BAD_INPUT;
    }
    if (o->from && (o->frames_set || o->every_set)) {
        app_error(tool, "--from: give the frames as --frames A:B (%s has no meaning here)",
                  o->frames_set ? "--frames N" : "--every");
        return APP_EXIT_BAD_INPUT;
    }
    return APP_EXIT_OK;
}

/* --frames: a count, or A:B with --from. */
static int take_frames(void* user, const char* option, const char* value)
{
    options* o = user;
    if (value && strchr(value, ':')) {
        if (!parse_range(value, o->range)) {
            app_error(tool, "%s: expected A:B, whole numbers with A <= B, got %s", option, value);
            return APP_EXIT_BAD_INPUT;
        }
        o->range_set = true;
        return APP_EXIT_OK;
    }
    if (!app_option_u32(tool, option, value, 1, 100000000, &o->frames))
        return APP_EXIT_BAD_INPUT;
    o->frames_set = true;
    return APP_EXIT_OK;
}

static int take_size(void* user, const char* option, const char* value)
{
    options* o = user;
    if (!value || !parse_size(value, o->size)) {
        app_error(tool, "%s: expected WIDTHxHEIGHT in pixels, each at least 1, got %s", option,
                  value ? value : "nothing");
        return APP_EXIT_BAD_INPUT;
    }
    o->size_set = true;
    o->size_text = value;
    return APP_EXIT_OK;
}

/* The outputs and the options that only make sense together, checked before any work. */
static int check_options(const options* o)
{
    if (!o->out && !o->video) {
        app_error(tool, "no output folder given (-o DIR)");
        return APP_EXIT_BAD_INPUT;
    }
    int status = check_from(o);
    if (status != APP_EXIT_OK)
        return status;
    if (o->video && o->from) {
        app_error(tool, "--video and --from: a video is made while simulating; render the bake's "
                  "frames to PNGs and encode those");
        return APP_EXIT_BAD_INPUT;
    }
    if (o->video && (!app_video_available(tool) || !app_video_name_ok(tool, o->video)))
        return APP_EXIT_BAD_INPUT;
    return APP_EXIT_OK;
}

/* Returns APP_EXIT_OK or APP_EXIT_BAD_INPUT; `done` is set for --help and --version. */
static int parse_args(int argc, char** argv, options* o, bool* done)
{
    const app_option table[] = {
        {"-o", "--output", APP_OPTION_PATH, .path = &o->out, .expected = "an output folder"},
        {"--frames", NULL, APP_OPTION_OTHER, .take = take_frames},
        {"--from", NULL, APP_OPTION_PATH, .path = &o->from, .expected = "a bake folder"},
        {"--every", NULL, APP_OPTION_U32, .number = &o->every, .min = 1, .max = 100000000,
         .flag = &o->every_set},
        {"--size", NULL, APP_OPTION_OTHER, .take = take_size},
        {"--set", NULL, APP_OPTION_SET, .overrides = &o->overrides},
        {"--video", NULL, APP_OPTION_PATH, .path = &o->video,
         .expected = "a file name such as clip.mp4"},
        {"--serial", NULL, APP_OPTION_FLAG, .flag = &o->serial},
        {"--quiet", "-q", APP_OPTION_FLAG, .flag = &o->quiet},
    };
    app_command_line line = {tool, usage, table, sizeof table / sizeof table[0], o, NULL};
    o->every = 1;
    int status = app_read_command_line(&line, argc, argv, &o->scene, done);
    return status != APP_EXIT_OK || *done ? status : check_options(o);
}

/* ---- the output folder ---------------------------------------------------------------- */

/* ---- the writer thread: encodes and writes images while the device works on the next ---- */

#define SLOTS 2

typedef struct writer {
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t changed;
    const char* folder;
    uint32_t width, height;
    uint8_t* pixels[SLOTS];
    uint32_t frame[SLOTS];     /* image number of each queued slot */
    bool full[SLOTS];
    uint32_t next_in, next_out;
    bool closing;
    bool failed;
    char message[600];
    double png_ms;             /* summed over written images */
    uint32_t written;
} writer;

static void* writer_main(void* user)
{
    writer* w = user;
    size_t len = strlen(w->folder) + 32;
    char* path = malloc(len);
    pthread_mutex_lock(&w->lock);
    for (;;) {
        while (!w->full[w->next_out] && !w->closing)
            pthread_cond_wait(&w->changed, &w->lock);
        if (!w->full[w->next_out])
            break;
        uint32_t slot = w->next_out;
        pthread_mutex_unlock(&w->lock);

        cvk_image image = {w->pixels[slot], w->width, w->height, 4 * w->width};
        cvk_error err;
        double t0 = app_now_ms();
        cvk_result r = CVK_ERROR_OUT_OF_MEMORY;
        if (path) {
            snprintf(path, len, "%s/frame_%04u.png", w->folder, w->frame[slot]);
            r = cvk_image_write_png(&image, path, &err);
        } else {
            snprintf(err.message, sizeof err.message, "out of memory");
        }
        double ms = app_now_ms() - t0;

        pthread_mutex_lock(&w->lock);
        if (r != CVK_SUCCESS && !w->failed) {
            w->failed = true;
            snprintf(w->message, sizeof w->message, "%s", err.message);
        }
        w->png_ms += ms;
        w->written += r == CVK_SUCCESS;
        w->full[slot] = false;
        w->next_out = (slot + 1) % SLOTS;
        pthread_cond_broadcast(&w->changed);
    }
    pthread_mutex_unlock(&w->lock);
    free(path);
    return NULL;
}

static bool writer_start(writer* w, const char* folder, uint32_t width, uint32_t height)
{
    memset(w, 0, sizeof *w);
    w->folder = folder;
    w->width = width;
    w->height = height;
    for (int i = 0; i < SLOTS; i++) {
        w->pixels[i] = malloc((size_t)width * height * 4);
        if (!w->pixels[i])
            return false;
    }
    pthread_mutex_init(&w->lock, NULL);
    pthread_cond_init(&w->changed, NULL);
    if (pthread_create(&w->thread, NULL, writer_main, w) != 0) {
        pthread_cond_destroy(&w->changed);
        pthread_mutex_destroy(&w->lock);
        return false;
    }
    return true;
}

/* Copies the image into a free slot (waiting for one) and queues it; false once writing failed. */
static bool writer_push(writer* w, const cvk_image* image, uint32_t frame)
{
    pthread_mutex_lock(&w->lock);
    while (w->full[w->next_in] && !w->failed)
        pthread_cond_wait(&w->changed, &w->lock);
    bool ok = !w->failed;
    uint32_t slot = w->next_in;
    pthread_mutex_unlock(&w->lock);
    if (!ok)
        return false;
    for (uint32_t y = 0; y < image->height; y++)
        memcpy(w->pixels[slot] + (size_t)y * 4 * w->width, image->pixels + (size_t)y * image->row_bytes,
               (size_t)4 * w->width);
    pthread_mutex_lock(&w->lock);
    w->frame[slot] = frame;
    w->full[slot] = true;
    w->next_in = (slot + 1) % SLOTS;
    pthread_cond_broadcast(&w->changed);
    pthread_mutex_unlock(&w->lock);
    return true;
}

/* Waits until every queued image is written. */
static void writer_drain(writer* w)
{
    pthread_mutex_lock(&w->lock);
    for (int i = 0; i < SLOTS; i++)
        while (w->full[i] && !w->failed)
            pthread_cond_wait(&w->changed, &w->lock);
    pthread_mutex_unlock(&w->lock);
}

/* Writes what is queued and stops the thread; returns false if any image failed. */
static bool writer_finish(writer* w)
{
    pthread_mutex_lock(&w->lock);
    w->closing = true;
    pthread_cond_broadcast(&w->changed);
    pthread_mutex_unlock(&w->lock);
    pthread_join(w->thread, NULL);
    pthread_cond_destroy(&w->changed);
    pthread_mutex_destroy(&w->lock);
    return !w->failed;
}

static void writer_free(writer* w)
{
    for (int i = 0; i < SLOTS; i++)
        free(w->pixels[i]);
}

/* ---- progress ------------------------------------------------------------------------- */

typedef struct totals {
    uint32_t images;
    double sim_ms, render_ms, wall_ms;
    double mesh_ms, shadow_ms, ao_ms, lit_ms, composite_ms, readback_ms, overlay_ms;
    uint32_t timed;
} totals;

static void format_time(double seconds, char* out, size_t size)
{
    long s = (long)(seconds + 0.5);
    if (s >= 3600)
        snprintf(out, size, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    else
        snprintf(out, size, "%ld:%02ld", s / 60, s % 60);
}

static void progress(const totals* t, uint32_t count, bool tty, double* last_print)
{
    double now = app_now_ms();
    bool last = t->images == count;
    /* A terminal gets one line rewritten in place; a log gets a line every few seconds. */
    if (!tty && !last && now - *last_print < 5000.0)
        return;
    if (!tty && last)
        return;
    *last_print = now;
    char left[32];
    format_time(t->wall_ms / t->images * (count - t->images) * 1e-3, left, sizeof left);
    fprintf(stderr, "%sframe %u/%u: simulation %.1f ms, render %.1f ms per image, %s left%s", tty ? "\r" : "",
            t->images, count, t->sim_ms / t->images, t->render_ms / t->images, left, tty ? "\033[K" : "\n");
    if (tty && last)
        fputc('\n', stderr);
    fflush(stderr);
}

/* ---- the run -------------------------------------------------------------------------- */

typedef struct run_state {
    const options* o;
    const cvk_scene_desc* scene;
    const char* scene_json; /* cvk_scene_get_json, for --from's check */
    cvk_context* ctx;
    cvk_sim* sim;
    cvk_mesh* mesh;
    cvk_renderer* renderer;
    app_bake* bake;         /* --from: frames come from here */
    uint32_t first, step;   /* image i is frame first + i * step */
    app_video* video; /* NULL without --video */
} run_state;

static int check_size(const run_state* s, const cvk_render_desc* render)
{
    cvk_context_info info = cvk_context_get_info(s->ctx);
    if (!info.graphics) {
        app_error(tool, "%s cannot draw: its queue has no graphics", info.device_name);
        return APP_EXIT_FAILURE;
    }
    if (render->size[0] <= info.max_image_size && render->size[1] <= info.max_image_size)
        return APP_EXIT_OK;
    if (s->o->size_set)
        app_error(tool, "--size %s: %s draws at most %u x %u pixels", s->o->size_text, info.device_name,
                  info.max_image_size, info.max_image_size);
    else
        app_error(tool, "%s: render.size: %u x %u pixels is more than %s allows (%u x %u)", s->o->scene,
                  render->size[0], render->size[1], info.device_name, info.max_image_size, info.max_image_size);
    return APP_EXIT_BAD_INPUT;
}

static int create_objects(run_state* s, const cvk_render_desc* render)
{
    cvk_error err;
    cvk_sim_desc sim_desc = cvk_default_sim_desc();
    sim_desc.scene = s->scene;
    cvk_result r = cvk_sim_create(s->ctx, &sim_desc, &s->sim, &err);
    if (r == CVK_SUCCESS)
        app_print_notes(tool, s->sim);
    if (r == CVK_SUCCESS)
        r = cvk_mesh_create(s->sim, NULL, &s->mesh, &err);
    if (r == CVK_SUCCESS)
        r = cvk_renderer_create(s->mesh, render, &s->renderer, &err);
    if (r != CVK_SUCCESS) {
        app_error(tool, "%s: %s", s->o->scene, err.message);
        return app_creation_status(r);
    }
    return APP_EXIT_OK;
}

static void add_timing(const cvk_renderer* renderer, totals* t)
{
    cvk_render_timing rt = cvk_renderer_get_timing(renderer);
    t->overlay_ms += rt.overlay_ms;
    if (rt.total_ms < 0)
        return;
    t->timed++;
    t->mesh_ms += rt.mesh_ms;
    t->shadow_ms += rt.shadow_ms;
    t->ao_ms += rt.ao_ms;
    t->lit_ms += rt.lit_ms - rt.composite_ms;
    t->composite_ms += rt.composite_ms;
    t->readback_ms += rt.readback_ms;
}

static int render_frames(run_state* s, writer* w, uint32_t count, totals* t)
{
    cvk_error err;
    bool tty = !s->o->quiet && isatty(STDERR_FILENO);
    double last_print = app_now_ms();
    /* Ctrl-C stops after the image being written is complete: no image is left half-written. */
    for (uint32_t i = 0; i < count && !app_interrupted(); i++) {
        double t0 = app_now_ms();
        uint32_t frame = s->first + i * s->step;
        if (s->bake) {
            int status = app_bake_load(s->bake, frame);
            if (status != APP_EXIT_OK)
                return status;
        } else if (i > 0) {
            cvk_result r = cvk_sim_step(s->sim, s->o->every, &err);
            if (r != CVK_SUCCESS) { /* the frames drawn so far are complete and stay */
                app_error(tool, "%s", err.message);
                return r == CVK_ERROR_DIVERGED ? APP_EXIT_DIVERGED : APP_EXIT_FAILURE;
            }
        }
        double t1 = app_now_ms();
        /* A keyframed camera goes where it is at this frame's simulated time. */
        double simulated = (double)(s->bake ? frame : i * s->o->every);
        cvk_renderer_set_time(s->renderer, simulated * s->scene->dt * s->scene->substeps);
        if (cvk_renderer_draw(s->renderer, &err) != CVK_SUCCESS) {
            app_error(tool, "%s", err.message);
            return APP_EXIT_FAILURE;
        }
        double t2 = app_now_ms();
        cvk_image image = cvk_renderer_get_image(s->renderer);
        if (s->video && !app_video_write(s->video, &image))
            return APP_EXIT_FAILURE;
        if (s->o->out && !writer_push(w, &image, s->bake ? frame : i))
            break;
        if (s->o->serial)
            writer_drain(w);
        t->images++;
        t->sim_ms += t1 - t0;
        t->render_ms += t2 - t1;
        t->wall_ms += app_now_ms() - t0;
        add_timing(s->renderer, t);
        if (!s->o->quiet)
            progress(t, count, tty, &last_print);
    }
    return APP_EXIT_OK;
}

static void print_summary(const run_state* s, const totals* t, const writer* w, uint32_t frames, double wall_ms)
{
    const cvk_render_desc* r = &s->scene->render;
    uint32_t width = s->o->size_set ? s->o->size[0] : r->size[0];
    uint32_t height = s->o->size_set ? s->o->size[1] : r->size[1];
    uint32_t last = (t->images - 1) * s->o->every;
    const char* name = s->scene->name ? s->scene->name : "scene";
    if (s->bake)
        printf("%s: %u images of %ux%u in %s (frames %u to %u from %s), %.1f s; per image: load "
               "%.1f ms, render %.1f ms", name, w->written, width, height, s->o->out, s->first,
               s->first + (t->images - 1) * s->step, s->o->from, wall_ms * 1e-3,
               t->sim_ms / t->images, t->render_ms / t->images);
    else
        printf("%s: %u images of %ux%u in %s (frames 0 to %u of %u, every %u), %.1f s; per image: "
               "simulation %.1f ms, render %.1f ms", name, w->written, width, height, s->o->out,
               last, frames, s->o->every, wall_ms * 1e-3, t->sim_ms / t->images,
               t->render_ms / t->images);
    if (t->timed)
        printf(" (mesh %.1f, shadow %.1f, lit %.1f, ao %.1f, composite %.1f, readback %.1f)", t->mesh_ms / t->timed,
               t->shadow_ms / t->timed, t->lit_ms / t->timed, t->ao_ms / t->timed, t->composite_ms / t->timed,
               t->readback_ms / t->timed);
    if (r->overlay)
        printf(", overlay %.2f ms", t->overlay_ms / t->images);
    printf(", png %.1f ms (%s); %.1f ms wall\n", w->png_ms / (w->written ? w->written : 1),
           s->o->serial ? "alone" : "beside the next image's work", wall_ms / t->images);
}

/* ---- render.fit over a sequence: one box for every image, so the camera holds still ---- */

/* The current particles added to the box lo..hi. */
static int add_particles(cvk_sim* sim, float* xyz, uint64_t n, float lo[3], float hi[3])
{
    cvk_error err;
    if (cvk_sim_read_positions(sim, xyz, n, &err) != CVK_SUCCESS) {
        app_error(tool, "%s", err.message);
        return APP_EXIT_FAILURE;
    }
    for (uint64_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], xyz[3 * i + k]);
            hi[k] = fmaxf(hi[k], xyz[3 * i + k]);
        }
    return APP_EXIT_OK;
}

/* The particles' box over every frame to be drawn: the bake's frames loaded in turn, or the
   scene simulated once before the run by a second simulation (from the same start, so the
   same frames), then handed to the renderer. One image frames its own particles. */
static int fit_sequence(run_state* s, uint32_t count)
{
    cvk_error err;
    cvk_sim* sim = s->sim;
    if (count == 1) { /* one image: its particles themselves, not their box */
        int status = s->bake ? app_bake_load(s->bake, s->first) : APP_EXIT_OK;
        if (status == APP_EXIT_OK && cvk_renderer_fit(s->renderer, NULL, NULL, &err) != CVK_SUCCESS) {
            app_error(tool, "%s", err.message);
            status = APP_EXIT_FAILURE;
        }
        return status;
    }
    if (!s->bake) {
        cvk_sim_desc desc = cvk_default_sim_desc();
        desc.scene = s->scene;
        if (cvk_sim_create(s->ctx, &desc, &sim, &err) != CVK_SUCCESS) {
            app_error(tool, "%s: %s", s->o->scene, err.message);
            return APP_EXIT_FAILURE;
        }
    }
    uint64_t n = cvk_sim_particle_count(sim);
    float* xyz = malloc((size_t)n * 3 * sizeof *xyz + 1);
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    int status = xyz ? APP_EXIT_OK : APP_EXIT_FAILURE;
    if (!xyz)
        app_error(tool, "out of memory for %llu positions", (unsigned long long)n);
    for (uint32_t i = 0; i < count && status == APP_EXIT_OK && !app_interrupted(); i++) {
        if (s->bake) {
            status = app_bake_load(s->bake, s->first + i * s->step);
        } else if (i > 0 && cvk_sim_step(sim, s->o->every, &err) != CVK_SUCCESS) {
            app_error(tool, "%s", err.message);
            status = APP_EXIT_FAILURE;
        }
        if (status == APP_EXIT_OK)
            status = add_particles(sim, xyz, n, lo, hi);
    }
    free(xyz);
    if (!s->bake)
        cvk_sim_destroy(sim);
    if (status == APP_EXIT_OK && cvk_renderer_fit(s->renderer, lo, hi, &err) != CVK_SUCCESS) {
        app_error(tool, "%s", err.message);
        status = APP_EXIT_FAILURE;
    }
    return status;
}

static int render_all(run_state* s, uint32_t frames)
{
    /* Simulating N frames draws the start and then every K-th state, the last one included:
       frames 0, K, ..., up to N (the bake's and clothvk-sim's --obj rule). */
    uint32_t count = s->bake ? frames : frames / s->o->every + 1;
    if (s->scene->render.fit && (count > 1 || s->bake)) {
        int fitted = fit_sequence(s, count);
        if (fitted != APP_EXIT_OK)
            return fitted;
    }
    cvk_image first = cvk_renderer_get_image(s->renderer);
    writer w;
    /* Without -o (a video only) the writer is given no image; its folder is never used. */
    if (!writer_start(&w, s->o->out ? s->o->out : ".", first.width, first.height)) {
        app_error(tool, "out of memory for %u x %u images", first.width, first.height);
        writer_free(&w);
        return APP_EXIT_FAILURE;
    }
    totals t = {0};
    double start = app_now_ms();
    int status = render_frames(s, &w, count, &t);
    bool written = writer_finish(&w);
    double wall = app_now_ms() - start;
    if (!written) {
        app_error(tool, "%s", w.message);
        status = APP_EXIT_FAILURE;
    } else if (app_interrupted()) {
        app_error(tool, "interrupted after %u of %u images", w.written, count);
        status = APP_EXIT_FAILURE;
    } else if (status == APP_EXIT_OK && s->video) {
        status = app_video_finish(s->video);
    }
    if (status == APP_EXIT_OK && !s->o->quiet && t.images && s->o->out)
        print_summary(s, &t, &w, frames, wall);
    if (status == APP_EXIT_OK && !s->o->quiet && s->video)
        printf("%s: video %s, %u frames of %ux%u\n", s->scene->name ? s->scene->name : "scene",
               s->o->video, s->video->frames, first.width, first.height);
    writer_free(&w);
    return status;
}

static int check_result(run_state* s)
{
    cvk_sim_stats st;
    cvk_error err;
    if (cvk_sim_get_stats(s->sim, &st, &err) != CVK_SUCCESS) {
        app_error(tool, "%s", err.message);
        return APP_EXIT_FAILURE;
    }
    if (st.nan_count) {
        app_error(tool, "%s: the simulation produced %llu non-finite coordinates", s->o->scene,
                  (unsigned long long)st.nan_count);
        return APP_EXIT_FAILURE;
    }
    return APP_EXIT_OK;
}

/* --from: the bake, checked against the scene and for every frame asked for; *frames
   becomes the number of images. */
static int open_bake(run_state* s, app_bake* bake, uint32_t* frames)
{
    const options* o = s->o;
    app_bake_desc desc = {o->scene, &o->overrides, s->scene, s->scene_json, 0, 0};
    int status = app_bake_open(bake, tool, s->sim, o->from, &desc);
    if (status != APP_EXIT_OK)
        return status;
    s->bake = bake;
    s->first = o->range_set ? o->range[0] : 0;
    s->step = o->range_set ? 1 : bake->every;
    uint32_t last = o->range_set ? o->range[1] : app_bake_last_frame(bake);
    *frames = (last - s->first) / s->step + 1;
    return app_bake_check_frames(bake, s->first, last, s->step);
}

static int run(const options* o)
{
    cvk_scene* file = NULL;
    run_state s = {.o = o, .step = 1};
    int status = app_open(tool, o->scene, &o->overrides, &file, &s.ctx);
    if (status != APP_EXIT_OK)
        return status;
    s.scene = cvk_scene_get_desc(file);
    s.scene_json = cvk_scene_get_json(file);
    cvk_render_desc render = s.scene->render;
    if (o->size_set) {
        render.size[0] = o->size[0];
        render.size[1] = o->size[1];
    }
    uint32_t frames = o->frames_set ? o->frames : s.scene->frames;
    /* Everything the input can get wrong (the device's limits included) is checked before the
       folder is made or any frame simulated. */
    status = check_size(&s, &render);
    if (status == APP_EXIT_OK)
        status = create_objects(&s, &render);
    app_bake bake = {0};
    if (status == APP_EXIT_OK && o->from)
        status = open_bake(&s, &bake, &frames);
    if (status == APP_EXIT_OK && o->out && !app_make_output_folder(tool, o->out))
        status = APP_EXIT_BAD_INPUT;
    app_video video = {.fd = -1};
    if (status == APP_EXIT_OK && o->video) {
        cvk_image first = cvk_renderer_get_image(s.renderer);
        double fps = 1.0 / ((double)s.scene->dt * s.scene->substeps * o->every);
        status = app_video_open(&video, tool, o->video, first.width, first.height, fps);
        s.video = &video;
    }
    if (status == APP_EXIT_OK)
        status = render_all(&s, frames);
    app_video_free(&video);
    if (status == APP_EXIT_OK)
        status = check_result(&s);
    app_bake_free(&bake);
    cvk_renderer_destroy(s.renderer);
    cvk_mesh_destroy(s.mesh);
    cvk_sim_destroy(s.sim);
    return app_close(tool, s.ctx, file, status);
}

int main(int argc, char** argv)
{
    options o = {0};
    bool done = false;
    int status = parse_args(argc, argv, &o, &done);
    if (status == APP_EXIT_OK && !done) {
        app_catch_interrupts();
        status = run(&o);
    }
    app_overrides_free(&o.overrides);
    return status;
}
