/* clothvk-bench: run time against error, convergence, stability and scaling experiments.
   Every argument, the scene and the output folder are checked before anything runs, so bad
   input gets one line and exit status 2 with nothing written. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bench.h"
#include "plot.h"

static const char tool[] = "clothvk-bench";

enum {
    CONVERGENCE = 1 << 0,
    BUDGET = 1 << 1,
    PARETO = 1 << 2,
    STABILITY = 1 << 3,
    SCALING = 1 << 4,
    COLLIDE = 1 << 5,
    CONTACT_STEPS = 1 << 6,
    EXPLICIT = 1 << 7,
    ENSEMBLE = 1 << 8,
    BATCH = 1 << 9,
    FUSED = 1 << 10,
    ALL = 0x7ff,
};

typedef struct experiment {
    const char* name;
    unsigned bit;
    bool needs_scene;
    int (*run)(bench* b);
    int width, height; /* of the plot, pixels */
    int (*check)(const bench_options* o); /* more input to check before anything runs; NULL */
} experiment;

static const experiment experiments[] = {
    {"convergence", CONVERGENCE, true, bench_convergence, 1500, 500, NULL},
    {"budget", BUDGET, true, bench_budget, 1000, 500, NULL},
    {"pareto", PARETO, true, bench_pareto, 1400, 550, NULL},
    {"stability", STABILITY, true, bench_stability, 1500, 560, NULL},
    {"scaling", SCALING, false, bench_scaling, 1200, 550, NULL},
    {"collide", COLLIDE, false, bench_collide, 1000, 600, NULL},
    {"contact-steps", CONTACT_STEPS, true, bench_contact_steps, 1000, 550, NULL},
    {"explicit-stability", EXPLICIT, true, bench_explicit_stability, 1000, 550, NULL},
    {"contact-ensemble", ENSEMBLE, false, bench_contact_ensemble, 1400, 600,
     bench_contact_ensemble_check},
    {"batch", BATCH, false, bench_batch, 1200, 500, bench_batch_check},
    {"fused", FUSED, true, bench_fused, 1000, 500, NULL},
};

/* ---- value parsing: each prints the one line and returns false -------------------------- */

static bool bad_value(const char* option, const char* expected, const char* got)
{
    app_error(tool, "%s: expected %s, got %s", option, expected, got ? got : "nothing");
    return false;
}

static bool parse_double(const char* option, const char* text, double low, double high,
                         bool open_low, const char* expected, double* out)
{
    if (!text || !*text)
        return bad_value(option, expected, text);
    errno = 0;
    char* end;
    double v = strtod(text, &end);
    bool in_range = (open_low ? v > low : v >= low) && v <= high;
    if (errno || *end || !isfinite(v) || !in_range)
        return bad_value(option, expected, text);
    *out = v;
    return true;
}

/* A comma-separated list of numbers in range, sorted ascending (the experiments step through
   budgets, time steps and stiffnesses in order, and bisect between neighbours). */
static bool parse_double_list(const char* option, const char* text, double low, double high,
                              bool open_low, const char* expected, double* out, uint32_t* count)
{
    *count = 0;
    if (!text || !*text)
        return bad_value(option, expected, text);
    char item[64];
    for (const char* at = text;; at++) {
        size_t n = strcspn(at, ",");
        if (n == 0 || n >= sizeof item || *count == BENCH_MAX_LIST)
            return bad_value(option, expected, text);
        memcpy(item, at, n);
        item[n] = '\0';
        double v;
        errno = 0;
        char* end;
        v = strtod(item, &end);
        if (errno || *end || !isfinite(v) || !((open_low ? v > low : v >= low) && v <= high))
            return bad_value(option, expected, text);
        out[(*count)++] = v;
        at += n;
        if (!*at) {
            qsort(out, *count, sizeof *out, bench_compare_doubles);
            return true;
        }
    }
}

