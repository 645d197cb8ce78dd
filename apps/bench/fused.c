/* fused: dispatches and time per frame with rbgs's sweeps unfused (solver.fuse off), fused
   (on: every sweep of a substep in one dispatch, a workgroup a copy) with the iterate in shared
   memory where it fits (cvk_sim_desc.fused_shared_memory 1) and fused in global memory (-1), in
   one sitting: --repeat rounds, each running the three in that order, so a noisy machine loads
   them alike. A run is
   --warmup untimed frames (pipelines compile on the first), then --frames timed ones (default
   30): the wall time of cvk_sim_step over them, and the GPU time of the last frame. Both runs of
   a round end on positions that must be the same bits (the fused sweeps do the same operations
   in the same order); a round where they differ fails the experiment. The summary gives each
   mode's median and what solver.fuse auto picks on this device. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "core/clock.h"
#include "plot.h"

static const char* const columns[] = {
    "round", "fuse", "frames", "dispatches_per_frame", "wall_ms_per_frame", "gpu_ms_per_frame",
    "same_bits",
};

#define DEFAULT_FRAMES 30u

typedef struct run_result {
    uint32_t dispatches;
    double wall_ms, gpu_ms;
    uint64_t hash;
    char plan_line[160]; /* the solver line of the plan */
} run_result;

