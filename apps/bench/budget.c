/* budget: how many iterations of each solver fit in a GPU-time budget for the solve of one
   frozen substep, and which residual and solve error they reach (seed 002's iterations per
   budget: RBGS 5/11/22/45, GS 1/2/4/9, Jacobi 9/19/32/70 at 1/2/4/8 ms on a GTX 970).

   The solve time of k iterations is close to a + b k (a: the fixed cost of a solve pass), so
   two calibration points give the k that fits; that k is then measured, and lowered while its
   median exceeds the budget. gs-cpu is timed on the host. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "plot.h"

static const char* const columns[] = {
    "label", "solver", "omega", "budget_ms", "iterations", "outer", "inner", "solve_ms",
    "solve_ms_min", "solve_ms_max", "fits", "residual", "residual_relative", "solve_error",
    "ms_per_iteration", "overhead_ms", "seed_002_gtx970",
};

#define CALIBRATION_SWEEPS 8u
#define MAX_CALIBRATION_SWEEPS 20000u
#define ADJUSTMENTS 4

/* The seed's name for the solver this one reproduces. */
static const char* seed_name(const bench_solver* s)
{
    switch (s->linear) {
    case CVK_LINEAR_RBGS: return "RBGS";
    case CVK_LINEAR_GS_CPU: return "GS (sequential)";
    case CVK_LINEAR_JACOBI: return "Jacobi";
    case CVK_LINEAR_CHEBYSHEV: break;
    case CVK_LINEAR_CG: break;
    }
    return "?";
}

/* Seed 002 appendix A (figures A.3-A.6, A.10-A.13): iterations within 1, 2, 4 and 8 ms. */
static double seed_iterations(const bench_solver* s, double budget)
{
    static const double budgets[4] = {1, 2, 4, 8};
    static const double rbgs[4] = {5, 11, 22, 45}, gs[4] = {1, 2, 4, 9}, jacobi[4] = {9, 19, 32, 70};
    const double* row = NULL;
    if (s->omega == 0.0f && s->linear == CVK_LINEAR_RBGS)
        row = rbgs;
    else if (s->omega == 0.0f && s->linear == CVK_LINEAR_GS_CPU)
        row = gs;
    else if (s->omega == 0.0f && s->linear == CVK_LINEAR_JACOBI)
        row = jacobi;
    for (int i = 0; row && i < 4; i++)
        if (budget == budgets[i])
            return row[i];
    return NAN;
}

typedef struct fit {
    double overhead_ms; /* a */
    double per_sweep;   /* b, ms */
} fit;

static bool calibrate(bench* b, bench_frozen* f, const bench_solver* s, double largest, fit* out)
{
    uint32_t inner = b->o->inner;
    uint32_t k1 = CALIBRATION_SWEEPS * inner;
    bench_point p1, p2;
    if (!bench_frozen_run(b, f, s, k1, b->o->warmup, b->o->repeat, &p1))
        return false;
    double guess = p1.solve_ms.median / k1;
    double k2 = guess > 0.0 ? largest / guess : 4.0 * k1;
    k2 = fmin(fmax(k2, 4.0 * k1), MAX_CALIBRATION_SWEEPS);
    uint32_t sweeps2 = (uint32_t)k2 / inner * inner;
    if (!bench_frozen_run(b, f, s, sweeps2, b->o->warmup, b->o->repeat, &p2))
        return false;
    out->per_sweep = (p2.solve_ms.median - p1.solve_ms.median) / (double)(p2.sweeps - p1.sweeps);
    if (!(out->per_sweep > 0.0))
        out->per_sweep = p2.solve_ms.median / p2.sweeps;
    out->overhead_ms = fmax(0.0, p1.solve_ms.median - out->per_sweep * p1.sweeps);
    return true;
}

typedef struct budget_point {
    bench_point p;
    bool fits;
} budget_point;