static bool parse_u32_list(const char* option, const char* text, uint32_t low, uint32_t high,
                           uint32_t* out, uint32_t* count)
{
    char expected[128];
    snprintf(expected, sizeof expected, "a comma-separated list of whole numbers from %u to %u",
             low, high);
    if (text && text[strspn(text, "0123456789,")] != '\0') /* digits only, as app_parse_u32 */
        return bad_value(option, expected, text);
    double values[BENCH_MAX_LIST];
    if (!parse_double_list(option, text, low, high, false, expected, values, count))
        return false;
    for (uint32_t i = 0; i < *count; i++)
        out[i] = (uint32_t)values[i];
    return true;
}

static bool parse_solver(const char* item, bench_solver* out)
{
    static const cvk_linear_solver all[] = {CVK_LINEAR_RBGS, CVK_LINEAR_JACOBI,
                                            CVK_LINEAR_CHEBYSHEV, CVK_LINEAR_GS_CPU};
    size_t n = strcspn(item, ":");
    *out = (bench_solver){0};
    static const cvk_integrator integrators[] = {CVK_INTEGRATOR_EULER, CVK_INTEGRATOR_RK2,
                                                 CVK_INTEGRATOR_AB4, CVK_INTEGRATOR_VERLET};
    for (size_t i = 0; i < sizeof integrators / sizeof integrators[0]; i++)
        if (!strcmp(item, cvk_integrator_name(integrators[i]))) {
            out->method = CVK_METHOD_EXPLICIT;
            out->integrator = integrators[i];
            snprintf(out->label, sizeof out->label, "%s", item);
            snprintf(out->title, sizeof out->title, "explicit %s", item);
            return true;
        }
    if (!strcmp(item, "cg") || !strcmp(item, "implicit-jacobi")) {
        out->method = CVK_METHOD_IMPLICIT;
        out->linear = item[0] == 'c' ? CVK_LINEAR_CG : CVK_LINEAR_JACOBI;
        snprintf(out->label, sizeof out->label, "%s", item);
        snprintf(out->title, sizeof out->title, "implicit %s",
                 cvk_linear_solver_name(out->linear));
        return true;
    }
    bool known = false;
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++) {
        const char* name = cvk_linear_solver_name(all[i]);
        if (strlen(name) == n && !strncmp(item, name, n)) {
            out->linear = all[i];
            known = true;
        }
    }
    if (!known || strlen(item) >= sizeof out->label)
        return false;
    if (item[n] == ':') {
        char* end;
        errno = 0;
        double omega = strtod(item + n + 1, &end);
        if (errno || *end || item[n + 1] == '\0' || !(omega > 0.0 && omega < 2.0))
            return false;
        out->omega = (float)omega;
        snprintf(out->title, sizeof out->title, "%.*s ω=%g", (int)n, item, omega);
    } else {
        snprintf(out->title, sizeof out->title, "%s", item);
    }
    snprintf(out->label, sizeof out->label, "%s", item);
    return true;
}

static bool parse_solvers(const char* text, bench_options* o)
{
    const char* expected = "a comma-separated list of jacobi, chebyshev, rbgs or gs-cpu, each "
                           "optionally with :OMEGA (0 < OMEGA < 2), or of cg, implicit-jacobi, "
                           "euler, rk2, adams-bashforth or verlet";
    o->solver_count = 0;
    if (!text || !*text)
        return bad_value("--solvers", expected, text);
    char item[64];
    for (const char* at = text;; at++) {
        size_t n = strcspn(at, ",");
        if (n == 0 || n >= sizeof item || o->solver_count == BENCH_MAX_LIST)
            return bad_value("--solvers", expected, text);
        memcpy(item, at, n);
        item[n] = '\0';
        if (!parse_solver(item, &o->solvers[o->solver_count]))
            return bad_value("--solvers", expected, text);
        for (uint32_t i = 0; i < o->solver_count; i++)
            if (!strcmp(o->solvers[i].label, item)) {
                app_error(tool, "--solvers: %s is listed twice", item);
                return false;
            }
        o->solver_count++;
        at += n;
        if (!*at)
            return true;
    }
}

/* ---- the options ---------------------------------------------------------------------------- */

typedef struct option_spec {
    const char* name;
    unsigned experiments;
    bool has_value;
} option_spec;

