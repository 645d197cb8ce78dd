/* contact-ensemble: does contact keep cloth from passing through cloth, in every showcase and
   under small changes of its settings? Each scene with self-contact runs as it is and in
   variants of its relaxation (solver.omega), damping, friction and substep length, applied as
   --set overrides are; after every frame the intersecting cloth triangle pairs are counted
   exactly on the host (cvk_sim_count_intersections). One row per run: how many frames had a
   pair, the most in a frame, the first frame with one, the stretch at the end, how often the
   contact bounds held particles back (cvk_sim_stats.contact_held_fraction), and where a run
   diverged or why it could not start. Pairs found are results, not failures: the exit status
   is 0 unless --require-clean asks for a clean ensemble. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "plot.h"

/* The showcases with contact, from the repository root. */
static const char* const showcases[] = {
    "assets/scenes/box-stack.json", "assets/scenes/sphere-hit.json",
    "assets/scenes/throw.json", "assets/scenes/funnel.json", "assets/scenes/drape.json",
    "assets/scenes/table.json", "assets/scenes/chair.json", "assets/scenes/ribbons.json",
    "assets/scenes/demo.json", "assets/scenes/poncho.json", "assets/scenes/contact-drape.json",
    "assets/scenes/contact-pile.json", "assets/scenes/contact-twist.json",
};

static const char* const columns[] = {
    "scene", "variant", "settings", "frame_time", "frames", "frames_run", "frames_with_pairs",
    "max_pairs", "end_pairs", "first_pair_frame", "end_max_stretch", "held_fraction",
    "diverged_frame", "step_ms", "count_ms", "error",
};

#define MAX_ITEMS 3
#define VARIANTS 9

/* A change of the scene's settings, as --set items (after the user's own). */
typedef struct variant {
    const char* name;
    char items[MAX_ITEMS][64];
    uint32_t item_count;
    const char* note;          /* what the items alone do not say; may be NULL */
} variant;

/* One run of a variant. Frames are numbered from 0, as the library's statistics and messages
   number them: frame f ends with the state after f + 1 frames. */
typedef struct outcome {
    uint32_t frames_run, frames_with_pairs;
    uint64_t max_pairs, end_pairs;
    int64_t first_pair;        /* the first frame that ended with a pair; -1: none did */
    int64_t diverged;          /* the frame that diverged; -1: none */
    double frame_time;         /* s, of the variant */
    double stretch;            /* max stretch at the end; NAN when not measured */
    double held;               /* particle-substeps held at their bounds, a fraction; NAN: not
                                  measured */
    double step_ms, count_ms;  /* wall time per frame of the step and of the count */
    char error[512];           /* why the run stopped early or never started; empty if not */
} outcome;

static void add_item(variant* v, const char* format, ...) __attribute__((format(printf, 2, 3)));
static void add_item(variant* v, const char* format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(v->items[v->item_count++], sizeof v->items[0], format, args);
    va_end(args);
}

/* Two values of omega around the scene's: 1.0 and 1.7 for Gauss-Seidel (SOR's plain value and
   a strong over-relaxation), moved off the scene's own value where it is one of them; ±10 %
   for the relaxed Jacobi solvers, below 2 (the methods without omega ignore it). */
static void omega_pair(const cvk_solver_desc* s, double* low, double* high)
{
    double w = s->omega;
    if (s->linear == CVK_LINEAR_RBGS || s->linear == CVK_LINEAR_GS_CPU) {
        *low = fabs(w - 1.0) < 1e-6 ? 0.9 : 1.0;
        *high = w < 1.7 - 1e-6 ? 1.7 : (w + 2.0) / 2.0;
    } else {
        *low = 0.9 * w;
        *high = fmin(1.1 * w, (w + 2.0) / 2.0);
    }
}

/* dt x k; the frame time is kept by dividing the substeps where k divides them. */
static void dt_variant(variant* v, const cvk_scene_desc* s, uint32_t k)
{
    add_item(v, "dt=%.7g", (double)s->dt * k);
    if (s->substeps % k == 0) {
        add_item(v, "substeps=%u", s->substeps / k);
        v->note = "frame time kept";
    } else {
        v->note = k == 2 ? "substeps kept: frame time x2" : "substeps kept: frame time x4";
    }
}

