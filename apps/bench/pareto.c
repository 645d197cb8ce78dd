/* pareto: error against GPU time per frame, over solver x iterations x substeps, and over
   the other families: implicit Euler (cg, block jacobi) x tolerance x substeps and the
   explicit integrators x their own substeps. Every setting simulates the scene from rest for
   the same simulated time; its errors are the residual (seed 002 eq. 4.1) and the trajectory
   error: the RMS distance to a reference trajectory at that time. The reference is the
   converged solver at a 4x smaller h than the finest projective-dynamics or implicit setting
   (or --reference-substeps): every substep solved to convergence by Newton's method
   (reference.h). The explicit integrators need steps far shorter than that; they are compared
   with the same reference, not with one of their own. The Pareto front of each error is
   marked, and the cheapest setting that reaches a target error is named. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "plot.h"
#include "sim/internal.h"

static const char* const columns[] = {
    "label", "method", "solver", "omega", "tolerance", "substeps", "dt", "iterations", "outer",
    "inner", "frames",
    "time_s", "frame_ms", "frame_ms_min", "frame_ms_max", "residual", "trajectory_error",
    "max_stretch", "nan_count", "stable", "front_residual", "front_trajectory",
};

#define REFERENCE_FACTOR 4 /* the reference's h is this much smaller than the finest */

typedef struct setup {
    uint32_t frames;
    double frame_time;
    uint64_t n;
    float* start;      /* positions at rest (user order) */
    float* reference;  /* the reference at the end */
    float* out;
    double reference_residual;
    uint32_t reference_substeps;
    uint32_t reference_steps;    /* most Newton steps a substep took */
    double reference_last_step;  /* largest last Newton step over the substeps, m */
} setup;

static cvk_scene_desc scene_with_substeps(const cvk_scene_desc* base, double frame_time,
                                          uint32_t substeps)
{
    cvk_scene_desc s = *base;
    s.substeps = substeps;
    s.dt = (float)(frame_time / substeps);
    return s;
}

/* Simulates `frames` frames from rest with `solver`; positions into out. */
static bool simulate(cvk_sim* sim, const setup* su, const cvk_solver_desc* solver, float* out,
                     cvk_sim_stats* st)
{
    cvk_error err;
    cvk_result r = cvk_sim_set_solver(sim, solver, &err);
    if (r == CVK_SUCCESS)
        r = cvk_sim_write_positions(sim, su->start, su->n, &err);
    if (r == CVK_SUCCESS)
        r = cvk_sim_step(sim, su->frames, &err);
    if (r == CVK_ERROR_DIVERGED) /* a configuration that blows up: its frozen state is its error */
        r = CVK_SUCCESS;
    if (r == CVK_SUCCESS)
        r = cvk_sim_get_stats(sim, st, &err);
    if (r == CVK_SUCCESS)
        r = cvk_sim_read_positions(sim, out, su->n, &err);
    if (r != CVK_SUCCESS)
        bench_fail(&err);
    return r == CVK_SUCCESS;
}

/* The reference trajectory: every one of `substeps` substeps per frame solved to convergence
   (Newton, reference.h), on the host in double precision. */
static bool reference(bench* b, setup* su, uint32_t substeps)
{
    su->reference_substeps = substeps;
    cvk_scene_desc scene = scene_with_substeps(b->scene, su->frame_time, su->reference_substeps);
    bench_host h;
    bool ok = bench_host_create(&scene, NULL, NULL, &h); /* at rest, as the simulations start */
    uint64_t steps = (uint64_t)su->frames * su->reference_substeps;
    for (uint64_t s = 0; ok && s < steps; s++) {
        cvk_ref_predict(&h.build, &h.params, h.x, h.prev, h.y);
        cvk_ref_newton_report report;
        ok = cvk_ref_solve_newton(&h.build, &h.params, h.y, b->o->reference_tolerance,
                                  b->o->reference_max, 0, h.x, &report);
        if (!ok)
            app_error("clothvk-bench", "out of memory for the reference trajectory");
        su->reference_steps = report.steps > su->reference_steps ? report.steps : su->reference_steps;
        su->reference_last_step = fmax(su->reference_last_step, report.last_step);
    }
    if (ok) {
        su->reference_residual = bench_host_residual(&h);
        bench_host_to_user(&h, su->reference);
    }
    bench_host_destroy(&h);
    return ok;
}