static const option_spec option_specs[] = {
    {"-o", ALL, true},
    {"--set", ALL, true},
    {"--solvers", ALL, true},
    {"--inner", ALL, true},
    {"--repeat", ALL, true},
    {"--warmup", ALL, true},
    {"--no-plot", ALL, false},
    {"--frame", CONVERGENCE | BUDGET, true},
    {"--max-iterations", CONVERGENCE | PARETO, true},
    {"--tolerances", PARETO, true},
    {"--explicit-substeps", PARETO, true},
    {"--reference-substeps", PARETO, true},
    {"--ms", BUDGET, true},
    {"--reference-tolerance", CONVERGENCE | BUDGET | PARETO, true},
    {"--reference-max-iterations", CONVERGENCE | BUDGET | PARETO, true},
    {"--iterations", PARETO | STABILITY | SCALING, true},
    {"--substeps", PARETO, true},
    {"--time", PARETO | STABILITY | CONTACT_STEPS | EXPLICIT, true},
    {"--target", PARETO, true},
    {"--target-residual", PARETO, true},
    {"--dt", STABILITY | CONTACT_STEPS, true},
    {"--stiffness", STABILITY, true},
    {"--damping", STABILITY, true},
    {"--energy-bound", STABILITY | EXPLICIT, true},
    {"--stretch-bound", STABILITY | PARETO | EXPLICIT, true},
    {"--kd", EXPLICIT, true},
    {"--limit-ratio", STABILITY | EXPLICIT, true},
    {"--min-steps", STABILITY | EXPLICIT, true},
    {"--grids", SCALING, true},
    {"--points", COLLIDE, true},
    {"--scenes", ENSEMBLE, true},
    {"--frames", ENSEMBLE | BATCH | FUSED, true},
    {"--counts", BATCH, true},
    {"--variants", ENSEMBLE, true},
    {"--require-clean", ENSEMBLE, false},
};

/* The option named by the first `length` characters of name. */
static const option_spec* find_option(const char* name, size_t length)
{
    for (size_t i = 0; i < sizeof option_specs / sizeof option_specs[0]; i++)
        if (strlen(option_specs[i].name) == length && !strncmp(option_specs[i].name, name, length))
            return &option_specs[i];
    return NULL;
}

static bool parse_u32(const char* option, const char* text, uint32_t low, uint32_t high,
                      uint32_t* out)
{
    return app_option_u32(tool, option, text, low, high, out);
}

/* contact-ensemble's and batch's options; false after printing why. */
static bool apply_ensemble_option(bench_options* o, const char* name, const char* v)
{
    if (!strcmp(name, "--counts"))
        return parse_u32_list(name, v, 1, 1u << 20, o->counts, &o->count_count);
    if (!strcmp(name, "--scenes")) {
        if (!v || !*v || strstr(v, ",,") || v[0] == ',' || v[strlen(v) - 1] == ',')
            return bad_value(name, "a comma-separated list of scene files", v);
        o->scenes = v;
        return true;
    }
    if (!strcmp(name, "--frames"))
        return parse_u32(name, v, 1, 1000000, &o->frames);
    if (!strcmp(name, "--variants"))
        return parse_u32(name, v, 1, 1000, &o->variants);
    if (!strcmp(name, "--require-clean")) {
        o->require_clean = true;
        return true;
    }
    return false;
}