/* The variants of scene s, which the user's --set overrides (when `overridden`) already changed. */
static uint32_t make_variants(const cvk_scene_desc* s, bool overridden, variant* v)
{
    double low, high, d = s->damping, f = s->collision.static_friction;
    omega_pair(&s->solver, &low, &high);
    const char* names[VARIANTS] = {"scene", "omega-low", "omega-high", "damping+0.01",
                                   "damping-x2", "friction-0", "friction-0.6", "dt-x2", "dt-x4"};
    for (uint32_t i = 0; i < VARIANTS; i++)
        v[i] = (variant){.name = names[i]};
    v[0].note = overridden ? "the scene with the --set overrides" : "the scene's own settings";
    add_item(&v[1], "solver.omega=%.7g", low);
    add_item(&v[2], "solver.omega=%.7g", high);
    add_item(&v[3], "damping=%.7g", fmin(d + 0.01, 0.999));
    add_item(&v[4], "damping=%.7g", d > 0.0 ? fmin(2.0 * d, 0.999) : 0.002);
    if (d <= 0.0)
        v[4].note = "no damping to double: 0.002";
    add_item(&v[5], "collision.friction=0"); /* frictionless: the static coefficient too */
    add_item(&v[5], "collision.static_friction=0");
    add_item(&v[6], "collision.static_friction=%.7g", fmax(f, 0.6));
    add_item(&v[6], "collision.friction=0.6");
    v[5].note = v[6].note = "colliders with their own friction keep it";
    dt_variant(&v[7], s, 2);
    dt_variant(&v[8], s, 4);
    return VARIANTS;
}

/* The variant's overrides after the user's --set, as one line for the CSV. */
static void describe(const variant* v, char* out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (uint32_t i = 0; i < v->item_count && used < size; i++)
        used += (size_t)snprintf(out + used, size - used, "%s%s", i ? " " : "", v->items[i]);
    if (v->note && used < size)
        snprintf(out + used, size - used, "%s(%s)", used ? " " : "", v->note);
}

static cvk_result load_variant(const bench* b, const char* path, const variant* v,
                               cvk_scene** out, cvk_error* err)
{
    const app_overrides* user = &b->o->overrides;
    const char** items = malloc((user->count + MAX_ITEMS) * sizeof *items);
    if (!items) {
        snprintf(err->message, sizeof err->message, "out of memory for the overrides");
        return CVK_ERROR_OUT_OF_MEMORY;
    }
    for (uint32_t i = 0; i < user->count; i++)
        items[i] = user->items[i];
    for (uint32_t i = 0; i < v->item_count; i++)
        items[user->count + i] = v->items[i];
    cvk_result r = cvk_scene_load(path, items, user->count + v->item_count, out, err);
    free(items);
    return r;
}

/* Steps frame by frame, counting after each; stops at the first failure (err says why). */
static cvk_result step_frames(cvk_sim* sim, uint32_t frames, outcome* o, cvk_error* err)
{
    double step_ms = 0.0, count_ms = 0.0;
    cvk_result r = CVK_SUCCESS;
    for (uint32_t f = 0; f < frames && r == CVK_SUCCESS; f++) {
        double t0 = app_now_ms();
        r = cvk_sim_step(sim, 1, err);
        double t1 = app_now_ms();
        if (r == CVK_ERROR_DIVERGED)
            o->diverged = f;
        uint64_t pairs = 0;
        if (r == CVK_SUCCESS)
            r = cvk_sim_count_intersections(sim, &pairs, err);
        if (r != CVK_SUCCESS)
            break;
        step_ms += t1 - t0;
        count_ms += app_now_ms() - t1;
        o->frames_run = f + 1;
        o->end_pairs = pairs;
        o->max_pairs = pairs > o->max_pairs ? pairs : o->max_pairs;
        if (pairs && o->first_pair < 0)
            o->first_pair = f;
        o->frames_with_pairs += pairs > 0;
    }
    if (o->frames_run) {
        o->step_ms = step_ms / o->frames_run;
        o->count_ms = count_ms / o->frames_run;
    }
    return r;
}