/* The most sweeps (a multiple of --inner) whose measured median fits the budget. */
static bool fit_budget(bench* b, bench_frozen* f, const bench_solver* s, const fit* model,
                       double budget, budget_point* out)
{
    uint32_t inner = b->o->inner;
    double k = floor((budget - model->overhead_ms) / model->per_sweep / inner) * inner;
    uint32_t sweeps = k >= inner ? (uint32_t)fmin(k, 1e8) : inner;
    for (int attempt = 0; attempt < ADJUSTMENTS; attempt++) {
        if (!bench_frozen_run(b, f, s, sweeps, b->o->warmup, b->o->repeat, &out->p))
            return false;
        out->fits = out->p.solve_ms.median <= budget;
        if (out->fits || sweeps == inner)
            return true;
        uint32_t lower = (uint32_t)floor(sweeps * budget / out->p.solve_ms.median / inner) * inner;
        sweeps = lower >= inner ? (lower < sweeps ? lower : sweeps - inner) : inner;
    }
    return true;
}

static void add_row(bench* b, const bench_frozen* f, const bench_solver* s, double budget,
                    const budget_point* bp, const fit* model)
{
    bench_table* t = &b->table;
    const bench_point* p = &bp->p;
    cvk_solver_desc d = bench_solver_desc(&f->scene.solver, s, 1, 1);
    bool fits = bp->fits;
    bench_table_row(t);
    bench_table_str(t, "label", s->label);
    bench_table_str(t, "solver", cvk_linear_solver_name(s->linear));
    bench_table_num(t, "omega", d.omega);
    bench_table_num(t, "budget_ms", budget);
    bench_table_int(t, "iterations", fits ? p->sweeps : 0);
    bench_table_int(t, "outer", fits ? p->sweeps / b->o->inner : 0);
    bench_table_int(t, "inner", b->o->inner);
    bench_table_num(t, "solve_ms", p->solve_ms.median);
    bench_table_num(t, "solve_ms_min", p->solve_ms.min);
    bench_table_num(t, "solve_ms_max", p->solve_ms.max);
    bench_table_int(t, "fits", fits);
    /* When not even one sweep fits, the solve never starts: the prediction stands. */
    double residual = fits ? p->residual : f->residual0;
    bench_table_num(t, "residual", residual);
    bench_table_num(t, "residual_relative", f->residual0 > 0 ? residual / f->residual0 : NAN);
    bench_table_num(t, "solve_error", fits ? p->solve_error : f->error0);
    bench_table_num(t, "ms_per_iteration", model->per_sweep);
    bench_table_num(t, "overhead_ms", model->overhead_ms);
    bench_table_num(t, "seed_002_gtx970", seed_iterations(s, budget));
}

static void print_tables(bench* b, const bench_frozen* f)
{
    const bench_table* t = &b->table;
    uint32_t ns = b->o->solver_count, nb = b->o->budget_count;
    printf("frozen substep: first of frame %u, h = %g s, %llu particles; start residual %.4g m^2, "
           "converged x* residual %.4g m^2 (Newton, last step %.3g m)\n", f->frame,
           (double)f->scene.dt, (unsigned long long)f->n, f->residual0, f->residual_star,
           f->star.last_step);
    const char* what[3] = {"iterations within the budget (solve pass; gs-cpu: host time)",
                           "residual reached, m^2", "solve error reached"};
    const char* column[3] = {"iterations", "residual", "solve_error"};
    for (int block = 0; block < 3; block++) {
        printf("%s\n%-9s", what[block], "budget");
        for (uint32_t s = 0; s < ns; s++)
            printf(" %11s", b->o->solvers[s].label);
        if (block == 0)
            printf("   | seed 002, GTX 970: RBGS GS Jacobi");
        printf("\n");
        for (uint32_t i = 0; i < nb; i++) {
            double budget = b->o->budgets[i];
            printf("%6g ms ", budget);
            for (uint32_t s = 0; s < ns; s++) {
                double v = bench_table_get(t, s * nb + i, column[block]);
                if (block == 0)
                    printf(" %11.0f", v);
                else
                    printf(" %11.3g", v);
            }
            bench_solver rbgs = {.linear = CVK_LINEAR_RBGS}, gs = {.linear = CVK_LINEAR_GS_CPU},
                         jacobi = {.linear = CVK_LINEAR_JACOBI};
            if (block == 0 && !isnan(seed_iterations(&rbgs, budget)))
                printf("   | %21s %4.0f %2.0f %6.0f", "", seed_iterations(&rbgs, budget),
                       seed_iterations(&gs, budget), seed_iterations(&jacobi, budget));
            printf("\n");
        }
    }
    printf("solve ms measured, median [min-max] of %u\n", b->o->repeat);
    for (uint32_t i = 0; i < nb; i++) {
        printf("%6g ms ", b->o->budgets[i]);
        for (uint32_t s = 0; s < ns; s++) {
            char cell[48];
            snprintf(cell, sizeof cell, "%.2f [%.2f-%.2f]", bench_table_get(t, s * nb + i, "solve_ms"),
                     bench_table_get(t, s * nb + i, "solve_ms_min"),
                     bench_table_get(t, s * nb + i, "solve_ms_max"));
            printf(" %18s", cell);
        }
        printf("\n");
    }
    printf("%-9s", "ms/iter");
    for (uint32_t s = 0; s < ns; s++)
        printf(" %11.4g", bench_table_get(t, s * nb, "ms_per_iteration"));
    printf("\n%-9s", "+ fixed");
    for (uint32_t s = 0; s < ns; s++)
        printf(" %11.4g", bench_table_get(t, s * nb, "overhead_ms"));
    printf("  (ms per solve pass)\n");
}