/* Applies one option with its value; false after printing why. */
static bool apply_option(bench_options* o, const char* name, const char* v)
{
    const char* positive = "a number greater than 0";
    const char* positive_list = "a comma-separated list of numbers greater than 0";
    if (!strcmp(name, "-o")) {
        o->out_dir = v;
        return true;
    }
    if (!strcmp(name, "--set"))
        return app_overrides_add(&o->overrides, tool, v) == APP_EXIT_OK;
    if (!strcmp(name, "--solvers"))
        return parse_solvers(v, o);
    if (!strcmp(name, "--inner"))
        return parse_u32(name, v, 1, 1000, &o->inner);
    if (!strcmp(name, "--repeat"))
        return parse_u32(name, v, 1, 1000, &o->repeat);
    if (!strcmp(name, "--warmup"))
        return parse_u32(name, v, 0, 1000, &o->warmup);
    if (!strcmp(name, "--frame")) {
        o->frame_set = true;
        return parse_u32(name, v, 0, 1000000, &o->frame);
    }
    if (!strcmp(name, "--max-iterations"))
        return parse_u32(name, v, 1, 100000, &o->max_iterations);
    if (!strcmp(name, "--ms"))
        return parse_double_list(name, v, 0.0, 1e6, true, positive_list, o->budgets,
                                 &o->budget_count);
    if (!strcmp(name, "--reference-tolerance"))
        return parse_double(name, v, 0.0, 1.0, true, "a number greater than 0 and at most 1",
                            &o->reference_tolerance);
    if (!strcmp(name, "--reference-max-iterations"))
        return parse_u32(name, v, 1, 100000, &o->reference_max);
    if (!strcmp(name, "--iterations"))
        return parse_u32_list(name, v, 1, 100000, o->iterations, &o->iteration_count);
    if (!strcmp(name, "--tolerances"))
        return parse_double_list(name, v, 0.0, 1.0, true, "a comma-separated list of numbers "
                                 "greater than 0 and at most 1", o->tolerances, &o->tolerance_count);
    if (!strcmp(name, "--explicit-substeps"))
        return parse_u32_list(name, v, 1, 10000, o->explicit_substeps, &o->explicit_substep_count);
    if (!strcmp(name, "--reference-substeps"))
        return parse_u32(name, v, 1, 10000, &o->reference_substeps);
    if (!strcmp(name, "--substeps"))
        return parse_u32_list(name, v, 1, 1000, o->substeps, &o->substep_count);
    if (!strcmp(name, "--time"))
        return parse_double(name, v, 0.0, 1e4, true, positive, &o->time);
    if (!strcmp(name, "--target"))
        return parse_double(name, v, 0.0, 1e6, true, positive, &o->target_error);
    if (!strcmp(name, "--target-residual"))
        return parse_double(name, v, 0.0, 1e12, true, positive, &o->target_residual);
    if (!strcmp(name, "--dt"))
        return parse_double_list(name, v, 0.0, 10.0, true, "a comma-separated list of time steps "
                                 "greater than 0 and at most 10 s", o->dts, &o->dt_count);
    if (!strcmp(name, "--stiffness"))
        return parse_double_list(name, v, 0.0, 1e12, true, positive_list, o->stiffness,
                                 &o->stiffness_count);
    if (!strcmp(name, "--damping"))
        return parse_double_list(name, v, 0.0, 0.999, false, "a comma-separated list of numbers "
                                 "from 0 to 0.999", o->damping, &o->damping_count);
    if (!strcmp(name, "--kd"))
        return parse_double(name, v, 0.0, 1e6, true, positive, &o->kd);
    if (!strcmp(name, "--energy-bound"))
        return parse_double(name, v, 0.0, 1e12, true, positive, &o->energy_bound);
    if (!strcmp(name, "--stretch-bound"))
        return parse_double(name, v, 0.0, 1e12, true, positive, &o->stretch_bound);
    if (!strcmp(name, "--limit-ratio"))
        return parse_double(name, v, 1.0, 10.0, true, "a number greater than 1 and at most 10",
                            &o->limit_ratio);
    if (!strcmp(name, "--min-steps"))
        return parse_u32(name, v, 1, 10000000, &o->min_steps);
    if (!strcmp(name, "--grids"))
        return parse_u32_list(name, v, 2, 65535, o->grids, &o->grid_count);
    if (!strcmp(name, "--points"))
        return parse_u32_list(name, v, 1, 16777216, o->points, &o->point_count);
    if (!strcmp(name, "--no-plot")) {
        o->plot = false;
        return true;
    }
    return apply_ensemble_option(o, name, v);
}

static const experiment* find_experiment(const char* name)
{
    for (size_t i = 0; i < sizeof experiments / sizeof experiments[0]; i++)
        if (!strcmp(experiments[i].name, name))
            return &experiments[i];
    return NULL;
}

