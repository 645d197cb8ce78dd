/* clothvk-bench: what the experiments share. Each experiment fills one table (the CSV), writes
   a gnuplot script that draws it, and prints a short summary on stdout. */
#ifndef CVK_BENCH_H
#define CVK_BENCH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "clothvk.h"
#include "common.h"
#include "sim/internal.h"

#define BENCH_MAX_LIST 32

/* ---- text and tables ------------------------------------------------------------------ */

/* A growing string; on out-of-memory it stays as it was and `failed` is set. */
typedef struct bench_text {
    char* data;
    size_t length, capacity;
    bool failed;
} bench_text;

void bench_text_add(bench_text* t, const char* format, ...) __attribute__((format(printf, 2, 3)));
void bench_text_free(bench_text* t);

/* The CSV: named columns, rows of cells set by column name. A last column "device" is added
   to every row when it is written. */
typedef struct bench_table {
    const char* const* columns;
    uint32_t column_count;
    char** cells;             /* row-major, NULL for an empty cell */
    uint32_t rows, capacity;
    bool failed;              /* out of memory, or a column name that does not exist */
    const char* device;
} bench_table;

void bench_table_init(bench_table* t, const char* const* columns, uint32_t count);
void bench_table_free(bench_table* t);
void bench_table_row(bench_table* t);                  /* starts a row; cells start empty */
void bench_table_str(bench_table* t, const char* column, const char* value);
void bench_table_num(bench_table* t, const char* column, double value);   /* %.6g, nan, inf */
void bench_table_int(bench_table* t, const char* column, uint64_t value);
/* Sets a cell of an earlier row. */
void bench_table_set_int(bench_table* t, uint32_t row, const char* column, uint64_t value);
/* The value of a cell of row `row` as a number (NAN when empty or not a number). */
double bench_table_get(const bench_table* t, uint32_t row, const char* column);
const char* bench_table_get_str(const bench_table* t, uint32_t row, const char* column);
/* app_writer for app_write_atomic: RFC 4180 CSV with a header line. */
bool bench_table_write(FILE* file, void* table);

/* ---- settings ---------------------------------------------------------------------------- */

/* One entry of --solvers: NAME or NAME:OMEGA. */
typedef struct bench_solver {
    cvk_method method;        /* implicit: "cg", "implicit-jacobi" (scaling only) */
    cvk_linear_solver linear;
    cvk_integrator integrator; /* explicit: euler, rk2, adams-bashforth or verlet */
    float omega;      /* 0: the scene's */
    char label[32];   /* as written: "rbgs", "rbgs:1.7" */
    char title[48];   /* for plots: "rbgs ω=1.7" */
} bench_solver;

typedef struct bench_options {
    const char* experiment;
    const char* scene_path;     /* NULL: scaling's built-in template */
    const char* out_dir;
    app_overrides overrides;
    uint32_t repeat;            /* timed runs per point */
    uint32_t warmup;            /* untimed runs before them */
    bench_solver solvers[BENCH_MAX_LIST];
    uint32_t solver_count;
    uint32_t inner;             /* linear sweeps per local step */
    bool plot;

    /* convergence, budget (and pareto's reference trajectory) */
    bool frame_set;
    uint32_t frame;             /* frames with the scene's solver before the frozen substep */
    uint32_t max_iterations;
    double reference_tolerance; /* m: the converged solve stops when a Newton step is smaller */
    uint32_t reference_max;     /* Newton steps at most */
    double budgets[BENCH_MAX_LIST];
    uint32_t budget_count;

    /* pareto, stability, scaling */
    uint32_t iterations[BENCH_MAX_LIST];
    uint32_t iteration_count;   /* 0: the experiment's default */
    uint32_t substeps[BENCH_MAX_LIST];
    uint32_t substep_count;
    double time;                /* simulated seconds; 0: the experiment's default */
    double target_error;        /* m */
    double target_residual;     /* m²; 0: twice the reference's */
    /* pareto with other families */
    double tolerances[BENCH_MAX_LIST]; /* implicit: relative residuals where the solve stops */
    uint32_t tolerance_count;
    uint32_t explicit_substeps[BENCH_MAX_LIST]; /* explicit: substeps per frame */
    uint32_t explicit_substep_count;
    uint32_t reference_substeps; /* 0: REFERENCE_FACTOR x the finest of --substeps */

    /* stability */
    double dts[BENCH_MAX_LIST];
    uint32_t dt_count;
    double stiffness[BENCH_MAX_LIST];
    uint32_t stiffness_count;
    double damping[BENCH_MAX_LIST];
    uint32_t damping_count;
    double energy_bound;        /* energy growth / energy scale */
    double stretch_bound;       /* max stretch (1 = 100%) */
    double limit_ratio;         /* bisection stops when hi / lo is below this */
    uint32_t min_steps;
    /* explicit-stability */
    double kd;                  /* N·s/m for the largest stable h */

    /* scaling */
    uint32_t grids[BENCH_MAX_LIST];
    uint32_t grid_count;

    /* collide */
    uint32_t points[BENCH_MAX_LIST];
    uint32_t point_count;

    /* contact-ensemble */
    const char* scenes;         /* comma-separated scene files; NULL: SCENE, or the showcases */
    uint32_t frames;            /* frames per run; 0: each scene's own */
    uint32_t variants;          /* variants per scene at most; 0: all */
    bool require_clean;         /* exit 1 unless every run was free of intersecting pairs */

    /* batch (frames: timed frames per count; 0: 10) */
    uint32_t counts[BENCH_MAX_LIST]; /* copies of the scene (instances.count), sorted */
    uint32_t count_count;       /* 0: 1, 2, 4, ..., 8192 */
} bench_options;

