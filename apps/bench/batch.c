/* batch: many small cloths at once. The scene (or the built-in napkin) is repeated N times by
   its "instances" block (instances.count = N, docs/scene-format.md) for each N of --counts;
   every copy steps in the same dispatches, so the dispatches per frame stay what one copy
   needs and the device fills up with N. Reports wall and GPU time per frame, steps per second
   (cloth substeps: copies × substeps per second of wall time) and particle steps per second
   against N, on whatever device it runs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "plot.h"

static const char* const columns[] = {
    "count", "cloths", "particles", "substeps", "dispatches_per_frame", "frames", "wall_ms",
    "wall_ms_min", "wall_ms_max", "frame_ms", "ms_per_copy", "copy_steps_per_s",
    "particle_steps_per_s",
};

/* A 16 × 16 napkin hanging from two corners: 8 substeps of 1/480 s, one local step of four
   rbgs sweeps, tethers; copies 0.5 m apart along x. */
static const char napkin[] =
    "{\"name\": \"napkin\", \"dt\": 0.00208333333, \"substeps\": 8, \"frames\": 60,"
    " \"solver\": {\"outer_iterations\": 1, \"inner_iterations\": 4, \"omega\": 1.5},"
    " \"cloths\": [{\"name\": \"napkin\", \"grid\": [16, 16], \"size\": [0.3, 0.3],"
    " \"origin\": [-0.15, 1.0, -0.15], \"mass\": 0.02,"
    " \"stiffness\": {\"structural\": 1e4, \"shear\": 1e3}, \"pins\": [[0, 0], [15, 0]],"
    " \"tethers\": 1}],"
    " \"instances\": {\"count\": 1, \"spacing\": [0.5, 0, 0]}}";

const char* bench_batch_builtin(void)
{
    return napkin;
}

static const uint32_t default_counts[] = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048,
                                          4096, 8192};

/* The scene with instances.count = n: the file (or the built-in napkin) read again with the
   tool's --set items and one more. NULL after printing the one line. */
static cvk_scene* load_copies(const bench* b, uint32_t n)
{
    const app_overrides* set = &b->o->overrides;
    const char** items = calloc(set->count + 1, sizeof *items);
    char count[48];
    snprintf(count, sizeof count, "instances.count=%u", n);
    if (!items) {
        app_error("clothvk-bench", "out of host memory");
        return NULL;
    }
    if (set->count)
        memcpy(items, set->items, set->count * sizeof *items);
    items[set->count] = count;
    cvk_scene* scene = NULL;
    cvk_error err;
    cvk_result r = b->o->scene_path
                       ? cvk_scene_load(b->o->scene_path, items, set->count + 1, &scene, &err)
                       : cvk_scene_parse(napkin, "built-in napkin", items, set->count + 1, &scene,
                                         &err);
    free(items);
    if (r != CVK_SUCCESS) {
        bench_fail(&err);
        return NULL;
    }
    return scene;
}

typedef struct point {
    bench_timing wall, gpu;
    cvk_sim_stats timing;
    uint64_t particles;
    uint32_t cloths, substeps;
} point;

/* Warm-up frames, then --frames timed one by one. false after printing why. */
static bool run_count(bench* b, uint32_t n, point* out)
{
    cvk_scene* file = load_copies(b, n);
    if (!file)
        return false;
    const cvk_scene_desc* scene = cvk_scene_get_desc(file);
    cvk_sim* sim = NULL;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = scene;
    cvk_error err;
    if (cvk_sim_create(b->ctx, &desc, &sim, &err) != CVK_SUCCESS) {
        app_error("clothvk-bench", "%s: %s", b->o->scene_path ? b->o->scene_path : "built-in napkin",
                  err.message);
        cvk_scene_destroy(file);
        return false;
    }
    uint32_t frames = b->o->frames;
    double* wall = calloc(frames, sizeof *wall);
    double* gpu = calloc(frames, sizeof *gpu);
    bool ok = wall && gpu;
    uint32_t timed = 0, measured = 0;
    for (uint32_t f = 0; ok && f < b->o->warmup + frames; f++) {
        double t0 = app_now_ms();
        ok = cvk_sim_step(sim, 1, &err) == CVK_SUCCESS;
        double elapsed = app_now_ms() - t0;
        if (!ok) {
            bench_fail(&err);
            break;
        }
        cvk_sim_get_timing(sim, &out->timing);
        if (f < b->o->warmup)
            continue;
        wall[timed++] = elapsed;
        if (out->timing.gpu_ms_per_frame >= 0.0)
            gpu[measured++] = out->timing.gpu_ms_per_frame;
    }
    if (ok) {
        out->wall = bench_timing_of(wall, timed);
        out->gpu = bench_timing_of(gpu, measured);
        out->particles = cvk_sim_particle_count(sim);
        out->cloths = scene->cloth_count;
        out->substeps = scene->substeps;
    } else if (!wall || !gpu) {
        app_error("clothvk-bench", "out of host memory");
    }
    free(wall);
    free(gpu);
    cvk_sim_destroy(sim);
    cvk_scene_destroy(file);
    return ok;
}