static void set_defaults(bench_options* o, const experiment* e)
{
    static const char* const solvers_for[] = {"jacobi,chebyshev,rbgs,rbgs:1.7,gs-cpu",
                                              "jacobi,chebyshev,rbgs,rbgs:1.7", "rbgs,chebyshev"};
    if (o->solver_count == 0) {
        const char* list = e->bit == STABILITY ? solvers_for[1]
                           : e->bit == SCALING ? solvers_for[2]
                                               : solvers_for[0];
        parse_solvers(list, o);
    }
    if (o->budget_count == 0) {
        const double ms[] = {1, 2, 4, 8};
        memcpy(o->budgets, ms, sizeof ms);
        o->budget_count = 4;
    }
    if (o->iteration_count == 0 && e->bit != STABILITY) {
        const uint32_t pareto[] = {1, 2, 4, 8, 16, 32}, scaling[] = {10, 30, 50, 70};
        bool is_pareto = e->bit == PARETO;
        memcpy(o->iterations, is_pareto ? pareto : scaling, is_pareto ? sizeof pareto : sizeof scaling);
        o->iteration_count = is_pareto ? 6 : 4;
    }
    if (o->tolerance_count == 0) {
        o->tolerances[0] = 1e-2;
        o->tolerances[1] = 1e-3;
        o->tolerance_count = 2;
    }
    if (o->substep_count == 0) {
        const uint32_t substeps[] = {2, 4, 8};
        memcpy(o->substeps, substeps, sizeof substeps);
        o->substep_count = 3;
    }
    if (o->time == 0.0)
        o->time = e->bit == EXPLICIT ? 1.0
                  : e->bit == STABILITY || e->bit == CONTACT_STEPS ? 0.5 : 0.25;
    if (o->kd == 0.0)
        o->kd = 10.0;
    if (o->limit_ratio == 0.0)
        o->limit_ratio = e->bit == EXPLICIT ? 1.02 : 1.05;
    if (o->dt_count == 0) {
        const double dts[] = {0.0005, 0.001, 0.002, 0.004, 0.008, 0.016, 1.0 / 30.0};
        memcpy(o->dts, dts, sizeof dts);
        o->dt_count = 7;
    }
    if (o->stiffness_count == 0) {
        const double k[] = {1e3, 1e4, 1e5, 1e6, 1e7, 1e8};
        memcpy(o->stiffness, k, sizeof k);
        o->stiffness_count = 6;
    }
    if (o->point_count == 0) {
        const uint32_t points[] = {1000, 10000, 100000};
        memcpy(o->points, points, sizeof points);
        o->point_count = 3;
    }
    if (o->damping_count == 0)
        o->damping_count = 1; /* damping[0] = 0 */
    if (e->bit == BATCH && o->frames == 0)
        o->frames = 10;
    /* x* of one substep to far below float rounding; a reference trajectory to far below the
       errors it measures, for a fraction of the time */
    if (o->reference_tolerance == 0.0)
        o->reference_tolerance = e->bit == PARETO ? 1e-8 : 1e-10;
}

typedef struct parsed {
    bench_options o;
    const experiment* e;
    bool done; /* --help or --version */
} parsed;

#define MAX_GIVEN 64

/* The command line sorted before any of it is applied: the options with their values in the
   order given (which ones an experiment takes is known only once it is named), then the
   experiment and the scene. */
typedef struct gathered {
    struct {
        const char* name;
        const char* value;
    } given[MAX_GIVEN];
    uint32_t given_count;
    const char* positional[2];
    uint32_t positionals;
} gathered;