/* What an experiment works with. */
typedef struct bench {
    const bench_options* o;
    cvk_context* ctx;
    const cvk_scene_desc* scene; /* NULL for scaling without a scene */
    const char* scene_name;      /* file name without folders, or "built-in" */
    char device[320];            /* device name, and LP_NUM_THREADS when set */
    bench_table table;
    bench_text plot;             /* gnuplot commands after the common preamble */
    int plot_height;             /* pixels; 0: the experiment's usual size */
    char check_failed[256];      /* set: a check the options asked for failed; the results are
                                    written, then this line goes to stderr and the exit status
                                    is 1 */
} bench;

/* ---- timing ------------------------------------------------------------------------------ */

typedef struct bench_timing {
    double median, min, max; /* ms; NAN when nothing was measured */
} bench_timing;

/* Median, min and max of n samples (sorted in place). */
bench_timing bench_timing_of(double* samples, uint32_t n);

/* qsort order for doubles, ascending. */
int bench_compare_doubles(const void* a, const void* b);

/* ---- solver settings ------------------------------------------------------------------------ */

/* The scene's solver with `s` applied and `sweeps` linear sweeps per substep arranged as
   outer = ceil(sweeps / inner) local steps of `inner` sweeps. */
cvk_solver_desc bench_solver_desc(const cvk_solver_desc* base, const bench_solver* s,
                                  uint32_t sweeps, uint32_t inner);
/* Sweeps per substep of a solver description. */
uint32_t bench_sweeps(const cvk_solver_desc* solver);

/* Creates a simulation; on failure prints the message and returns NULL. */
cvk_sim* bench_sim_create(bench* b, const cvk_scene_desc* scene);
/* The same with `desc`'s other fields (desc->scene set by the caller). */
cvk_sim* bench_sim_create_desc(bench* b, const cvk_sim_desc* desc);
/* Prints a library error as the tool's one line. */
void bench_fail(const cvk_error* err);

/* ---- the host reference (double precision, internal particle order) -------------------------- */

/* A scene's particles on the host for the reference solvers: positions x, the previous
   positions prev that Verlet needs, the prediction y, and a float copy for the metrics. */
typedef struct bench_host {
    cvk_build build;
    cvk_ref_params params;
    double* x;
    double* prev;
    double* y;
    float* xf;
} bench_host;

/* Builds the scene and sets the state from user-order positions x0 and velocities v0 as
   cvk_sim_write_state does (x0 NULL: the built grid; v0 NULL: at rest). On failure prints the
   message and returns false (bench_host_destroy is still safe). */
bool bench_host_create(const cvk_scene_desc* scene, const float* x0, const float* v0, bench_host* h);
/* The structural residual of x, from its float rounding (as the GPU state would have it). */
double bench_host_residual(bench_host* h);
/* x rounded to float, in user order (out holds 3 floats per particle). */
void bench_host_to_user(bench_host* h, float* out);
void bench_host_destroy(bench_host* h);

/* ---- frozen substeps (convergence, budget) -------------------------------------------------- */

/* One substep frozen in time: the state after `frame` frames of the scene with its own solver,
   a simulation with one substep per frame to replay it, and the converged solution x* of that
   substep from the double-precision host solver. */
