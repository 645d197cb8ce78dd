/* explicit-stability: seed 001 §3 reproduced. On the scene (the seed's: 30 x 30 points,
   ks = 150, g = 9.8, h = 1 ms; assets/scenes/seed001.json), with the explicit method:
   - the largest stable damping kd at the scene's h for forward Euler and TVD-RK2;
   - with kd = --kd (default 10), the largest stable h for Euler, RK2 and Adams-Bashforth 4
     (and Verlet), and the ratio Euler / Adams-Bashforth.
   Each limit is measured by bisection on device runs (from rest with a 1 µm jitter; the
   stability verdict of verdict.c: the divergence watch, NaN, energy growth, stretch) and
   predicted beside it from
   the linearised system's stiffest mode: the largest eigenvalue λ_d of M⁻¹D (the damping
   matrix per unit kd, by power iteration on the host at the rest positions) with the
   stiffness of the same vector, k = uᵀM⁻¹Ku, put through the method's stability region
   (explicit_region.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "explicit_region.h"
#include "plot.h"

static const char* const columns[] = {
    "measure", "integrator", "damping_model", "dt", "kd", "measured", "unstable_at",
    "predicted", "measured_over_predicted", "seed", "lambda_d", "lambda_k", "runs", "steps",
};

#define POWER_ITERATIONS 3000

/* The stiffest mode of the linearised system at the build's positions. */
typedef struct mode {
    double d1; /* 1/s per N·s/m of kd: largest eigenvalue of M⁻¹D for kd = 1 */
    double k;  /* 1/s²: uᵀ M⁻¹K u for the same unit vector u */
} mode;

/* out = M⁻¹ A u over the free particles, A per spring on the relative motion r = u_p − u_c
   (a pinned neighbour does not move), n the spring's direction at the build's positions:
   the damping matrix per unit kd, (n·r) n along the spring or r for viscosity; or the
   stiffness matrix, k ((n·r) n + (1 − L/l)(r − (n·r) n)). */
static void apply(const cvk_build* b, bool stiffness, bool viscosity, const double* u, double* out)
{
    size_t nf = b->free_count;
    for (size_t p = 0; p < nf; p++) {
        double acc[3] = {0, 0, 0};
        for (uint32_t s = 0; s < b->max_degree; s++) {
            size_t e = (size_t)s * nf + p;
            uint32_t c = b->adj_index[e];
            double n[3], r[3], l = 0.0;
            for (int i = 0; i < 3; i++) {
                n[i] = (double)b->position[3 * p + i] - b->position[3 * (size_t)c + i];
                r[i] = u[3 * p + i] - (c < nf ? u[3 * (size_t)c + i] : 0.0);
                l += n[i] * n[i];
            }
            l = sqrt(l);
            if (l == 0.0) /* padding slots point at the particle itself */
                continue;
            for (int i = 0; i < 3; i++)
                n[i] /= l;
            double nr = n[0] * r[0] + n[1] * r[1] + n[2] * r[2];
            double t = 1.0 - b->adj_rest[e] / l;
            for (int i = 0; i < 3; i++) {
                if (stiffness)
                    acc[i] += b->adj_k[e] * (nr * n[i] + t * (r[i] - nr * n[i]));
                else
                    acc[i] += viscosity ? r[i] : nr * n[i];
            }
        }
        for (int i = 0; i < 3; i++)
            out[3 * p + i] = acc[i] / b->mass[p];
    }
}