/* Times frames after the simulated run; a setting that blows up while being timed sets
   *diverged and is not timed. */
static bool time_frames(bench* b, cvk_sim* sim, bench_timing* out, bool* diverged)
{
    cvk_error err;
    double samples[1000];
    uint32_t measured = 0;
    for (uint32_t f = 0; f < b->o->warmup + b->o->repeat; f++) {
        cvk_result r = cvk_sim_step(sim, 1, &err);
        if (r == CVK_ERROR_DIVERGED) {
            *diverged = true;
            *out = (bench_timing){NAN, NAN, NAN};
            return true;
        }
        if (r != CVK_SUCCESS) {
            bench_fail(&err);
            return false;
        }
        cvk_sim_stats timing;
        cvk_sim_get_timing(sim, &timing);
        if (f >= b->o->warmup && timing.gpu_ms_per_frame >= 0.0)
            samples[measured++] = timing.gpu_ms_per_frame;
    }
    *out = bench_timing_of(samples, measured);
    return true;
}

/* One setting: `sweeps` per substep for projective dynamics; for implicit Euler the solve
   stops at `tolerance` (at most --max-iterations), and its iterations are the mean it used per
   substep in the simulated run's last frame; the explicit integrators have neither. */
static bool run_setting(bench* b, setup* su, cvk_sim* sim, const cvk_scene_desc* scene,
                        const bench_solver* s, uint32_t sweeps, double tolerance)
{
    cvk_solver_desc d = bench_solver_desc(&scene->solver, s, sweeps, b->o->inner);
    if (s->method == CVK_METHOD_IMPLICIT) {
        d.tolerance = (float)tolerance;
        d.max_iterations = b->o->max_iterations;
    }
    cvk_sim_stats st;
    bench_timing frame_ms;
    if (!simulate(sim, su, &d, su->out, &st))
        return false;
    double iterations = s->method == CVK_METHOD_PD       ? (double)bench_sweeps(&d)
                        : s->method == CVK_METHOD_IMPLICIT ? (double)st.solver_iterations / scene->substeps
                                                           : 1.0;
    /* A setting that blew up stays frozen where it did: it is unstable, and not timed. */
    frame_ms = (bench_timing){NAN, NAN, NAN};
    if (!st.diverged && !time_frames(b, sim, &frame_ms, &st.diverged))
        return false;
    double error = cvk_metrics_rms_distance(su->out, su->reference, su->n);
    bench_table* t = &b->table;
    bench_table_row(t);
    bench_table_str(t, "label", s->label);
    bench_table_str(t, "method", cvk_method_name(s->method));
    bench_table_str(t, "solver", s->method == CVK_METHOD_EXPLICIT ? cvk_integrator_name(s->integrator)
                                                                : cvk_linear_solver_name(s->linear));
    bench_table_num(t, "omega", s->method == CVK_METHOD_PD ? d.omega : NAN);
    bench_table_num(t, "tolerance", s->method == CVK_METHOD_IMPLICIT ? tolerance : NAN);
    bench_table_int(t, "substeps", scene->substeps);
    bench_table_num(t, "dt", scene->dt);
    bench_table_num(t, "iterations", iterations);
    bench_table_num(t, "outer", s->method == CVK_METHOD_PD ? d.outer_iterations : NAN);
    bench_table_num(t, "inner", s->method == CVK_METHOD_PD ? d.inner_iterations : NAN);
    bench_table_int(t, "frames", su->frames);
    bench_table_num(t, "time_s", su->frames * su->frame_time);
    bench_table_num(t, "frame_ms", frame_ms.median);
    bench_table_num(t, "frame_ms_min", frame_ms.min);
    bench_table_num(t, "frame_ms_max", frame_ms.max);
    bench_table_num(t, "residual", st.nan_count ? NAN : st.residual);
    bench_table_num(t, "trajectory_error", st.nan_count ? NAN : error);
    bench_table_num(t, "max_stretch", st.max_stretch);
    bench_table_int(t, "nan_count", st.nan_count);
    /* as the stability experiment judges it; an exploded setting is on no front */
    bench_table_int(t, "stable", !st.diverged && st.nan_count == 0 &&
                                     st.max_stretch <= b->o->stretch_bound);
    return true;
}

