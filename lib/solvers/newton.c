/* The converged solution of one substep by Newton's method (see reference.h): the ground
   truth the benchmark measures solve and trajectory errors against. Double precision, on the
   host, never on the fast path. Unknowns are the free particles; pinned ones stay put. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "solvers/reference.h"

/* CG stops at this relative residual, or sooner (inexact Newton), and after this many. */
#define CG_MIN_REDUCTION 1e-12
#define CG_MAX_ITERATIONS 100000u
/* Steps below this many tolerances are taken whole: E's change is then below its rounding. */
#define WHOLE_STEP_TOLERANCES 1e3

typedef struct work {
    const cvk_build* b;
    const double* y;
    double inv_h2;
    size_t nf3;                    /* 3 × free particles */
    double *g, *d, *r, *z, *p, *q; /* 3 per free particle */
    double* pre;                   /* 9 per free particle: inverse block-Jacobi blocks */
    double* dir;                   /* 3 per spring: unit direction a − b */
    double* alpha;                 /* per spring: max(0, 1 − L/l) */
    double* trial;                 /* 3 per particle */
} work;

static double dot(const double* a, const double* b, size_t n)
{
    double s = 0.0;
    for (size_t i = 0; i < n; i++)
        s += a[i] * b[i];
    return s;
}

static double max_abs(const double* a, size_t n)
{
    double m = 0.0;
    for (size_t i = 0; i < n; i++)
        m = fmax(m, fabs(a[i]));
    return m;
}

static double energy(const work* w, const double* x)
{
    const cvk_build* b = w->b;
    double e = 0.0;
    for (uint32_t p = 0; p < b->free_count; p++)
        for (int c = 0; c < 3; c++) {
            double d = x[3 * (size_t)p + c] - w->y[3 * (size_t)p + c];
            e += 0.5 * b->mass[p] * w->inv_h2 * d * d;
        }
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        const double* xa = &x[3 * (size_t)sp->a];
        const double* xb = &x[3 * (size_t)sp->b];
        double l = sqrt((xa[0] - xb[0]) * (xa[0] - xb[0]) + (xa[1] - xb[1]) * (xa[1] - xb[1]) +
                        (xa[2] - xb[2]) * (xa[2] - xb[2]));
        e += 0.5 * sp->k * (l - sp->rest) * (l - sp->rest);
    }
    return e;
}

/* Gradient into w->g; spring directions and clamped transverse factors for the Hessian. */
static void gradient(work* w, const double* x)
{
    const cvk_build* b = w->b;
    uint32_t nf = b->free_count;
    for (uint32_t p = 0; p < nf; p++)
        for (int c = 0; c < 3; c++)
            w->g[3 * (size_t)p + c] =
                b->mass[p] * w->inv_h2 * (x[3 * (size_t)p + c] - w->y[3 * (size_t)p + c]);
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        double e[3], l = 0.0;
        for (int c = 0; c < 3; c++) {
            e[c] = x[3 * (size_t)sp->a + c] - x[3 * (size_t)sp->b + c];
            l += e[c] * e[c];
        }
        l = sqrt(l);
        double* n = &w->dir[3 * (size_t)s];
        /* coincident ends: no direction and no stiffness to give (the mass term keeps H
           positive definite) */
        for (int c = 0; c < 3; c++)
            n[c] = l > 0.0 ? e[c] / l : 0.0;
        w->alpha[s] = l > 0.0 ? fmax(0.0, 1.0 - sp->rest / l) : 0.0;
        double f = sp->k * (l - sp->rest);
        for (int c = 0; c < 3; c++) {
            if (sp->a < nf)
                w->g[3 * (size_t)sp->a + c] += f * n[c];
            if (sp->b < nf)
                w->g[3 * (size_t)sp->b + c] -= f * n[c];
        }
    }
}

/* out = H v over the free particles (v of pinned particles is 0). */
static void hessian_times(const work* w, const double* v, double* out)
{
    const cvk_build* b = w->b;
    uint32_t nf = b->free_count;
    for (uint32_t p = 0; p < nf; p++)
        for (int c = 0; c < 3; c++)
            out[3 * (size_t)p + c] = b->mass[p] * w->inv_h2 * v[3 * (size_t)p + c];
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        const double* n = &w->dir[3 * (size_t)s];
        double dv[3];
        for (int c = 0; c < 3; c++)
            dv[c] = (sp->a < nf ? v[3 * (size_t)sp->a + c] : 0.0) -
                    (sp->b < nf ? v[3 * (size_t)sp->b + c] : 0.0);
        double along = n[0] * dv[0] + n[1] * dv[1] + n[2] * dv[2];
        for (int c = 0; c < 3; c++) {
            double f = sp->k * (along * n[c] + w->alpha[s] * (dv[c] - along * n[c]));
            if (sp->a < nf)
                out[3 * (size_t)sp->a + c] += f;
            if (sp->b < nf)
                out[3 * (size_t)sp->b + c] -= f;
        }
    }
}