static bool stiffest_mode(const cvk_scene_desc* scene, bool viscosity, mode* out)
{
    cvk_build b;
    cvk_error err;
    if (cvk_build_create(scene, &b, &err) != CVK_SUCCESS) {
        bench_fail(&err);
        return false;
    }
    size_t n3 = 3 * (size_t)b.free_count;
    double* u = malloc((2 * n3 + 1) * sizeof(double));
    if (!u) {
        cvk_build_destroy(&b);
        return false;
    }
    double* w = u + n3;
    uint32_t seed = 12345u;
    for (size_t i = 0; i < n3; i++) {
        seed = seed * 1664525u + 1013904223u;
        u[i] = (double)(seed >> 8) / 16777216.0 - 0.5;
    }
    double lambda = 0.0;
    for (int it = 0; it < POWER_ITERATIONS; it++) {
        double norm = 0.0;
        for (size_t i = 0; i < n3; i++)
            norm += u[i] * u[i];
        norm = sqrt(norm);
        for (size_t i = 0; i < n3; i++)
            u[i] /= norm > 0.0 ? norm : 1.0;
        apply(&b, false, viscosity, u, w);
        lambda = 0.0;
        for (size_t i = 0; i < n3; i++)
            lambda += u[i] * w[i];
        memcpy(u, w, n3 * sizeof(double));
    }
    double norm = 0.0, k = 0.0;
    for (size_t i = 0; i < n3; i++)
        norm += u[i] * u[i];
    for (size_t i = 0; i < n3; i++)
        u[i] /= sqrt(norm);
    apply(&b, true, viscosity, u, w);
    for (size_t i = 0; i < n3; i++)
        k += u[i] * w[i];
    *out = (mode){lambda, k};
    free(u);
    cvk_build_destroy(&b);
    return true;
}

/* ---- predictions ------------------------------------------------------------------------ */

static bool mode_stable(cvk_integrator i, const mode* m, double h, double kd)
{
    return cvk_explicit_mode_radius(i, h, m->d1 * kd, m->k) <= 1.0 + 1e-12;
}

/* The largest stable h (vary_kd false, kd fixed) or kd (h fixed): the top of the first stable
   interval on a 1 % grid from 1e-7, refined by bisection. NAN when none is found. */
static double predict(cvk_integrator i, const mode* m, bool vary_kd, double fixed)
{
    double lo = NAN, x = vary_kd ? 1e-4 : 1e-7, top = vary_kd ? 1e6 : 10.0;
    for (; x < top; x *= 1.01) {
        bool ok = vary_kd ? mode_stable(i, m, fixed, x) : mode_stable(i, m, x, fixed);
        if (ok)
            lo = x;
        else if (!isnan(lo))
            break;
    }
    if (isnan(lo) || x >= top)
        return NAN;
    double hi = x;
    for (int it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        bool ok = vary_kd ? mode_stable(i, m, fixed, mid) : mode_stable(i, m, mid, fixed);
        *(ok ? &lo : &hi) = mid;
    }
    return lo;
}

/* ---- measurements --------------------------------------------------------------------------- */

typedef struct limit {
    double stable, unstable; /* the bracket the bisection ended with */
    uint32_t runs;
    uint64_t steps;          /* per run at the stable end */
} limit;

static uint64_t steps_for(const bench* b, double h)
{
    double steps = ceil(b->o->time / h - 1e-9);
    return steps < b->o->min_steps ? b->o->min_steps : (uint64_t)fmin(steps, 1e9);
}

/* Moves every particle by up to JITTER m along each axis (a fixed pseudo-random pattern), so
   that every mode starts with some amplitude: a cloth hanging in its plane from a pinned row
   moves column by column in identical arithmetic, and modes that vary across it would never
   start from rounding alone. */
#define JITTER 1e-6

static bool jitter(cvk_sim* sim, cvk_error* err)
{
    uint64_t n = cvk_sim_particle_count(sim);
    float* xyz = malloc(3 * n * sizeof(float) + 1);
    if (!xyz) {
        snprintf(err->message, sizeof err->message, "out of host memory for the positions");
        return false;
    }
    bool ok = cvk_sim_read_positions(sim, xyz, n, err) == CVK_SUCCESS;
    uint32_t seed = 2463534242u;
    for (uint64_t i = 0; ok && i < 3 * n; i++) {
        seed ^= seed << 13, seed ^= seed >> 17, seed ^= seed << 5;
        xyz[i] += (float)(JITTER * ((double)seed / 4294967296.0 * 2.0 - 1.0));
    }
    ok = ok && cvk_sim_write_positions(sim, xyz, n, err) == CVK_SUCCESS;
    free(xyz);
    return ok;
}