typedef struct bench_frozen {
    cvk_scene_desc scene;   /* the bench scene with substeps = 1 */
    cvk_sim* sim;
    uint64_t n;
    float* x0;              /* positions at the start of the substep (user order) */
    float* v0;              /* velocities */
    double* x_star;         /* converged solution (user order) */
    float* x_star_f;        /* the same rounded to float, for distances */
    float* out;             /* scratch: positions after a run */
    uint32_t frame;         /* the substep frozen is the first of this frame */
    double residual0;       /* residual of the prediction: the iterate before the first sweep */
    double error0;          /* solve error of the prediction */
    double residual_star;   /* residual of x* */
    cvk_ref_newton_report star; /* how x* was found */
} bench_frozen;

bool bench_frozen_create(bench* b, bench_frozen* f);
void bench_frozen_destroy(bench_frozen* f);

typedef struct bench_point {
    uint32_t sweeps;
    double residual;
    double solve_error;     /* |x − x*| / |x* − x0| */
    double distance_rms;    /* RMS |x − x*|, m */
    uint64_t nan_count;
    bench_timing solve_ms;  /* GPU (host for gs-cpu) time of the solve pass */
} bench_point;

/* Replays the frozen substep with `sweeps` sweeps of solver `s`: warm-up runs, then `timed`
   timed runs (0: one untimed run). */
bool bench_frozen_run(bench* b, bench_frozen* f, const bench_solver* s, uint32_t sweeps,
                      uint32_t warmup, uint32_t timed, bench_point* out);

/* ---- the stability verdict ------------------------------------------------------------------ */

typedef enum bench_verdict {
    BENCH_STABLE = 0,
    BENCH_NAN,      /* a coordinate became NaN or infinite */
    BENCH_ENERGY,   /* the energy grew past the bound */
    BENCH_STRETCH,  /* a spring stretched past the bound */
    BENCH_DIVERGED, /* the library's divergence watch stopped the run (too fast, or a spring
                       ten times its length) */
} bench_verdict;

/* "stable", "nan", "energy", "stretch", "diverged" */
const char* bench_verdict_name(bench_verdict v);

/* What a run is compared with: its start. */
typedef struct bench_watch {
    double energy0;   /* kinetic + gravitational at the start, J */
    double scale;     /* J: kinetic + elastic at the start + M·max(|g|, 9.81)·D (D: the
                         cloth's extent), so a resting cloth without gravity has one too */
    double stretch0;  /* max stretch at the start */
} bench_watch;

bench_watch bench_watch_start(const cvk_sim_stats* start, double total_mass, const float gravity[3],
                              double extent);
/* Classifies the statistics of a run against its start; *growth receives the gain of kinetic
   + gravitational energy over the scale (see verdict.c for why springs are left out).
   Unstable: the library's divergence watch tripped; a NaN or infinity; growth above energy_bound; max stretch above
   max(stretch_bound, the start's). */
bench_verdict bench_classify(const bench_watch* w, const cvk_sim_stats* now, double energy_bound,
                             double stretch_bound, double* growth);

/* ---- experiments ---------------------------------------------------------------------------- */

/* --help: the experiments and their options (usage.c). */
void bench_usage(FILE* out);

/* Each returns APP_EXIT_OK or APP_EXIT_FAILURE (after printing why). */
int bench_convergence(bench* b);
int bench_budget(bench* b);
int bench_pareto(bench* b);
int bench_stability(bench* b);
int bench_scaling(bench* b);
int bench_collide(bench* b);
int bench_contact_steps(bench* b);
int bench_explicit_stability(bench* b);
int bench_contact_ensemble(bench* b);
int bench_fused(bench* b);
/* Its scenes load (with --set), and not both SCENE and --scenes: else one line and
   APP_EXIT_BAD_INPUT (APP_EXIT_FAILURE when out of memory). */
int bench_contact_ensemble_check(const bench_options* o);
/* batch (batch.c): N copies of a scene for each N of --counts; its check loads the scene with
   the largest count (one line and APP_EXIT_BAD_INPUT when that fails). The built-in scene's
   text, for the tests. */
int bench_batch(bench* b);
int bench_batch_check(const bench_options* o);
/* The largest count fits the device: else one line and APP_EXIT_BAD_INPUT, before anything
   is printed, measured or written. */
int bench_batch_fits(bench* b);
const char* bench_batch_builtin(void);

/* Stability of one configuration, for the experiment and the tests: steps the simulation
   `steps` substeps (checking every few) and classifies it. */
typedef struct bench_stability_run {
    bench_verdict verdict;
    uint64_t steps_done;    /* where it failed, or all */
    double max_stretch;     /* at the end (or the failure) */
    double growth;          /* energy growth at the end (or the failure) */
    uint64_t nan_count;
} bench_stability_run;

bool bench_run_stability(cvk_sim* sim, const cvk_scene_desc* scene, uint64_t steps,
                         double energy_bound, double stretch_bound, bench_stability_run* out,
                         cvk_error* error);

#endif
