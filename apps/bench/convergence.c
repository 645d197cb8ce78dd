/* convergence: residual (seed 002 eq. 4.1) and solve error against iterations for every
   solver on one frozen substep, and against the solve's GPU time (seed 002 figures 6.3, 6.6,
   A.1, A.2, A.8, A.9). An iteration is one linear sweep; with --inner N every N sweeps share
   one local step. Each point is its own run of the substep with that many iterations. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "plot.h"

static const char* const columns[] = {
    "label", "solver", "omega", "iterations", "outer", "inner", "residual", "residual_relative",
    "solve_error", "distance_rms", "nan_count", "solve_ms", "solve_ms_min", "solve_ms_max",
    "ms_per_iteration",
};

/* Wang 2015 compares iteration counts to a 1e-3 reduction. */
#define REDUCTION 1e-3
#define MAX_SAMPLES 128

typedef struct series {
    bench_point* points;
    uint32_t count, capacity;
    uint32_t to_residual; /* iterations to residual ≤ 1e-3 r0; 0: not within the range */
    uint32_t to_error;    /* iterations to solve error ≤ 1e-3 */
} series;

static int compare_u32(const void* a, const void* b)
{
    uint32_t x = *(const uint32_t*)a, y = *(const uint32_t*)b;
    return (x > y) - (x < y);
}

/* Outer iteration counts: 1..10, then a quarter more each, the powers of ten, and `last`. */
static uint32_t sample_counts(uint32_t last, uint32_t* out)
{
    uint32_t n = 0;
    for (uint32_t k = 1; k <= 10 && k <= last; k++)
        out[n++] = k;
    for (double k = 12.5; k < last && n < MAX_SAMPLES - 8; k *= 1.25)
        out[n++] = (uint32_t)lround(k);
    for (uint32_t k = 100; k < last && k <= 100000000u / 10u; k *= 10)
        out[n++] = k;
    out[n++] = last;
    qsort(out, n, sizeof *out, compare_u32);
    uint32_t unique = 0;
    for (uint32_t i = 0; i < n; i++)
        if (unique == 0 || out[i] != out[unique - 1])
            out[unique++] = out[i];
    return unique;
}

static bool add_point(series* s, const bench_point* p)
{
    if (s->count == s->capacity) {
        uint32_t capacity = s->capacity ? 2 * s->capacity : 64;
        bench_point* grown = realloc(s->points, capacity * sizeof *grown);
        if (!grown) {
            app_error("clothvk-bench", "out of memory");
            return false;
        }
        s->points = grown;
        s->capacity = capacity;
    }
    s->points[s->count++] = *p;
    return true;
}

static const bench_point* point_at(const series* s, uint32_t sweeps)
{
    for (uint32_t i = 0; i < s->count; i++)
        if (s->points[i].sweeps == sweeps)
            return &s->points[i];
    return NULL;
}

typedef bool (*reached_fn)(const bench_point* p, const bench_frozen* f);

static bool residual_reached(const bench_point* p, const bench_frozen* f)
{
    return p->residual <= REDUCTION * f->residual0;
}

static bool error_reached(const bench_point* p, const bench_frozen* f)
{
    (void)f;
    return p->solve_error <= REDUCTION;
}

static bool measure(bench* b, bench_frozen* f, const bench_solver* solver, uint32_t outer,
                    bench_point* p)
{
    return bench_frozen_run(b, f, solver, outer * b->o->inner, b->o->warmup, b->o->repeat, p);
}

/* The fewest outer iterations in (lo, hi] that reach the target, by bisection (the
   iterates converge monotonically; hi reaches it, lo does not). Every probe is a point. */
static bool bisect(bench* b, bench_frozen* f, const bench_solver* solver, series* s,
                   reached_fn reached, uint32_t lo, uint32_t hi, uint32_t* out)
{
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        bench_point p;
        const bench_point* known = point_at(s, mid * b->o->inner); /* from the other target */
        if (known)
            p = *known;
        else if (!measure(b, f, solver, mid, &p) || !add_point(s, &p))
            return false;
        if (reached(&p, f))
            hi = mid;
        else
            lo = mid;
    }
    *out = hi * b->o->inner;
    return true;
}

static int compare_points(const void* a, const void* b)
{
    uint32_t x = ((const bench_point*)a)->sweeps, y = ((const bench_point*)b)->sweeps;
    return (x > y) - (x < y);
}

static bool run_solver(bench* b, bench_frozen* f, const bench_solver* solver, series* s)
{
    uint32_t counts[MAX_SAMPLES];
    uint32_t last = b->o->max_iterations / b->o->inner;
    uint32_t n = sample_counts(last ? last : 1, counts);
    uint32_t previous = 0;
    bool targets = f->residual0 > 0.0;
    for (uint32_t i = 0; i < n; i++) {
        bench_point p;
        if (!measure(b, f, solver, counts[i], &p) || !add_point(s, &p))
            return false;
        if (targets && !s->to_residual && residual_reached(&p, f) &&
            !bisect(b, f, solver, s, residual_reached, previous, counts[i], &s->to_residual))
            return false;
        if (!s->to_error && error_reached(&p, f) &&
            !bisect(b, f, solver, s, error_reached, previous, counts[i], &s->to_error))
            return false;
        previous = counts[i];
    }
    qsort(s->points, s->count, sizeof *s->points, compare_points);
    return true;
}