/* Marks the rows no other row beats in both time and `error`. */
static void mark_front(bench_table* t, const char* error, const char* mark)
{
    for (uint32_t r = 0; r < t->rows; r++) {
        double time = bench_table_get(t, r, "frame_ms"), e = bench_table_get(t, r, error);
        bool on = isfinite(time) && isfinite(e) && bench_table_get(t, r, "stable") == 1.0;
        for (uint32_t q = 0; on && q < t->rows; q++) {
            double tq = bench_table_get(t, q, "frame_ms"), eq = bench_table_get(t, q, error);
            bool stable = bench_table_get(t, q, "stable") == 1.0;
            if (q != r && stable && tq <= time && eq <= e && (tq < time || eq < e))
                on = false;
        }
        bench_table_set_int(t, r, mark, on);
    }
}

static void print_setting(const bench_table* t, uint32_t r)
{
    const char* method = bench_table_get_str(t, r, "method");
    printf("%-15s %4.0f substeps x ", bench_table_get_str(t, r, "label"),
           bench_table_get(t, r, "substeps"));
    if (!strcmp(method, "implicit"))
        printf("%5.1f iterations (to %g)", bench_table_get(t, r, "iterations"),
               bench_table_get(t, r, "tolerance"));
    else
        printf("%3.0f iterations", bench_table_get(t, r, "iterations"));
}

/* The label of a point on a plot's front: substeps x sweeps, or x tolerance for implicit. */
static void front_label(bench_text* plot, const bench_table* t, uint32_t r)
{
    if (!strcmp(bench_table_get_str(t, r, "method"), "implicit"))
        bench_text_add(plot, "%.0fx%g", bench_table_get(t, r, "substeps"),
                       bench_table_get(t, r, "tolerance"));
    else
        bench_text_add(plot, "%.0fx%.0f", bench_table_get(t, r, "substeps"),
                       bench_table_get(t, r, "iterations"));
}

/* The cheapest row on the front `mark` that costs more than `after` ms, or -1: walking it
 * from after = -1 lists the front ordered by time. */
static int next_on_front(const bench_table* t, const char* mark, double after)
{
    int best = -1;
    for (uint32_t r = 0; r < t->rows; r++) {
        double time = bench_table_get(t, r, "frame_ms");
        if (bench_table_get(t, r, mark) == 1.0 && time > after &&
            (best < 0 || time < bench_table_get(t, (uint32_t)best, "frame_ms")))
            best = (int)r;
    }
    return best;
}

static void print_front(const bench_table* t, const char* error, const char* mark, const char* unit)
{
    double printed = -1.0;
    for (;;) {
        int best = next_on_front(t, mark, printed);
        if (best < 0)
            return;
        printed = bench_table_get(t, (uint32_t)best, "frame_ms");
        char range[48];
        snprintf(range, sizeof range, "[%.3f-%.3f]", bench_table_get(t, (uint32_t)best, "frame_ms_min"),
                 bench_table_get(t, (uint32_t)best, "frame_ms_max"));
        printf("  ");
        print_setting(t, (uint32_t)best);
        printf("  %9.3f ms %-17s %10.4g %s\n", printed, range,
               bench_table_get(t, (uint32_t)best, error), unit);
    }
}

static void print_cheapest(const bench_table* t, const char* error, double target, const char* what,
                           const char* unit)
{
    int best = -1;
    for (uint32_t r = 0; r < t->rows; r++)
        if (bench_table_get(t, r, error) <= target && bench_table_get(t, r, "stable") == 1.0 &&
            (best < 0 || bench_table_get(t, r, "frame_ms") <
                             bench_table_get(t, (uint32_t)best, "frame_ms")))
            best = (int)r;
    printf("cheapest setting with %s <= %.3g %s: ", what, target, unit);
    if (best < 0) {
        printf("none of those tried\n");
        return;
    }
    print_setting(t, (uint32_t)best);
    printf(", %.3f ms per frame (%s %.4g %s)\n", bench_table_get(t, (uint32_t)best, "frame_ms"),
           what, bench_table_get(t, (uint32_t)best, error), unit);
}