/* One device run at (h, kd) from the jittered rest state; *stable receives the verdict. */
static bool run_once(bench* b, cvk_integrator i, double h, double kd, bool* stable, limit* l)
{
    cvk_scene_desc scene = *b->scene;
    scene.dt = (float)h;
    scene.substeps = 10;
    scene.solver.method = CVK_METHOD_EXPLICIT;
    scene.solver.linear = CVK_LINEAR_RBGS;
    scene.solver.integrator = i;
    scene.solver.kd = (float)kd;
    cvk_sim* sim = bench_sim_create(b, &scene);
    if (!sim)
        return false;
    cvk_error err;
    bench_stability_run r = {0};
    bool ok = jitter(sim, &err) &&
              bench_run_stability(sim, &scene, steps_for(b, h), b->o->energy_bound,
                                  b->o->stretch_bound, &r, &err);
    if (!ok)
        bench_fail(&err);
    cvk_sim_destroy(sim);
    *stable = r.verdict == BENCH_STABLE;
    l->runs++;
    return ok;
}

/* The largest stable h (or kd) near the prediction `guess`: a bracket found by halving and
   doubling from 0.6 and 1.9 times it (off-centre, so no run lands on the prediction itself
   unless the bisection gets there), then bisection in log space to --limit-ratio. */
static bool measure(bench* b, cvk_integrator i, bool vary_kd, double fixed, double guess,
                    limit* out)
{
    *out = (limit){NAN, NAN, 0, 0};
    double lo = guess * 0.6, hi = guess * 1.9;
    bool ok = true, stable = false;
#define RUN(x) (vary_kd ? run_once(b, i, fixed, (x), &stable, out) \
                        : run_once(b, i, (x), fixed, &stable, out))
    for (int tries = 0; ok && tries < 4; tries++, lo /= 2) {
        ok = RUN(lo);
        if (!ok || stable)
            break;
        hi = lo;
    }
    if (!ok || !stable)
        return ok;
    for (int tries = 0; ok && tries < 4; tries++, hi *= 2) {
        ok = RUN(hi);
        if (!ok || !stable)
            break;
        lo = hi;
    }
    if (!ok || stable)
        return ok;
    while (ok && hi / lo > b->o->limit_ratio) {
        double mid = sqrt(lo * hi);
        ok = RUN(mid);
        *(stable ? &lo : &hi) = mid;
    }
#undef RUN
    *out = (limit){lo, hi, out->runs, steps_for(b, vary_kd ? fixed : lo)};
    return ok;
}

static void add_row(bench* b, const char* measure_name, const char* integrator, double h,
                    double kd, const limit* l, double predicted, const mode* m, const char* seed)
{
    bench_table* t = &b->table;
    bench_table_row(t);
    bench_table_str(t, "measure", measure_name);
    bench_table_str(t, "integrator", integrator);
    bench_table_str(t, "damping_model",
                    cvk_damping_model_name(b->scene->solver.damping_model == CVK_DAMPING_VISCOSITY
                                               ? CVK_DAMPING_VISCOSITY
                                               : CVK_DAMPING_SPRING));
    if (!isnan(h)) /* the fixed one of the two */
        bench_table_num(t, "dt", h);
    if (!isnan(kd))
        bench_table_num(t, "kd", kd);
    bench_table_num(t, "measured", l->stable);
    bench_table_num(t, "unstable_at", l->unstable);
    bench_table_num(t, "predicted", predicted);
    bench_table_num(t, "measured_over_predicted", l->stable / predicted);
    bench_table_str(t, "seed", seed);
    bench_table_num(t, "lambda_d", m->d1);
    bench_table_num(t, "lambda_k", m->k);
    if (l->runs) {
        bench_table_int(t, "runs", l->runs);
        bench_table_int(t, "steps", l->steps);
    }
}

static void print_row(const char* what, const limit* l, double predicted, const char* unit,
                      double scale, const char* seed)
{
    printf("  %-34s measured %8.4g %s (unstable at %.4g), predicted %8.4g %s (%+.1f %%), "
           "seed %s\n", what, l->stable * scale, unit, l->unstable * scale, predicted * scale,
           unit, 100.0 * (l->stable / predicted - 1.0), seed);
}