static void run_variant(bench* b, const char* path, const variant* v, uint32_t frames,
                        outcome* o)
{
    *o = (outcome){.first_pair = -1, .diverged = -1, .frame_time = NAN, .stretch = NAN,
                   .held = NAN, .step_ms = NAN, .count_ms = NAN};
    cvk_error err = {0};
    cvk_scene* file = NULL;
    cvk_sim* sim = NULL;
    cvk_result r = load_variant(b, path, v, &file, &err);
    if (r == CVK_SUCCESS) {
        const cvk_scene_desc* scene = cvk_scene_get_desc(file);
        o->frame_time = (double)scene->dt * scene->substeps;
        cvk_sim_desc desc = cvk_default_sim_desc();
        desc.scene = scene;
        desc.timing = -1;
        r = cvk_sim_create(b->ctx, &desc, &sim, &err);
    }
    if (r == CVK_SUCCESS)
        r = step_frames(sim, frames, o, &err);
    if (r != CVK_SUCCESS)
        snprintf(o->error, sizeof o->error, "%s", err.message);
    cvk_sim_stats st;
    if (sim && o->frames_run && cvk_sim_get_stats(sim, &st, &err) == CVK_SUCCESS) {
        o->stretch = st.max_stretch;
        o->held = st.contact_held_fraction;
    }
    cvk_sim_destroy(sim);
    cvk_scene_destroy(file);
}

static void add_row(bench* b, const char* scene, const variant* v, uint32_t frames,
                    const outcome* o)
{
    char settings[320];
    describe(v, settings, sizeof settings);
    bench_table* t = &b->table;
    bench_table_row(t);
    bench_table_str(t, "scene", scene);
    bench_table_str(t, "variant", v->name);
    bench_table_str(t, "settings", settings);
    bench_table_num(t, "frame_time", o->frame_time);
    bench_table_int(t, "frames", frames);
    bench_table_int(t, "frames_run", o->frames_run);
    bench_table_int(t, "frames_with_pairs", o->frames_with_pairs);
    bench_table_int(t, "max_pairs", o->max_pairs);
    bench_table_int(t, "end_pairs", o->end_pairs);
    bench_table_num(t, "first_pair_frame", (double)o->first_pair);
    bench_table_num(t, "end_max_stretch", o->stretch);
    bench_table_num(t, "held_fraction", o->held);
    bench_table_num(t, "diverged_frame", (double)o->diverged);
    bench_table_num(t, "step_ms", o->step_ms);
    bench_table_num(t, "count_ms", o->count_ms);
    bench_table_str(t, "error", o->error);
}

static void print_run(const variant* v, uint32_t frames, const outcome* o)
{
    printf("  %-13s %6u/%-6u %8u %9llu %9llu %8.3f %7.2f %9.1f", v->name, o->frames_run, frames,
           o->frames_with_pairs, (unsigned long long)o->max_pairs,
           (unsigned long long)o->end_pairs, o->stretch, 100.0 * o->held,
           o->step_ms + o->count_ms);
    if (o->error[0])
        printf("  stopped: %s", o->error);
    printf("\n");
    fflush(stdout);
}

/* The scene files to run: --scenes, SCENE, or the showcases. Returns how many, 0 (after one
   line) when out of memory; *list is freed by the caller, with *copy. */
static uint32_t scene_paths(const bench_options* o, const char*** list, char** copy)
{
    const char* text = o->scenes ? o->scenes : o->scene_path;
    uint32_t n = text ? 1 : sizeof showcases / sizeof showcases[0];
    for (const char* c = text; c && *c; c++)
        n += *c == ',';
    *list = malloc(n * sizeof **list);
    *copy = text ? strdup(text) : NULL;
    if (!*list || (text && !*copy)) {
        app_error("clothvk-bench", "out of memory for the scene list");
        return 0;
    }
    for (uint32_t i = 0; i < n; i++)
        (*list)[i] = text ? strtok(i ? NULL : *copy, ",") : showcases[i];
    return n;
}

