/* clothvk-ab: two builds of the library compared in one process, frame by frame.

       clothvk-ab BEFORE.so AFTER.so SCENE [--rounds N] [--frames-per-turn F] [--warm-up W]
                  [--set KEY=VALUE]...

   Loads each libclothvk.so given (dlopen, each with its own symbols), makes each one's context
   and simulation of SCENE (each build reads the scene itself, with the --set overrides), steps
   both W frames untimed, then N rounds in which each steps F frames, the two taking turns to go
   first. So both run the same frames under the same load, interleaved within a second or two: a
   shared machine whose speed drifts by tens of per cent from one run to the next (two runs an
   hour apart differ by 1.5x) slows both alike. Prints, per pass and for the whole frame, each
   build's GPU time summed over the timed frames (timestamps, ms), AFTER over BEFORE, and the
   median over frames of that ratio frame by frame; then whether the two reached the same
   positions bit for bit. Exit status 0, 1 when a run failed (or the validation layer, on with
   $CLOTHVK_VALIDATION 1, said anything), 2 on bad arguments or a bad scene.

   Not linked with the library: both builds are opened at run time, so neither binds the
   other's functions. */
#include <dlfcn.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "clothvk.h"

#define TOOL "clothvk-ab"

/* The functions of one build. */
typedef struct build {
    const char* path;
    void* handle;
    cvk_context_desc (*default_context_desc)(void);
    cvk_result (*context_create)(const cvk_context_desc*, cvk_context**, cvk_error*);
    void (*context_destroy)(cvk_context*);
    uint32_t (*context_validation_message_count)(const cvk_context*);
    cvk_result (*scene_load)(const char*, const char* const*, uint32_t, cvk_scene**, cvk_error*);
    const cvk_scene_desc* (*scene_get_desc)(const cvk_scene*);
    void (*scene_destroy)(cvk_scene*);
    cvk_sim_desc (*default_sim_desc)(void);
    cvk_result (*sim_create)(cvk_context*, const cvk_sim_desc*, cvk_sim**, cvk_error*);
    void (*sim_destroy)(cvk_sim*);
    cvk_result (*sim_step)(cvk_sim*, uint32_t, cvk_error*);
    void (*sim_get_timing)(const cvk_sim*, cvk_sim_stats*);
    uint64_t (*sim_particle_count)(const cvk_sim*);
    cvk_result (*sim_read_positions)(cvk_sim*, float*, uint64_t, cvk_error*);
    cvk_context* context;
    cvk_scene* scene;
    cvk_sim* sim;
} build;

/* The timings of one build, frame by frame: the whole frame first, then each pass by name. */
typedef struct series {
    char names[CVK_MAX_PASSES + 1][48];
    uint32_t count;   /* names in use */
    double* ms;       /* frames × (CVK_MAX_PASSES + 1) */
    uint32_t frames;
} series;

static int bind_build(build* b)
{
    b->handle = dlopen(b->path, RTLD_NOW | RTLD_LOCAL);
    if (!b->handle) {
        app_error(TOOL, "%s", dlerror());
        return APP_EXIT_BAD_INPUT;
    }
#define BIND(field, name)                                                                      \
    do {                                                                                       \
        void* f = dlsym(b->handle, name);                                                      \
        if (!f) {                                                                              \
            app_error(TOOL, "%s: no function %s (not a build of clothvk)", b->path, name);     \
            return APP_EXIT_BAD_INPUT;                                                         \
        }                                                                                      \
        memcpy(&b->field, &f, sizeof f);                                                       \
    } while (0)
    BIND(default_context_desc, "cvk_default_context_desc");
    BIND(context_create, "cvk_context_create");
    BIND(context_destroy, "cvk_context_destroy");
    BIND(context_validation_message_count, "cvk_context_validation_message_count");
    BIND(scene_load, "cvk_scene_load");
    BIND(scene_get_desc, "cvk_scene_get_desc");
    BIND(scene_destroy, "cvk_scene_destroy");
    BIND(default_sim_desc, "cvk_default_sim_desc");
    BIND(sim_create, "cvk_sim_create");
    BIND(sim_destroy, "cvk_sim_destroy");
    BIND(sim_step, "cvk_sim_step");
    BIND(sim_get_timing, "cvk_sim_get_timing");
    BIND(sim_particle_count, "cvk_sim_particle_count");
    BIND(sim_read_positions, "cvk_sim_read_positions");
#undef BIND
    return 0;
}