/* The front of `mark` ordered by time, as a gnuplot datablock: time,error,label. */
static void front_block(bench* b, const char* name, const char* error, const char* mark)
{
    const bench_table* t = &b->table;
    bench_text_add(&b->plot, "$%s << EOD\n", name);
    double printed = -1.0;
    for (;;) {
        int best = next_on_front(t, mark, printed);
        if (best < 0)
            break;
        printed = bench_table_get(t, (uint32_t)best, "frame_ms");
        bench_text_add(&b->plot, "%.6g,%.6g,", printed, bench_table_get(t, (uint32_t)best, error));
        front_label(&b->plot, t, (uint32_t)best);
        bench_text_add(&b->plot, "\n");
    }
    bench_text_add(&b->plot, "EOD\n");
}

static void write_plot(bench* b, const setup* su)
{
    bench_text* t = &b->plot;
    bench_plot_styles(t);
    const char* errors[2] = {"residual", "trajectory_error"};
    const char* marks[2] = {"front_residual", "front_trajectory"};
    const char* titles[2] = {"residual (m²)", "trajectory error (m RMS)"};
    for (int i = 0; i < 2; i++)
        front_block(b, marks[i], errors[i], marks[i]);
    bench_text_add(t, "set multiplot layout 1,2 title \"%s: error after %.3g s against GPU time per "
                      "frame (gs-cpu: host), on %s\"\nset xlabel \"time per frame (ms)\"\n"
                      "set datafile missing \"nan\"\n"
                      "set format y \"%%.0e\"\nset key bottom left\n",
                   b->scene_name, su->frames * su->frame_time, b->device);
    for (int i = 0; i < 2; i++) {
        bench_text front = {0};
        bench_text_add(&front, "$%s using 1:2 with lines linecolor rgb \"black\" title \"Pareto "
                               "front\", \\\n     $%s using 1:2:3 with labels left offset 0.5,0.3 "
                               "font \",7\" notitle", marks[i], marks[i]);
        if (i == 0 && su->reference_residual > 0)
            bench_text_add(&front, ", \\\n     %.9g with lines linecolor rgb \"black\" dashtype 3 "
                                   "title \"reference (converged, h/%u)\"", su->reference_residual,
                           su->reference_substeps / (uint32_t)(su->frame_time / b->scene->dt + 0.5));
        bench_text_add(t, "set title \"%s; front: substeps x iterations (implicit: x "
                          "tolerance); unstable left out\"\nset ylabel \"%s\"\n",
                       titles[i], titles[i]);
        bench_plot_solvers(b, "pareto.csv", "frame_ms", errors[i], "points", true, true, "stable",
                           &front);
        bench_text_free(&front);
    }
    bench_text_add(t, "unset multiplot\n");
}

static bool prepare(bench* b, setup* su)
{
    su->frame_time = (double)b->scene->dt * b->scene->substeps;
    double frames = round(b->o->time / su->frame_time);
    su->frames = frames < 1.0 ? 1u : (uint32_t)fmin(frames, 1e6);
    cvk_sim* probe = bench_sim_create(b, b->scene);
    if (!probe)
        return false;
    su->n = cvk_sim_particle_count(probe);
    size_t bytes = 3 * (size_t)su->n * sizeof(float);
    su->start = malloc(bytes);
    su->reference = malloc(bytes);
    su->out = malloc(bytes);
    cvk_error err;
    bool ok = su->start && su->reference && su->out;
    if (!ok)
        app_error("clothvk-bench", "out of memory for %llu particles", (unsigned long long)su->n);
    if (ok && cvk_sim_read_positions(probe, su->start, su->n, &err) != CVK_SUCCESS) {
        bench_fail(&err);
        ok = false;
    }
    cvk_sim_destroy(probe);
    return ok;
}