static void write_plot(bench* b)
{
    bench_plot_styles(&b->plot);
    bench_text_add(&b->plot,
                   "set title \"%s: measured against predicted stability limits, on %s\"\n"
                   "set ylabel \"measured / predicted\"\nset yrange [0:2]\nset xtics rotate by "
                   "-30 font \",8\"\nset style fill solid 0.6\nset boxwidth 0.6\n"
                   "set arrow from graph 0, first 1 to graph 1, first 1 nohead dashtype 2\n"
                   "plot \"explicit-stability.csv\" using 0:\"measured_over_predicted\":"
                   "xtic(sprintf(\"%%s %%s\", strcol(\"integrator\"), strcol(\"measure\"))) "
                   "with boxes linestyle 1 notitle\n",
                   b->scene_name, b->device);
}

static const cvk_integrator h_integrators[] = {CVK_INTEGRATOR_EULER, CVK_INTEGRATOR_RK2,
                                               CVK_INTEGRATOR_AB4, CVK_INTEGRATOR_VERLET};
static const char* const h_seed[] = {"0.00093", "0.00104", "0.00014-0.00015", ""};

int bench_explicit_stability(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    bool viscosity = b->scene->solver.damping_model == CVK_DAMPING_VISCOSITY;
    mode m;
    if (!stiffest_mode(b->scene, viscosity, &m))
        return APP_EXIT_FAILURE;
    double h = b->scene->dt, kd = b->o->kd;
    printf("stiffest mode: lambda_d %.5g 1/s per N s/m, lambda_k %.5g 1/s^2; runs of %g s "
           "(at least %u steps) from rest\n", m.d1, m.k, b->o->time, b->o->min_steps);
    printf("largest stable kd at h = %g s:\n", h);
    const cvk_integrator kd_integrators[] = {CVK_INTEGRATOR_EULER, CVK_INTEGRATOR_RK2};
    const char* const kd_seed[] = {"9", "11"};
    for (size_t k = 0; k < 2; k++) {
        cvk_integrator i = kd_integrators[k];
        double predicted = predict(i, &m, true, h);
        limit l;
        if (!measure(b, i, true, h, predicted, &l))
            return APP_EXIT_FAILURE;
        add_row(b, "largest stable kd", cvk_integrator_name(i), h, NAN, &l, predicted, &m,
                kd_seed[k]);
        print_row(cvk_integrator_name(i), &l, predicted, "N s/m", 1.0, kd_seed[k]);
    }
    printf("largest stable h at kd = %g N s/m:\n", kd);
    limit euler = {0}, ab = {0};
    double euler_p = NAN, ab_p = NAN;
    for (size_t k = 0; k < 4; k++) {
        cvk_integrator i = h_integrators[k];
        double predicted = predict(i, &m, false, kd);
        limit l;
        if (!measure(b, i, false, kd, predicted, &l))
            return APP_EXIT_FAILURE;
        add_row(b, "largest stable h", cvk_integrator_name(i), NAN, kd, &l, predicted, &m,
                h_seed[k]);
        print_row(cvk_integrator_name(i), &l, predicted, "s", 1.0, h_seed[k][0] ? h_seed[k] : "-");
        if (i == CVK_INTEGRATOR_EULER) {
            euler = l;
            euler_p = predicted;
        } else if (i == CVK_INTEGRATOR_AB4) {
            ab = l;
            ab_p = predicted;
        }
    }
    limit ratio = {euler.stable / ab.stable, euler.unstable / ab.unstable, 0, 0};
    add_row(b, "h ratio", "euler / adams-bashforth", NAN, kd, &ratio, euler_p / ab_p, &m,
            "6.2 (predicted 6.66)");
    print_row("ratio euler / adams-bashforth", &ratio, euler_p / ab_p, "", 1.0,
              "6.2 (predicted 6.66)");
    write_plot(b);
    return APP_EXIT_OK;
}