/* The build's context and simulation of the scene; 0, or the exit status with a line said. */
static int open_simulation(build* b, const char* scene, const char* const* sets, uint32_t set_count)
{
    cvk_error err = {0};
    cvk_context_desc cd = b->default_context_desc();
    cvk_result r = b->context_create(&cd, &b->context, &err);
    if (r == CVK_SUCCESS) {
        r = b->scene_load(scene, sets, set_count, &b->scene, &err);
        if (r != CVK_SUCCESS) {
            app_error(TOOL, "%s", err.message);
            return APP_EXIT_BAD_INPUT;
        }
    }
    if (r == CVK_SUCCESS) {
        cvk_sim_desc sd = b->default_sim_desc();
        sd.scene = b->scene_get_desc(b->scene);
        r = b->sim_create(b->context, &sd, &b->sim, &err);
    }
    if (r != CVK_SUCCESS) {
        app_error(TOOL, "%s: %s", b->path, err.message);
        return APP_EXIT_FAILURE;
    }
    return 0;
}

static void close_build(build* b)
{
    if (b->sim)
        b->sim_destroy(b->sim);
    if (b->scene)
        b->scene_destroy(b->scene);
    if (b->context)
        b->context_destroy(b->context);
    /* The library stays loaded: the Vulkan loader may still hold its layers' hooks. */
}

/* Column of pass `name` in s, added when new; -1 when the table is full. */
static int column(series* s, const char* name)
{
    for (uint32_t i = 0; i < s->count; i++)
        if (strcmp(s->names[i], name) == 0)
            return (int)i;
    if (s->count == CVK_MAX_PASSES + 1)
        return -1;
    snprintf(s->names[s->count], sizeof s->names[0], "%s", name);
    return (int)s->count++;
}

/* Steps one frame and records its timings. */
static int step_and_record(build* b, series* s)
{
    cvk_error err = {0};
    if (b->sim_step(b->sim, 1, &err) != CVK_SUCCESS) {
        app_error(TOOL, "%s: %s", b->path, err.message);
        return APP_EXIT_FAILURE;
    }
    cvk_sim_stats st;
    memset(&st, 0, sizeof st);
    b->sim_get_timing(b->sim, &st);
    double* row = &s->ms[(size_t)s->frames * (CVK_MAX_PASSES + 1)];
    row[column(s, "frame")] = st.gpu_ms_per_frame;
    for (uint32_t p = 0; p < st.pass_count && p < CVK_MAX_PASSES; p++) {
        int c = column(s, st.passes[p].name ? st.passes[p].name : "?");
        if (c >= 0)
            row[c] += st.passes[p].gpu_ms;
    }
    s->frames++;
    return 0;
}