static void write_plot(bench* b, const bench_frozen* f)
{
    bench_text* t = &b->plot;
    bench_plot_styles(t);
    bench_text_add(t, "set multiplot layout 1,2 title \"%s, frozen substep of frame %u, on %s\"\n"
                      "set key top left\nset xlabel \"solve budget per substep (ms)\"\nset xtics (",
                   b->scene_name, f->frame, b->device);
    for (uint32_t i = 0; i < b->o->budget_count; i++)
        bench_text_add(t, "%s%g", i ? ", " : "", b->o->budgets[i]);
    bench_text_add(t, ")\n");
    bench_text_add(t, "set title \"iterations within the budget (dashed: seed 002, GTX 970)\"\n"
                      "set ylabel \"iterations\"\n");
    /* the seed's points beside ours, dashed in the same colours */
    bench_text seed = {0};
    const char* sep = "";
    for (uint32_t i = 0; i < b->o->solver_count; i++) {
        const bench_solver* s = &b->o->solvers[i];
        if (isnan(seed_iterations(s, 1.0)) && isnan(seed_iterations(s, 8.0)))
            continue;
        bench_text_add(&seed, "%s\"budget.csv\" using \"budget_ms\":(strcol(\"label\") eq \"%s\" ? "
                              "column(\"seed_002_gtx970\") : NaN) with linespoints linestyle %u "
                              "dashtype 3 pointtype 6 title \"%s, seed 002\"",
                       sep, s->label, i + 1, seed_name(s));
        sep = ", \\\n     ";
    }
    bench_plot_solvers(b, "budget.csv", "budget_ms", "iterations", "linespoints", true, true, NULL, &seed);
    bench_text_free(&seed);
    bench_text_add(t, "set title \"residual reached within the budget\"\nset key bottom left\n"
                      "set ylabel \"residual (m²)\"\nset format y \"%%.0e\"\n");
    bench_plot_solvers(b, "budget.csv", "budget_ms", "residual", "linespoints", true, true, NULL, NULL);
    bench_text_add(t, "unset multiplot\n");
}

int bench_budget(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    bench_frozen f;
    if (!bench_frozen_create(b, &f)) {
        bench_frozen_destroy(&f);
        return APP_EXIT_FAILURE;
    }
    double largest = 0.0;
    for (uint32_t i = 0; i < b->o->budget_count; i++)
        largest = fmax(largest, b->o->budgets[i]);
    bool ok = true;
    for (uint32_t s = 0; ok && s < b->o->solver_count; s++) {
        const bench_solver* solver = &b->o->solvers[s];
        fit model;
        ok = calibrate(b, &f, solver, largest, &model);
        for (uint32_t i = 0; ok && i < b->o->budget_count; i++) {
            budget_point bp;
            ok = fit_budget(b, &f, solver, &model, b->o->budgets[i], &bp);
            if (ok)
                add_row(b, &f, solver, b->o->budgets[i], &bp, &model);
        }
    }
    if (ok) {
        print_tables(b, &f);
        write_plot(b, &f);
    }
    bench_frozen_destroy(&f);
    return ok ? APP_EXIT_OK : APP_EXIT_FAILURE;
}