static uint64_t fnv1a64(const float* data, size_t count)
{
    const unsigned char* p = (const unsigned char*)data;
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < count * sizeof *data; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

/* The line of the plan's description that starts with "solver:". */
static void solver_line(const cvk_sim* sim, char* out, size_t size)
{
    static char text[65536];
    out[0] = '\0';
    cvk_sim_describe_plan(sim, text, sizeof text);
    const char* at = strstr(text, "solver:");
    if (!at)
        return;
    size_t n = strcspn(at, "\n");
    snprintf(out, size, "%.*s", (int)n, at);
}

/* The three ways a round runs, in its order. */
typedef struct mode {
    const char* name; /* the CSV's "fuse" column */
    cvk_fuse fuse;
    int shared_memory; /* cvk_sim_desc.fused_shared_memory */
} mode;
static const mode modes[] = {
    {"off", CVK_FUSE_OFF, 0},
    {"shared", CVK_FUSE_ON, 1},
    {"global", CVK_FUSE_ON, -1},
};
#define MODES (sizeof modes / sizeof modes[0])

static bool run_mode(bench* b, const mode* m, uint32_t frames, run_result* out)
{
    cvk_scene_desc scene = *b->scene;
    scene.solver.fuse = m->fuse;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = &scene;
    desc.fused_shared_memory = m->shared_memory;
    cvk_sim* sim = bench_sim_create_desc(b, &desc);
    if (!sim)
        return false;
    cvk_error err;
    bool ok = true;
    *out = (run_result){0};
    solver_line(sim, out->plan_line, sizeof out->plan_line);
    if (b->o->warmup > 0)
        ok = cvk_sim_step(sim, b->o->warmup, &err) == CVK_SUCCESS;
    double t0 = cvk_now_ms();
    ok = ok && cvk_sim_step(sim, frames, &err) == CVK_SUCCESS;
    double t1 = cvk_now_ms();
    cvk_sim_stats st;
    ok = ok && cvk_sim_get_stats(sim, &st, &err) == CVK_SUCCESS;
    float* xyz = NULL;
    uint64_t n = cvk_sim_particle_count(sim);
    if (ok) {
        xyz = malloc(3 * n * sizeof(float));
        ok = xyz && cvk_sim_read_positions(sim, xyz, n, &err) == CVK_SUCCESS;
        if (!xyz)
            snprintf(err.message, sizeof err.message, "out of host memory for positions");
    }
    if (ok) {
        out->dispatches = st.dispatches_per_frame;
        out->wall_ms = (t1 - t0) / frames;
        out->gpu_ms = st.gpu_ms_per_frame;
        out->hash = fnv1a64(xyz, 3 * n);
    } else {
        bench_fail(&err);
    }
    free(xyz);
    cvk_sim_destroy(sim);
    return ok;
}

static void add_row(bench* b, uint32_t round, const char* fuse, uint32_t frames,
                    const run_result* r, bool same)
{
    bench_table_row(&b->table);
    bench_table_int(&b->table, "round", round);
    bench_table_str(&b->table, "fuse", fuse);
    bench_table_int(&b->table, "frames", frames);
    bench_table_int(&b->table, "dispatches_per_frame", r->dispatches);
    bench_table_num(&b->table, "wall_ms_per_frame", r->wall_ms);
    bench_table_num(&b->table, "gpu_ms_per_frame", r->gpu_ms);
    bench_table_int(&b->table, "same_bits", same ? 1 : 0);
}

int bench_fused(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    uint32_t frames = b->o->frames ? b->o->frames : DEFAULT_FRAMES;
    uint32_t rounds = b->o->repeat;
    double wall[MODES][1000], gpu[MODES][1000];
    uint32_t dispatches[MODES] = {0};
    uint32_t differ = 0;
    printf("%s: %u frames after %u untimed, %u rounds of unfused, fused in shared memory and "
           "fused in global memory\n%6s %6s %12s %12s %12s %10s\n", b->scene_name, frames,
           b->o->warmup, rounds, "round", "fuse", "dispatches", "wall ms", "gpu ms", "same bits");
    for (uint32_t r = 0; r < rounds; r++) {
        run_result run[MODES];
        for (size_t m = 0; m < MODES; m++)
            if (!run_mode(b, &modes[m], frames, &run[m]))
                return APP_EXIT_FAILURE;
        for (size_t m = 0; m < MODES; m++) {
            bool same = run[m].hash == run[0].hash;
            differ += !same;
            add_row(b, r + 1, modes[m].name, frames, &run[m], same);
            wall[m][r] = run[m].wall_ms;
            gpu[m][r] = run[m].gpu_ms;
            dispatches[m] = run[m].dispatches;
            printf("%6u %6s %12u %12.3f %12.3f %10s\n", r + 1, modes[m].name, run[m].dispatches,
                   run[m].wall_ms, run[m].gpu_ms, same ? "yes" : "NO");
        }
        if (r == 0)
            for (size_t m = 0; m < MODES; m++)
                printf("  %-7s %s\n", modes[m].name, run[m].plan_line);
    }
    for (size_t m = 0; m < MODES; m++) {
        bench_timing w = bench_timing_of(wall[m], rounds), g = bench_timing_of(gpu[m], rounds);
        printf("fuse %-6s: %u dispatches per frame, wall %.3f ms per frame (median; %.3f-%.3f), "
               "gpu %.3f ms\n", modes[m].name, dispatches[m], w.median, w.min, w.max, g.median);
    }
    cvk_scene_desc scene = *b->scene;
    scene.solver.fuse = CVK_FUSE_AUTO;
    cvk_sim* sim = bench_sim_create(b, &scene);
    if (!sim)
        return APP_EXIT_FAILURE;
    char line[160];
    solver_line(sim, line, sizeof line);
    cvk_sim_destroy(sim);
    printf("auto on this device: %s\n", line);
    /* Where the library keeps the fused iterate here (cvk_sim_desc.fused_shared_memory 0):
       the fused pass's line of the plan says. */
    scene.solver.fuse = CVK_FUSE_ON;
    sim = bench_sim_create(b, &scene);
    if (!sim)
        return APP_EXIT_FAILURE;
    static char text[65536];
    cvk_sim_describe_plan(sim, text, sizeof text);
    cvk_sim_destroy(sim);
    printf("fused sweeps' iterate by default on this device: %s\n",
           strstr(text, "shared memory") ? "shared memory" : "global memory");
    if (differ)
        snprintf(b->check_failed, sizeof b->check_failed,
                 "fused: %u fused runs of %u rounds ended on positions that differ from the "
                 "unfused", differ, rounds);
    bench_plot_styles(&b->plot);
    bench_text_add(&b->plot,
                   "set title \"%s: ms per frame, unfused and fused sweeps, on %s\"\n"
                   "set xlabel \"round\"\nset ylabel \"wall ms per frame\"\nset key top left\n"
                   "plot \"fused.csv\" using \"round\":(strcol(\"fuse\") eq \"off\" ? "
                   "column(\"wall_ms_per_frame\") : 1/0) with linespoints linestyle 1 title "
                   "\"unfused\", \\\n     \"fused.csv\" using \"round\":(strcol(\"fuse\") eq \"shared\" ? "
                   "column(\"wall_ms_per_frame\") : 1/0) with linespoints linestyle 2 title "
                   "\"fused, shared memory\", \\\n     \"fused.csv\" using \"round\":(strcol(\"fuse\") eq \"global\" ? "
                   "column(\"wall_ms_per_frame\") : 1/0) with linespoints linestyle 3 title "
                   "\"fused, global memory\"\n",
                   b->scene_name, b->device);
    return APP_EXIT_OK;
}