static int gather(int argc, char** argv, gathered* g, bool* done)
{
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
        if (app_help_or_version(tool, a, bench_usage)) {
            *done = true;
            return APP_EXIT_OK;
        }
        if (a[0] == '-' && a[1]) {
            size_t length = 0;
            const char* inline_value = app_option_split(a, &length);
            const option_spec* spec = find_option(a, length);
            if (!spec) {
                app_error(tool, "unknown option %s (see --help)", a);
                return APP_EXIT_BAD_INPUT;
            }
            if (!spec->has_value && inline_value) {
                app_error(tool, "%s takes no value, got %s", spec->name, a);
                return APP_EXIT_BAD_INPUT;
            }
            if (spec->has_value && !inline_value && i + 1 >= argc) {
                app_error(tool, "%s: expected a value", a);
                return APP_EXIT_BAD_INPUT;
            }
            if (g->given_count == MAX_GIVEN) {
                app_error(tool, "too many options");
                return APP_EXIT_BAD_INPUT;
            }
            g->given[g->given_count].name = spec->name;
            g->given[g->given_count++].value = !spec->has_value ? NULL
                                               : inline_value   ? inline_value
                                                                : argv[++i];
        } else if (g->positionals == 2) {
            app_error(tool, "unexpected argument %s (an experiment and one scene at most)", a);
            return APP_EXIT_BAD_INPUT;
        } else {
            g->positional[g->positionals++] = a;
        }
    }
    return APP_EXIT_OK;
}

/* The experiment named first, and the scene it may need. */
static int choose_experiment(const gathered* g, parsed* p)
{
    if (!g->positional[0]) {
        app_error(tool, "no experiment given");
        bench_usage(stderr);
        return APP_EXIT_BAD_INPUT;
    }
    p->e = find_experiment(g->positional[0]);
    if (!p->e) {
        app_error(tool, "unknown experiment \"%s\" (expected convergence, budget, pareto, "
                  "stability, scaling, collide, contact-steps, explicit-stability, "
                  "contact-ensemble, batch or fused)",
                  g->positional[0]);
        return APP_EXIT_BAD_INPUT;
    }
    p->o.experiment = p->e->name;
    p->o.scene_path = g->positional[1];
    if (p->e->needs_scene && !p->o.scene_path) {
        app_error(tool, "%s needs a scene file", p->e->name);
        return APP_EXIT_BAD_INPUT;
    }
    return APP_EXIT_OK;
}

/* Each option given, if the experiment takes it. */
static int apply_given(const gathered* g, parsed* p)
{
    for (uint32_t i = 0; i < g->given_count; i++) {
        const option_spec* spec = find_option(g->given[i].name, strlen(g->given[i].name));
        if (!(spec->experiments & p->e->bit)) {
            app_error(tool, "%s is not an option of %s (see --help)", g->given[i].name, p->e->name);
            return APP_EXIT_BAD_INPUT;
        }
        if (!apply_option(&p->o, g->given[i].name, g->given[i].value))
            return APP_EXIT_BAD_INPUT;
    }
    return APP_EXIT_OK;
}

/* The solver families each experiment measures: implicit Euler in scaling and pareto,
   explicit integrators in pareto only, and there with their own substeps. */
static int check_solver_families(const bench_options* o, const experiment* e)
{
    bool explicit_listed = false;
    for (uint32_t i = 0; i < o->solver_count; i++) {
        const bench_solver* s = &o->solvers[i];
        explicit_listed |= s->method == CVK_METHOD_EXPLICIT;
        if (s->method == CVK_METHOD_IMPLICIT && e->bit != SCALING && e->bit != PARETO) {
            app_error(tool, "--solvers: %s (implicit Euler) is measured by scaling and pareto only",
                      s->label);
            return APP_EXIT_BAD_INPUT;
        }
        if (s->method == CVK_METHOD_EXPLICIT && e->bit != PARETO) {
            app_error(tool, "--solvers: %s (explicit) is measured by pareto only (and by "
                      "explicit-stability, which takes no --solvers)", s->label);
            return APP_EXIT_BAD_INPUT;
        }
    }
    if (e->bit == PARETO && explicit_listed != (o->explicit_substep_count > 0)) {
        app_error(tool, explicit_listed ? "pareto: explicit integrators need --explicit-substeps "
                                          "(their steps are far shorter than the others')"
                                        : "pareto: --explicit-substeps without an explicit "
                                          "integrator in --solvers");
        return APP_EXIT_BAD_INPUT;
    }
    return APP_EXIT_OK;
}