static const char* base_name(const char* path)
{
    const char* slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* Runs, runs with a pair, frames with a pair summed over the runs, runs that stopped early. */
typedef struct tally {
    uint32_t runs, with_pairs, stopped;
    uint64_t pair_frames;
} tally;

static void run_scene(bench* b, const char* path, const cvk_scene_desc* s, tally* all)
{
    variant v[VARIANTS];
    uint32_t n = make_variants(s, b->o->overrides.count > 0, v);
    if (b->o->variants && b->o->variants < n)
        n = b->o->variants;
    uint32_t frames = b->o->frames ? b->o->frames : s->frames;
    const char* name = base_name(path);
    printf("%s: %u variants x %u frames\n  %-13s %13s %8s %9s %9s %8s %7s %9s\n", name, n,
           frames, "variant", "frames run", "w/ pairs", "max pairs", "end pairs", "stretch",
           "held %", "ms/frame");
    tally t = {0};
    for (uint32_t i = 0; i < n; i++) {
        outcome o;
        run_variant(b, path, &v[i], frames, &o);
        add_row(b, name, &v[i], frames, &o);
        print_run(&v[i], frames, &o);
        t.runs++;
        t.with_pairs += o.frames_with_pairs > 0;
        t.pair_frames += o.frames_with_pairs;
        t.stopped += o.frames_run < frames;
    }
    printf("%s: %u runs, %u with an intersecting pair, %llu pair-frames", name, t.runs,
           t.with_pairs, (unsigned long long)t.pair_frames);
    if (t.stopped)
        printf(", %u stopped early", t.stopped);
    printf("\n");
    all->runs += t.runs;
    all->with_pairs += t.with_pairs;
    all->pair_frames += t.pair_frames;
    all->stopped += t.stopped;
}

static int load_scenes(const bench_options* o, const char* const* paths, uint32_t n,
                       cvk_scene** out)
{
    for (uint32_t i = 0; i < n; i++) {
        int status = app_load_scene("clothvk-bench", paths[i], &o->overrides, &out[i]);
        if (status != APP_EXIT_OK)
            return status;
    }
    return APP_EXIT_OK;
}

static void plot(bench* b)
{
    if (b->table.rows == 0) {
        bench_plot_empty(&b->plot);
        return;
    }
    bench_plot_styles(&b->plot);
    bench_text_add(&b->plot,
                   "set title \"contact-ensemble: frames with an intersecting cloth triangle pair, "
                   "per run, on %s\"\nset style fill solid 0.6\nset boxwidth 0.8\n"
                   "set xtics rotate by 90 right font \",8\"\nset yrange [0:*]\n"
                   "set ylabel \"frames with a pair\"\n"
                   "plot \"contact-ensemble.csv\" using 0:\"frames_with_pairs\":"
                   "xticlabels(strcol(\"scene\").\" \".strcol(\"variant\")) with boxes "
                   "linestyle 1 notitle\n", b->device);
}

static void finish(bench* b, const tally* all)
{
    printf("ensemble: %u runs, %u with an intersecting pair, %llu pair-frames, %u stopped early\n",
           all->runs, all->with_pairs, (unsigned long long)all->pair_frames, all->stopped);
    if (b->o->require_clean && (all->with_pairs || all->stopped))
        snprintf(b->check_failed, sizeof b->check_failed,
                 "--require-clean: %u of %u runs had an intersecting pair, %u stopped early",
                 all->with_pairs, all->runs, all->stopped);
    plot(b);
}

int bench_contact_ensemble_check(const bench_options* o)
{
    if (o->scenes && o->scene_path) {
        app_error("clothvk-bench", "contact-ensemble: a SCENE or --scenes, not both");
        return APP_EXIT_BAD_INPUT;
    }
    const char** paths = NULL;
    char* copy = NULL;
    uint32_t n = scene_paths(o, &paths, &copy);
    int status = n ? APP_EXIT_OK : APP_EXIT_FAILURE;
    for (uint32_t i = 0; i < n && status == APP_EXIT_OK; i++) {
        cvk_scene* scene = NULL;
        status = load_scenes(o, &paths[i], 1, &scene);
        cvk_scene_destroy(scene);
    }
    free(paths);
    free(copy);
    return status;
}

int bench_contact_ensemble(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    const char** paths = NULL;
    char* copy = NULL;
    uint32_t n = scene_paths(b->o, &paths, &copy);
    cvk_scene** scenes = n ? calloc(n, sizeof *scenes) : NULL;
    int status = scenes ? load_scenes(b->o, paths, n, scenes) : APP_EXIT_FAILURE;
    tally all = {0};
    for (uint32_t i = 0; i < n && status == APP_EXIT_OK; i++) {
        const cvk_scene_desc* s = cvk_scene_get_desc(scenes[i]);
        if (s->collision.self)
            run_scene(b, paths[i], s, &all);
        else
            printf("%s: no self-contact (collision.self is false): skipped\n", base_name(paths[i]));
    }
    for (uint32_t i = 0; scenes && i < n; i++)
        cvk_scene_destroy(scenes[i]);
    free(scenes);
    free(paths);
    free(copy);
    if (status == APP_EXIT_OK)
        finish(b, &all);
    return status;
}