static int compare_doubles(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static void report(const series* before, const series* after)
{
    uint32_t frames = before->frames;
    double* ratios = malloc((frames ? frames : 1) * sizeof *ratios);
    printf("%-16s %12s %12s %8s %14s\n", "pass", "before ms", "after ms", "after/", "median of");
    printf("%-16s %12s %12s %8s %14s\n", "", "(summed)", "(summed)", "before", "frame ratios");
    for (uint32_t c = 0; ratios && c < before->count; c++) {
        int d = -1;
        for (uint32_t i = 0; i < after->count; i++)
            if (strcmp(after->names[i], before->names[c]) == 0)
                d = (int)i;
        double sb = 0, sa = 0;
        uint32_t n = 0;
        for (uint32_t f = 0; f < frames; f++) {
            double x = before->ms[(size_t)f * (CVK_MAX_PASSES + 1) + c];
            double y = d < 0 ? 0 : after->ms[(size_t)f * (CVK_MAX_PASSES + 1) + (uint32_t)d];
            sb += x;
            sa += y;
            if (x > 0 && y > 0)
                ratios[n++] = y / x;
        }
        if (sb <= 0 && sa <= 0)
            continue; /* a pass that took no time in either build (not timed, or never run) */
        qsort(ratios, n, sizeof *ratios, compare_doubles);
        char median[32] = "-";
        if (n)
            snprintf(median, sizeof median, "%.3f", n % 2 ? ratios[n / 2]
                                                           : 0.5 * (ratios[n / 2 - 1] + ratios[n / 2]));
        char ratio[32] = "-";
        if (sb > 0)
            snprintf(ratio, sizeof ratio, "%.3f", sa / sb);
        printf("%-16s %12.2f %12.2f %8s %14s\n", before->names[c], sb, sa, ratio, median);
    }
    if (!ratios)
        app_error(TOOL, "out of host memory for the ratios");
    free(ratios);
}

/* Whether the two simulations hold the same positions, bit for bit; prints the verdict. */
static int compare_positions(build* before, build* after)
{
    uint64_t n = before->sim_particle_count(before->sim);
    if (after->sim_particle_count(after->sim) != n) {
        printf("positions: %llu particles before, %llu after\n", (unsigned long long)n,
               (unsigned long long)after->sim_particle_count(after->sim));
        return 0;
    }
    float* x = malloc((n ? n : 1) * 3 * sizeof *x);
    float* y = malloc((n ? n : 1) * 3 * sizeof *y);
    cvk_error err = {0};
    int status = 0;
    if (!x || !y) {
        app_error(TOOL, "out of host memory for %llu positions", (unsigned long long)n);
        status = APP_EXIT_FAILURE;
    } else if (before->sim_read_positions(before->sim, x, n, &err) != CVK_SUCCESS ||
               after->sim_read_positions(after->sim, y, n, &err) != CVK_SUCCESS) {
        app_error(TOOL, "%s", err.message);
        status = APP_EXIT_FAILURE;
    } else {
        double most = 0;
        for (uint64_t i = 0; i < 3 * n; i++) {
            double d = x[i] > y[i] ? (double)x[i] - y[i] : (double)y[i] - x[i];
            most = d > most || d != d ? d : most;
        }
        if (memcmp(x, y, n * 3 * sizeof *x) == 0)
            printf("positions: the same bits (%llu particles)\n", (unsigned long long)n);
        else
            printf("positions: differ, by up to %g m\n", most);
    }
    free(x);
    free(y);
    return status;
}

static void usage(FILE* out)
{
    fprintf(out, "usage: " TOOL " BEFORE.so AFTER.so SCENE [--rounds N] [--frames-per-turn F] "
                 "[--warm-up W] [--set KEY=VALUE]... [--version]\n");
}

/* The command line. */
typedef struct options {
    const char* positional[3]; /* BEFORE.so, AFTER.so, SCENE */
    uint32_t positional_count;
    uint32_t rounds, per_turn, warm_up;
    app_overrides sets;
} options;

/* BEFORE.so, AFTER.so and SCENE, in that order. */
static int take_positional(void* user, const char* arg)
{
    options* o = user;
    if (o->positional_count == 3) {
        app_error(TOOL, "one argument too many: %s", arg);
        return APP_EXIT_BAD_INPUT;
    }
    o->positional[o->positional_count++] = arg;
    return APP_EXIT_OK;
}

/* Reads argv into o (apps/cli.h, as the other tools): APP_EXIT_OK, -1 after --help or
   --version (printed), or the exit status with a line said. */
static int parse_options(int argc, char** argv, options* o)
{
    const app_option table[] = {
        {.name = "--rounds", .kind = APP_OPTION_U32, .number = &o->rounds, .min = 1, .max = 100000},
        {.name = "--frames-per-turn", .kind = APP_OPTION_U32, .number = &o->per_turn, .min = 1,
         .max = 10000},
        {.name = "--warm-up", .kind = APP_OPTION_U32, .number = &o->warm_up, .min = 0, .max = 10000},
        {.name = "--set", .kind = APP_OPTION_SET, .overrides = &o->sets},
    };
    const app_command_line line = {.tool = TOOL, .usage = usage, .options = table,
                                   .option_count = sizeof table / sizeof table[0], .user = o,
                                   .take_argument = take_positional};
    bool done = false;
    int status = app_read_command_line(&line, argc, argv, NULL, &done);
    if (status != APP_EXIT_OK || done)
        return done ? -1 : status;
    if (o->positional_count < 3) {
        usage(stderr);
        return APP_EXIT_BAD_INPUT;
    }
    return APP_EXIT_OK;
}

/* Both builds stepped in turns, o->rounds rounds of o->per_turn frames each, into s. */
static int run_rounds(build b[2], series s[2], const options* o)
{
    int status = 0;
    for (uint32_t r = 0; r < o->rounds && !status; r++)
        for (int k = 0; k < 2 && !status; k++) {
            int i = r % 2 ? 1 - k : k; /* the builds take turns to go first */
            for (uint32_t f = 0; f < o->per_turn && !status; f++)
                status = step_and_record(&b[i], &s[i]);
        }
    return status;
}

int main(int argc, char** argv)
{
    options o = {.rounds = 20, .per_turn = 2, .warm_up = 2};
    int status = parse_options(argc, argv, &o);
    if (status) {
        app_overrides_free(&o.sets);
        return status < 0 ? 0 : status;
    }
    build b[2] = {{.path = o.positional[0]}, {.path = o.positional[1]}};
    status = bind_build(&b[0]);
    if (!status)
        status = bind_build(&b[1]);
    for (int i = 0; i < 2 && !status; i++)
        status = open_simulation(&b[i], o.positional[2], o.sets.items, o.sets.count);
    series s[2] = {{.count = 0}, {.count = 0}};
    size_t frames = (size_t)o.rounds * o.per_turn;
    for (int i = 0; i < 2 && !status; i++) {
        s[i].ms = calloc(frames * (CVK_MAX_PASSES + 1), sizeof(double));
        if (!s[i].ms) {
            app_error(TOOL, "out of host memory for %zu frames", frames);
            status = APP_EXIT_FAILURE;
        }
    }
    for (int i = 0; i < 2 && !status; i++) {
        cvk_error err = {0};
        if (o.warm_up && b[i].sim_step(b[i].sim, o.warm_up, &err) != CVK_SUCCESS) {
            app_error(TOOL, "%s: %s", b[i].path, err.message);
            status = APP_EXIT_FAILURE;
        }
    }
    if (!status)
        status = run_rounds(b, s, &o);
    if (!status) {
        printf("%s: %zu frames each after %u untimed, %u rounds of %u a turn, GPU ms from "
               "timestamps\nbefore: %s\nafter:  %s\n", o.positional[2], frames, o.warm_up,
               o.rounds, o.per_turn, b[0].path, b[1].path);
        report(&s[0], &s[1]);
        status = compare_positions(&b[0], &b[1]);
    }
    /* With the validation layer on ($CLOTHVK_VALIDATION 1), any message fails the run. */
    for (int i = 0; i < 2; i++) {
        uint32_t messages = b[i].context ? b[i].context_validation_message_count(b[i].context) : 0;
        if (messages) {
            app_error(TOOL, "%s: %u validation messages", b[i].path, messages);
            status = status ? status : APP_EXIT_FAILURE;
        }
    }
    free(s[0].ms);
    free(s[1].ms);
    app_overrides_free(&o.sets);
    close_build(&b[1]);
    close_build(&b[0]);
    return status;
}