static int parse_args(int argc, char** argv, parsed* p)
{
    p->o = (bench_options){
        .out_dir = ".", .repeat = 3, .warmup = 1, .inner = 1, .plot = true,
        .max_iterations = 1000, .reference_max = 200,
        .target_error = 1e-3,
        .energy_bound = 1.0, .stretch_bound = 10.0, .min_steps = 50,
    };
    gathered g = {0};
    int status = gather(argc, argv, &g, &p->done);
    if (status != APP_EXIT_OK || p->done)
        return status;
    status = choose_experiment(&g, p);
    if (status == APP_EXIT_OK)
        status = apply_given(&g, p);
    if (status == APP_EXIT_OK)
        status = check_solver_families(&p->o, p->e);
    if (status == APP_EXIT_OK)
        set_defaults(&p->o, p->e);
    if (status == APP_EXIT_OK && p->e->check)
        status = p->e->check(&p->o);
    return status;
}

/* ---- the output folder ------------------------------------------------------------------------ */

/* Can files be created in dir? Tries, and removes what it made. */
static bool probe_writable(const char* dir, char* why, size_t why_size)
{
    char probe[4096];
    snprintf(probe, sizeof probe, "%s/.clothvk-bench-XXXXXX", dir);
    int fd = mkstemp(probe);
    if (fd < 0) {
        snprintf(why, why_size, "%s", strerror(errno));
        return false;
    }
    close(fd);
    unlink(probe);
    return true;
}

/* The folder exists and takes files, or its parent does (then it is made when results are
   written). Nothing is left behind either way. */
static bool check_out_dir(const char* dir, bool* create)
{
    char why[256];
    struct stat st;
    *create = false;
    if (strlen(dir) > 3000) {
        app_error(tool, "-o: the folder name is too long");
        return false;
    }
    if (stat(dir, &st) == 0) {
        if (!S_ISDIR(st.st_mode)) {
            app_error(tool, "-o %s: not a folder", dir);
            return false;
        }
        if (!probe_writable(dir, why, sizeof why)) {
            app_error(tool, "-o %s: cannot write there: %s", dir, why);
            return false;
        }
        return true;
    }
    if (errno != ENOENT) {
        app_error(tool, "-o %s: cannot use it as a folder: %s", dir, strerror(errno));
        return false;
    }
    char parent[4096];
    snprintf(parent, sizeof parent, "%s", dir);
    size_t n = strlen(parent);
    while (n > 1 && parent[n - 1] == '/')
        parent[--n] = '\0';
    char* slash = strrchr(parent, '/');
    if (!slash)
        snprintf(parent, sizeof parent, ".");
    else if (slash == parent)
        parent[1] = '\0';
    else
        *slash = '\0';
    if (stat(parent, &st) != 0 || !S_ISDIR(st.st_mode)) {
        app_error(tool, "-o %s: cannot create the folder: %s is not a folder", dir, parent);
        return false;
    }
    if (!probe_writable(parent, why, sizeof why)) {
        app_error(tool, "-o %s: cannot create the folder: %s", dir, why);
        return false;
    }
    *create = true;
    return true;
}

/* ---- running --------------------------------------------------------------------------------- */

static void describe_device(bench* b)
{
    const char* threads = getenv("LP_NUM_THREADS");
    snprintf(b->device, sizeof b->device, "%s%s%s", cvk_context_get_info(b->ctx).device_name,
             threads ? ", LP_NUM_THREADS=" : "", threads ? threads : "");
}