static void print_summary(bench* b, const setup* su)
{
    const bench_table* t = &b->table;
    printf("%u frames of %g s from rest (%.3g s); reference: every substep converged (Newton, "
           "double, host) at %u substeps per frame (h = %.3g s): at most %u Newton steps, last "
           "steps below %.3g m; its residual %.4g m^2\n",
           su->frames, su->frame_time, su->frames * su->frame_time, su->reference_substeps,
           su->frame_time / su->reference_substeps, su->reference_steps, su->reference_last_step,
           su->reference_residual);
    printf("Pareto front, trajectory error (time per frame: median [min-max] of %u):\n",
           b->o->repeat);
    print_front(t, "trajectory_error", "front_trajectory", "m");
    printf("Pareto front, residual:\n");
    print_front(t, "residual", "front_residual", "m^2");
    bool header = false;
    for (uint32_t r = 0; r < t->rows; r++) {
        if (bench_table_get(t, r, "stable") == 1.0)
            continue;
        if (!header)
            printf("unstable settings (NaN, or a spring stretched past %g%%), on no front:\n",
                   100.0 * b->o->stretch_bound);
        header = true;
        printf("  ");
        print_setting(t, r);
        printf("  max stretch %.3g%%, NaN %.0f\n", 100.0 * bench_table_get(t, r, "max_stretch"),
               bench_table_get(t, r, "nan_count"));
    }
    double target_residual = b->o->target_residual > 0 ? b->o->target_residual
                                                        : 2.0 * su->reference_residual;
    print_cheapest(t, "trajectory_error", b->o->target_error, "trajectory error", "m");
    print_cheapest(t, "residual", target_residual, "residual", "m^2");
}

int bench_pareto(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    setup su = {0};
    uint32_t finest = 0;
    for (uint32_t i = 0; i < b->o->substep_count; i++)
        finest = b->o->substeps[i] > finest ? b->o->substeps[i] : finest;
    uint32_t reference_substeps = b->o->reference_substeps ? b->o->reference_substeps
                                                           : REFERENCE_FACTOR * finest;
    bool ok = prepare(b, &su) && reference(b, &su, reference_substeps);
    for (uint32_t i = 0; ok && i < b->o->substep_count; i++) {
        cvk_scene_desc scene = scene_with_substeps(b->scene, su.frame_time, b->o->substeps[i]);
        cvk_sim* sim = bench_sim_create(b, &scene);
        ok = sim != NULL;
        for (uint32_t s = 0; ok && s < b->o->solver_count; s++) {
            const bench_solver* solver = &b->o->solvers[s];
            if (solver->method == CVK_METHOD_PD)
                for (uint32_t k = 0; ok && k < b->o->iteration_count; k++)
                    ok = run_setting(b, &su, sim, &scene, solver, b->o->iterations[k], 0.0);
            else if (solver->method == CVK_METHOD_IMPLICIT)
                for (uint32_t k = 0; ok && k < b->o->tolerance_count; k++)
                    ok = run_setting(b, &su, sim, &scene, solver, 0, b->o->tolerances[k]);
        }
        cvk_sim_destroy(sim);
    }
    for (uint32_t i = 0; ok && i < b->o->explicit_substep_count; i++) {
        cvk_scene_desc scene = scene_with_substeps(b->scene, su.frame_time, b->o->explicit_substeps[i]);
        cvk_sim* sim = bench_sim_create(b, &scene);
        ok = sim != NULL;
        for (uint32_t s = 0; ok && s < b->o->solver_count; s++)
            if (b->o->solvers[s].method == CVK_METHOD_EXPLICIT)
                ok = run_setting(b, &su, sim, &scene, &b->o->solvers[s], 1, 0.0);
        cvk_sim_destroy(sim);
    }
    if (ok) {
        mark_front(&b->table, "residual", "front_residual");
        mark_front(&b->table, "trajectory_error", "front_trajectory");
        print_summary(b, &su);
        write_plot(b, &su);
    }
    free(su.start);
    free(su.reference);
    free(su.out);
    return ok ? APP_EXIT_OK : APP_EXIT_FAILURE;
}