static void invert3(const double m[9], double out[9])
{
    double c0 = m[4] * m[8] - m[5] * m[7], c1 = m[5] * m[6] - m[3] * m[8],
           c2 = m[3] * m[7] - m[4] * m[6];
    double inv = 1.0 / (m[0] * c0 + m[1] * c1 + m[2] * c2);
    out[0] = c0 * inv;
    out[1] = (m[2] * m[7] - m[1] * m[8]) * inv;
    out[2] = (m[1] * m[5] - m[2] * m[4]) * inv;
    out[3] = c1 * inv;
    out[4] = (m[0] * m[8] - m[2] * m[6]) * inv;
    out[5] = (m[2] * m[3] - m[0] * m[5]) * inv;
    out[6] = c2 * inv;
    out[7] = (m[1] * m[6] - m[0] * m[7]) * inv;
    out[8] = (m[0] * m[4] - m[1] * m[3]) * inv;
}

/* The 3×3 diagonal blocks of H, inverted. */
static void preconditioner(work* w)
{
    const cvk_build* b = w->b;
    uint32_t nf = b->free_count;
    double* blocks = w->pre;
    memset(blocks, 0, 9 * (size_t)nf * sizeof(double));
    for (uint32_t p = 0; p < nf; p++)
        for (int c = 0; c < 3; c++)
            blocks[9 * (size_t)p + 4 * c] = b->mass[p] * w->inv_h2;
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        const double* n = &w->dir[3 * (size_t)s];
        uint32_t ends[2] = {sp->a, sp->b};
        for (int e = 0; e < 2; e++) {
            if (ends[e] >= nf)
                continue;
            double* m = &blocks[9 * (size_t)ends[e]];
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    m[3 * i + j] += sp->k * ((1.0 - w->alpha[s]) * n[i] * n[j] + (i == j ? w->alpha[s] : 0.0));
        }
    }
    for (uint32_t p = 0; p < nf; p++) {
        double m[9];
        memcpy(m, &blocks[9 * (size_t)p], sizeof m);
        invert3(m, &blocks[9 * (size_t)p]);
    }
}

static void precondition(const work* w, const double* in, double* out)
{
    for (size_t p = 0; p < w->nf3 / 3; p++) {
        const double* m = &w->pre[9 * p];
        const double* v = &in[3 * p];
        for (int i = 0; i < 3; i++)
            out[3 * p + i] = m[3 * i] * v[0] + m[3 * i + 1] * v[1] + m[3 * i + 2] * v[2];
    }
}

/* d ≈ −H⁻¹ g to a relative residual `reduction`; returns the iterations. */
static uint64_t conjugate_gradients(work* w, double reduction)
{
    size_t n = w->nf3;
    memset(w->d, 0, n * sizeof(double));
    for (size_t i = 0; i < n; i++)
        w->r[i] = -w->g[i];
    precondition(w, w->r, w->z);
    memcpy(w->p, w->z, n * sizeof(double));
    double rz = dot(w->r, w->z, n), stop = reduction * sqrt(dot(w->r, w->r, n));
    uint64_t it = 0;
    while (it < CG_MAX_ITERATIONS && sqrt(dot(w->r, w->r, n)) > stop) {
        hessian_times(w, w->p, w->q);
        double pq = dot(w->p, w->q, n);
        if (!(pq > 0.0))
            break;
        double a = rz / pq;
        for (size_t i = 0; i < n; i++) {
            w->d[i] += a * w->p[i];
            w->r[i] -= a * w->q[i];
        }
        precondition(w, w->r, w->z);
        double rz_next = dot(w->r, w->z, n);
        for (size_t i = 0; i < n; i++)
            w->p[i] = w->z[i] + rz_next / rz * w->p[i];
        rz = rz_next;
        it++;
    }
    return it;
}