static const char* base_name(const char* path)
{
    const char* slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* A scene too large for the device is bad input, found before anything runs. */
static int check_scene_fits(bench* b)
{
    cvk_error err;
    cvk_sim* sim = NULL;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = b->scene;
    desc.timing = -1;
    cvk_result r = cvk_sim_create(b->ctx, &desc, &sim, &err);
    cvk_sim_destroy(sim);
    if (r == CVK_SUCCESS)
        return APP_EXIT_OK;
    app_error(tool, "%s: %s", b->o->scene_path, err.message);
    return r == CVK_ERROR_INVALID_ARGUMENT || r == CVK_ERROR_DEVICE_LIMIT ? APP_EXIT_BAD_INPUT
                                                                          : APP_EXIT_FAILURE;
}

static int write_results(bench* b, const experiment* e, bool create)
{
    const char* dir = b->o->out_dir;
    if (create && mkdir(dir, 0777) != 0 && errno != EEXIST) {
        app_error(tool, "-o %s: cannot create the folder: %s", dir, strerror(errno));
        return APP_EXIT_FAILURE;
    }
    char path[4096], message[512];
    snprintf(path, sizeof path, "%s/%s.csv", dir, e->name);
    b->table.device = b->device;
    if (b->table.failed) {
        app_error(tool, "out of memory for the results");
        return APP_EXIT_FAILURE;
    }
    if (!app_write_atomic(path, bench_table_write, &b->table, message, sizeof message)) {
        app_error(tool, "%s", message);
        return APP_EXIT_FAILURE;
    }
    int height = b->plot_height ? b->plot_height : e->height;
    bool plotted = b->o->plot &&
                   bench_plot(dir, e->name, e->width, height, &b->plot, message, sizeof message);
    printf("wrote %s", path);
    if (plotted)
        printf(", %s/%s.png (gnuplot script %s.gp)", dir, e->name, e->name);
    printf("\n");
    fflush(stdout);
    if (b->o->plot && !plotted)
        fprintf(stderr, "%s: no plot: %s; the CSV is complete\n", tool, message);
    return APP_EXIT_OK;
}

static int run(const parsed* p)
{
    const bench_options* o = &p->o;
    cvk_scene* file = NULL;
    int status = o->scene_path ? app_load_scene(tool, o->scene_path, &o->overrides, &file)
                               : APP_EXIT_OK;
    if (status != APP_EXIT_OK)
        return status;
    if (!o->scene_path && o->overrides.count && p->e->bit != ENSEMBLE && p->e->bit != BATCH) {
        app_error(tool, "--set needs a scene file (scaling's built-in scene has none)");
        return APP_EXIT_BAD_INPUT;
    }
    bool create = false;
    if (!check_out_dir(o->out_dir, &create)) {
        cvk_scene_destroy(file);
        return APP_EXIT_BAD_INPUT;
    }
    bench b = {.o = o, .scene = file ? cvk_scene_get_desc(file) : NULL,
               .scene_name = o->scene_path ? base_name(o->scene_path)
                             : p->e->bit == ENSEMBLE ? "(scenes below)"
                             : p->e->bit == BATCH    ? "built-in napkin"
                                                     : "built-in"};
    status = app_create_context(tool, &b.ctx);
    if (status != APP_EXIT_OK) {
        cvk_scene_destroy(file);
        return status;
    }
    status = p->e->bit == BATCH ? bench_batch_fits(&b)
             : b.scene          ? check_scene_fits(&b)
                                : APP_EXIT_OK;
    if (status != APP_EXIT_OK) {
        cvk_context_destroy(b.ctx);
        cvk_scene_destroy(file);
        return status;
    }
    describe_device(&b);
    printf("%s %s on %s\n", p->e->name, b.scene_name, b.device);
    status = app_validation_status(tool, b.ctx, p->e->run(&b));
    if (status == APP_EXIT_OK)
        status = write_results(&b, p->e, create);
    if (status == APP_EXIT_OK && b.check_failed[0]) { /* the results are written all the same */
        app_error(tool, "%s", b.check_failed);
        status = APP_EXIT_FAILURE;
    }
    bench_table_free(&b.table);
    bench_text_free(&b.plot);
    cvk_context_destroy(b.ctx);
    cvk_scene_destroy(file);
    return status;
}

int main(int argc, char** argv)
{
    parsed p = {0};
    int status = parse_args(argc, argv, &p);
    if (status == APP_EXIT_OK && !p.done)
        status = run(&p);
    app_overrides_free(&p.o.overrides);
    return status;
}