static void add_rows(bench* b, const bench_solver* solver, const bench_frozen* f, const series* s)
{
    cvk_solver_desc any = bench_solver_desc(&f->scene.solver, solver, 1, 1);
    for (uint32_t i = 0; i < s->count; i++) {
        const bench_point* p = &s->points[i];
        bench_table* t = &b->table;
        bench_table_row(t);
        bench_table_str(t, "label", solver->label);
        bench_table_str(t, "solver", cvk_linear_solver_name(solver->linear));
        bench_table_num(t, "omega", any.omega);
        bench_table_int(t, "iterations", p->sweeps);
        bench_table_int(t, "outer", p->sweeps / b->o->inner);
        bench_table_int(t, "inner", b->o->inner);
        bench_table_num(t, "residual", p->residual);
        bench_table_num(t, "residual_relative", f->residual0 > 0 ? p->residual / f->residual0 : NAN);
        bench_table_num(t, "solve_error", p->solve_error);
        bench_table_num(t, "distance_rms", p->distance_rms);
        bench_table_int(t, "nan_count", p->nan_count);
        bench_table_num(t, "solve_ms", p->solve_ms.median);
        bench_table_num(t, "solve_ms_min", p->solve_ms.min);
        bench_table_num(t, "solve_ms_max", p->solve_ms.max);
        bench_table_num(t, "ms_per_iteration", p->solve_ms.median / p->sweeps);
    }
}

static void print_block(bench* b, const series* all, const char* what, bool error)
{
    /* Sweeps at powers of ten of outer iterations (as sampled) and at the last sample. */
    uint32_t inner = b->o->inner, last = b->o->max_iterations / inner ? b->o->max_iterations / inner : 1;
    uint32_t columns_at[8], n = 0;
    for (uint32_t k = 1; k <= last && n < 7; k *= 10)
        columns_at[n++] = k * inner;
    if (columns_at[n - 1] != last * inner)
        columns_at[n++] = last * inner;
    printf("%-14s", what);
    for (uint32_t c = 0; c < n; c++)
        printf(" %11s%-6u", "k=", columns_at[c]);
    printf("\n");
    for (uint32_t i = 0; i < b->o->solver_count; i++) {
        printf("  %-12s", b->o->solvers[i].label);
        for (uint32_t c = 0; c < n; c++) {
            const bench_point* p = point_at(&all[i], columns_at[c]);
            if (p)
                printf(" %17.4g", error ? p->solve_error : p->residual);
            else
                printf(" %17s", "-");
        }
        printf("\n");
    }
}

static void print_count(uint32_t count, uint32_t max)
{
    char cell[24];
    if (count)
        snprintf(cell, sizeof cell, "%u", count);
    else
        snprintf(cell, sizeof cell, ">%u", max);
    printf(" %12s", cell);
}

static const series* find(const bench* b, const series* all, cvk_linear_solver linear, float omega)
{
    for (uint32_t i = 0; i < b->o->solver_count; i++)
        if (b->o->solvers[i].linear == linear && b->o->solvers[i].omega == omega)
            return &all[i];
    return NULL;
}

/* Seed 002's claim: RBGS converges per iteration exactly as sequential GS does. The float
   solver's rounding shows once the residual has fallen far, so the agreement is given up to
   each power of ten. */
static void print_rbgs_claim(const bench* b, const series* all)
{
    const series* rbgs = find(b, all, CVK_LINEAR_RBGS, 0.0f);
    const series* gs = find(b, all, CVK_LINEAR_GS_CPU, 0.0f);
    if (!rbgs || !gs)
        return;
    printf("rbgs vs gs-cpu, largest relative difference of the residual per iteration:");
    uint32_t most = b->o->max_iterations;
    for (uint32_t limit = 10;; limit *= 10) {
        uint32_t upto = limit < most ? limit : most;
        double worst = 0.0;
        for (uint32_t i = 0; i < rbgs->count; i++) {
            const bench_point* p = point_at(gs, rbgs->points[i].sweeps);
            if (p && p->residual > 0.0 && p->sweeps <= upto)
                worst = fmax(worst, fabs(rbgs->points[i].residual - p->residual) / p->residual);
        }
        printf(" %.2g up to %u", worst, upto);
        if (upto == most)
            break;
        printf(",");
    }
    printf("\n");
}