/* x ← x + t d with backtracking (Armijo) on E; returns t, 0 when E cannot fall further. */
static double line_search(work* w, double* x, double tolerance)
{
    size_t n_all = 3 * (size_t)w->b->particle_count;
    double step = max_abs(w->d, w->nf3);
    if (step <= WHOLE_STEP_TOLERANCES * tolerance) {
        for (size_t i = 0; i < w->nf3; i++)
            x[i] += w->d[i];
        return 1.0;
    }
    double e0 = energy(w, x), slope = dot(w->g, w->d, w->nf3);
    memcpy(w->trial, x, n_all * sizeof(double));
    for (double t = 1.0; t > 1e-12; t *= 0.5) {
        for (size_t i = 0; i < w->nf3; i++)
            w->trial[i] = x[i] + t * w->d[i];
        if (energy(w, w->trial) <= e0 + 1e-4 * t * slope) {
            memcpy(x, w->trial, w->nf3 * sizeof(double));
            return t;
        }
    }
    return 0.0;
}

/* The largest change Gauss-Seidel iterations make when started from x (x is kept). */
static double gauss_seidel_change(work* w, const cvk_ref_params* params, const double* x,
                                  uint32_t sweeps)
{
    const cvk_build* b = w->b;
    double* rhs = malloc(4 * (size_t)b->particle_count * sizeof(double));
    if (!rhs)
        return NAN;
    memcpy(w->trial, x, 3 * (size_t)b->particle_count * sizeof(double));
    double largest = 0.0;
    for (uint32_t s = 0; s < sweeps; s++) {
        cvk_ref_rhs(b, params, w->trial, w->y, rhs);
        largest = fmax(largest, cvk_ref_gauss_seidel_sweep(b, rhs, 1.0, w->trial));
    }
    free(rhs);
    return largest;
}

static bool alloc_work(work* w)
{
    size_t nf3 = w->nf3, springs = w->b->spring_count ? w->b->spring_count : 1;
    double** vectors[] = {&w->g, &w->d, &w->r, &w->z, &w->p, &w->q};
    bool ok = true;
    for (size_t i = 0; i < sizeof vectors / sizeof vectors[0]; i++)
        ok = (*vectors[i] = malloc((nf3 ? nf3 : 1) * sizeof(double))) && ok;
    ok = (w->pre = malloc((nf3 ? 3 * nf3 : 1) * sizeof(double))) && ok;
    ok = (w->dir = malloc(3 * springs * sizeof(double))) && ok;
    ok = (w->alpha = malloc(springs * sizeof(double))) && ok;
    ok = (w->trial = malloc(3 * (size_t)w->b->particle_count * sizeof(double))) && ok;
    return ok;
}

static void free_work(work* w)
{
    double* all[] = {w->g, w->d, w->r, w->z, w->p, w->q, w->pre, w->dir, w->alpha, w->trial};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        free(all[i]);
}

bool cvk_ref_solve_newton(const cvk_build* b, const cvk_ref_params* params, const double* y,
                          double tolerance, uint32_t max_steps, uint32_t check_sweeps, double* x,
                          cvk_ref_newton_report* report)
{
    work w = {.b = b, .y = y, .inv_h2 = params->inv_h2, .nf3 = 3 * (size_t)b->free_count};
    memset(report, 0, sizeof *report);
    if (!alloc_work(&w)) {
        free_work(&w);
        return false;
    }
    gradient(&w, x);
    double g0 = sqrt(dot(w.g, w.g, w.nf3));
    report->last_step = INFINITY;
    while (report->steps < max_steps && report->last_step > tolerance && w.nf3 > 0) {
        double g = sqrt(dot(w.g, w.g, w.nf3));
        if (g == 0.0) {
            report->last_step = 0.0;
            break;
        }
        /* inexact Newton (Eisenstat-Walker style): solve loosely far from x*, more tightly
           near it; superlinear convergence without solving every step to rounding */
        double reduction = fmax(CG_MIN_REDUCTION, fmin(0.1, sqrt(g / fmax(g0, 1e-300))));
        preconditioner(&w);
        report->cg_iterations += conjugate_gradients(&w, reduction);
        double t = line_search(&w, x, tolerance);
        report->steps++;
        report->last_step = t * max_abs(w.d, w.nf3);
        gradient(&w, x);
        if (t == 0.0)
            break; /* E cannot fall any more: x is as converged as doubles allow */
    }
    report->gradient = sqrt(dot(w.g, w.g, w.nf3));
    report->gs_change = check_sweeps ? gauss_seidel_change(&w, params, x, check_sweeps) : 0.0;
    free_work(&w);
    return true;
}