static void add_row(bench* b, uint32_t n, const point* p)
{
    bench_table* t = &b->table;
    double per_s = 1000.0 / p->wall.median; /* frames per second of wall time */
    bench_table_row(t);
    bench_table_int(t, "count", n);
    bench_table_int(t, "cloths", p->cloths);
    bench_table_int(t, "particles", p->particles);
    bench_table_int(t, "substeps", p->substeps);
    bench_table_int(t, "dispatches_per_frame", p->timing.dispatches_per_frame);
    bench_table_int(t, "frames", b->o->frames);
    bench_table_num(t, "wall_ms", p->wall.median);
    bench_table_num(t, "wall_ms_min", p->wall.min);
    bench_table_num(t, "wall_ms_max", p->wall.max);
    bench_table_num(t, "frame_ms", p->gpu.median);
    bench_table_num(t, "ms_per_copy", p->wall.median / n);
    bench_table_num(t, "copy_steps_per_s", (double)n * p->substeps * per_s);
    bench_table_num(t, "particle_steps_per_s", (double)p->particles * p->substeps * per_s);
}

static void write_plot(bench* b)
{
    bench_text* t = &b->plot;
    bench_plot_styles(t);
    bench_text_add(t, "set multiplot layout 1,2 title \"batch: N copies of %s on %s\"\n"
                      "set logscale xy\nset xlabel \"copies N\"\nset key top left\n",
                   b->scene_name, b->device);
    bench_text_add(t, "set title \"wall time per frame\"\nset ylabel \"ms\"\n"
                      "plot \"batch.csv\" using \"count\":\"wall_ms\" with linespoints "
                      "linestyle 1 title \"wall\", \"batch.csv\" using \"count\":\"frame_ms\" "
                      "with linespoints linestyle 2 title \"GPU (timestamps)\"\n");
    bench_text_add(t, "set title \"throughput\"\nset ylabel \"per second\"\n"
                      "plot \"batch.csv\" using \"count\":\"particle_steps_per_s\" with "
                      "linespoints linestyle 1 title \"particle steps\", \"batch.csv\" using "
                      "\"count\":\"copy_steps_per_s\" with linespoints linestyle 2 title "
                      "\"cloth steps\"\n");
    bench_text_add(t, "unset multiplot\n");
}

static const uint32_t* counts_of(const bench_options* o, uint32_t* count)
{
    *count = o->count_count ? o->count_count : sizeof default_counts / sizeof default_counts[0];
    return o->count_count ? o->counts : default_counts;
}

int bench_batch_check(const bench_options* o)
{
    uint32_t count;
    const uint32_t* counts = counts_of(o, &count);
    bench b = {.o = o};
    cvk_scene* largest = load_copies(&b, counts[count - 1]); /* --counts is sorted */
    cvk_scene_destroy(largest);
    return largest ? APP_EXIT_OK : APP_EXIT_BAD_INPUT;
}

/* The largest count fits the device (a count past its limits is bad input, found before
   anything is measured or written). */
int bench_batch_fits(bench* b)
{
    uint32_t count;
    const uint32_t* counts = counts_of(b->o, &count);
    cvk_scene* file = load_copies(b, counts[count - 1]);
    if (!file)
        return APP_EXIT_BAD_INPUT;
    cvk_sim* sim = NULL;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = cvk_scene_get_desc(file);
    desc.timing = -1;
    cvk_error err;
    cvk_result r = cvk_sim_create(b->ctx, &desc, &sim, &err);
    cvk_sim_destroy(sim);
    cvk_scene_destroy(file);
    if (r == CVK_SUCCESS)
        return APP_EXIT_OK;
    app_error("clothvk-bench", "%s: %s", b->o->scene_path ? b->o->scene_path : "built-in napkin",
              err.message);
    return r == CVK_ERROR_INVALID_ARGUMENT || r == CVK_ERROR_DEVICE_LIMIT ? APP_EXIT_BAD_INPUT
                                                                          : APP_EXIT_FAILURE;
}

int bench_batch(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    uint32_t count;
    const uint32_t* counts = counts_of(b->o, &count);
    printf("%u timed frames a count after %u warm-up frames\n%8s %10s %6s %10s %10s %12s %14s\n",
           b->o->frames, b->o->warmup, "copies", "particles", "disp.", "wall ms", "GPU ms",
           "cloth st/s", "particle st/s");
    for (uint32_t i = 0; i < count; i++) {
        point p = {0};
        if (!run_count(b, counts[i], &p))
            return APP_EXIT_FAILURE;
        add_row(b, counts[i], &p);
        uint32_t row = b->table.rows - 1;
        printf("%8u %10llu %6u %10.3f %10.3f %12.4g %14.4g\n", counts[i],
               (unsigned long long)p.particles, p.timing.dispatches_per_frame, p.wall.median,
               p.gpu.median, bench_table_get(&b->table, row, "copy_steps_per_s"),
               bench_table_get(&b->table, row, "particle_steps_per_s"));
        fflush(stdout);
    }
    write_plot(b);
    return APP_EXIT_OK;
}