/* Wang 2015: Chebyshev needs at least 10x fewer iterations than Jacobi. */
static void print_wang(const bench* b, const series* all)
{
    const series* jacobi = find(b, all, CVK_LINEAR_JACOBI, 0.0f);
    const series* cheb = find(b, all, CVK_LINEAR_CHEBYSHEV, 0.0f);
    if (!jacobi || !cheb)
        return;
    const char* what[2] = {"residual to 1e-3 of the initial", "solve error to 1e-3"};
    uint32_t j[2] = {jacobi->to_residual, jacobi->to_error};
    uint32_t c[2] = {cheb->to_residual, cheb->to_error};
    for (int i = 0; i < 2; i++) {
        if (c[i] && j[i])
            printf("chebyshev / jacobi iterations, %s: %u / %u = %.3g (jacobi needs %.3gx as many)\n",
                   what[i], c[i], j[i], (double)c[i] / j[i], (double)j[i] / c[i]);
        else if (c[i])
            printf("chebyshev / jacobi iterations, %s: %u / >%u < %.3g\n", what[i], c[i],
                   b->o->max_iterations, (double)c[i] / b->o->max_iterations);
        else
            printf("chebyshev / jacobi iterations, %s: not reached by chebyshev within %u\n",
                   what[i], b->o->max_iterations);
    }
}

static void print_summary(bench* b, const bench_frozen* f, const series* all)
{
    printf("frozen substep: first of frame %u, h = %g s, %llu particles; --inner %u\n", f->frame,
           (double)f->scene.dt, (unsigned long long)f->n, b->o->inner);
    printf("start (the prediction): residual %.6g m^2, solve error %.4g\n", f->residual0,
           f->error0);
    const cvk_ref_newton_report* star = &f->star;
    bool converged = star->last_step <= b->o->reference_tolerance;
    printf("converged x*: residual %.6g m^2; Newton, %u steps (%llu CG iterations), last step "
           "%.3g m, |grad E| %.3g N; gs-cpu from x* moves %.3g m%s\n", f->residual_star,
           star->steps, (unsigned long long)star->cg_iterations, star->last_step, star->gradient,
           star->gs_change, converged ? "" : " -- NOT CONVERGED: raise --reference-max-iterations");
    print_block(b, all, "residual m^2", false);
    print_block(b, all, "solve error", true);
    printf("%-14s %12s %12s %12s\n", "iterations to", "r<=1e-3 r0", "error<=1e-3", "ms/iteration");
    for (uint32_t i = 0; i < b->o->solver_count; i++) {
        const series* s = &all[i];
        printf("  %-12s", b->o->solvers[i].label);
        print_count(s->to_residual, b->o->max_iterations);
        print_count(s->to_error, b->o->max_iterations);
        const bench_point* p = s->count ? &s->points[s->count - 1] : NULL;
        printf(" %12.4g%s\n", p ? p->solve_ms.median / p->sweeps : NAN,
               b->o->solvers[i].linear == CVK_LINEAR_GS_CPU ? " (host)" : "");
    }
    print_rbgs_claim(b, all);
    print_wang(b, all);
}

static void write_plot(bench* b, const bench_frozen* f)
{
    bench_text* t = &b->plot;
    bench_plot_styles(t);
    bench_text_add(t, "set multiplot layout 1,3 title \"%s, frozen substep of frame %u on %s\"\n"
                      "set key bottom left\nset format y \"%%.0e\"\n",
                   b->scene_name, f->frame, b->device);
    bench_text_add(t, "set title \"residual vs iterations\"\nset xlabel \"iterations\"\n"
                      "set ylabel \"residual (m²)\"\n");
    bench_text star = {0};
    bench_text_add(&star, "%.9g with lines linecolor rgb \"black\" dashtype 3 title \"x* (converged)\"",
                   f->residual_star);
    bench_plot_solvers(b, "convergence.csv", "iterations", "residual", "linespoints", true, true, NULL,
                       f->residual_star > 0 ? &star : NULL);
    bench_text_add(t, "set title \"solve error |x - x*| / |x* - x0|\"\nset ylabel \"solve error\"\n");
    bench_plot_solvers(b, "convergence.csv", "iterations", "solve_error", "linespoints", true, true, NULL, NULL);
    bench_text_add(t, "set title \"residual vs solve time (gs-cpu: host time)\"\n"
                      "set xlabel \"solve time per substep (ms)\"\nset ylabel \"residual (m²)\"\n");
    bench_plot_solvers(b, "convergence.csv", "solve_ms", "residual", "linespoints", true, true, NULL,
                       f->residual_star > 0 ? &star : NULL);
    bench_text_add(t, "unset multiplot\n");
    bench_text_free(&star);
}

int bench_convergence(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    bench_frozen f;
    if (!bench_frozen_create(b, &f)) {
        bench_frozen_destroy(&f);
        return APP_EXIT_FAILURE;
    }
    series* all = calloc(b->o->solver_count, sizeof *all);
    bool ok = all != NULL;
    for (uint32_t i = 0; ok && i < b->o->solver_count; i++) {
        ok = run_solver(b, &f, &b->o->solvers[i], &all[i]);
        if (ok)
            add_rows(b, &b->o->solvers[i], &f, &all[i]);
    }
    if (ok) {
        print_summary(b, &f, all);
        write_plot(b, &f);
    }
    for (uint32_t i = 0; all && i < b->o->solver_count; i++)
        free(all[i].points);
    free(all);
    bench_frozen_destroy(&f);
    return ok ? APP_EXIT_OK : APP_EXIT_FAILURE;
}
