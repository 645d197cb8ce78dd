/* stability: where each solver stays a cloth. Sweeps h x stiffness (x damping) per solver
   setting, from rest, one substep per frame, for --time simulated seconds (at least
   --min-steps steps). A run is unstable when a coordinate becomes NaN or infinite, its energy
   grows by more than --energy-bound energy scales, or a spring stretches past
   --stretch-bound (see verdict.c). The largest stable h of every setting and stiffness is
   found by bisection between the grid points; then the extremes a user will try: h = 1/30 s,
   stiffness 1e8, a pin far from its rest position, coincident and collapsed particles.
   Seed 001 §3 measured such limits for explicit integrators. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "plot.h"

static const char* const columns[] = {
    "kind", "case", "label", "solver", "omega", "iterations", "outer", "inner", "dt",
    "dt_unstable", "substeps", "stiffness", "damping", "steps", "stable", "reason",
    "failed_at_step", "max_stretch", "energy_growth", "nan_count",
};

#define PIN_OFFSET 1.0     /* m: how far the moved pin is from its rest position */
#define EXTREME_STIFFNESS 1e8
#define MAX_CLOTHS 64

/* One solver setting: a --solvers entry with a sweep count. */
typedef struct setting {
    const bench_solver* solver;
    cvk_solver_desc desc;
    char name[64];   /* "rbgs 4x4" */
} setting;

/* What a run changes in the scene and in the positions it starts from. */
typedef enum extreme {
    NONE,
    LONG_STEP,   /* h = 1/30 s, one substep */
    STIFF,       /* stiffness 1e8 */
    FAR_PIN,     /* the first pin moved PIN_OFFSET along u */
    COINCIDENT,  /* row 1 of the first cloth on row 0 */
    COLLAPSED,   /* every particle of the first cloth at its centre */
    EXTREME_COUNT
} extreme;

static const char* const extreme_names[EXTREME_COUNT] = {
    "", "h = 1/30 s, 1 substep", "stiffness 1e8", "pin 1 m off its rest position",
    "coincident rows", "collapsed to a point",
};

typedef struct config {
    const setting* s;
    double dt, stiffness, damping;
    extreme what;
} config;

typedef struct scene_copy {
    cvk_scene_desc scene;
    cvk_cloth_desc cloths[MAX_CLOTHS];
    uint32_t pins[1][2];
} scene_copy;

/* The bench scene with the config's step, stiffness, damping and solver. */
static void make_scene(const bench* b, const config* c, scene_copy* out)
{
    out->scene = *b->scene;
    out->scene.dt = (float)c->dt;
    out->scene.substeps = 1;
    out->scene.damping = (float)c->damping;
    out->scene.solver = c->s->desc;
    uint32_t count = b->scene->cloth_count < MAX_CLOTHS ? b->scene->cloth_count : MAX_CLOTHS;
    for (uint32_t i = 0; i < count; i++) {
        cvk_cloth_desc* cloth = &out->cloths[i];
        *cloth = b->scene->cloths[i];
        double scale = cloth->stiffness.structural > 0.0f
                           ? c->stiffness / cloth->stiffness.structural
                           : 1.0;
        cloth->stiffness.structural = (float)c->stiffness;
        cloth->stiffness.shear = (float)(cloth->stiffness.shear * scale);
        cloth->stiffness.bend = (float)(cloth->stiffness.bend * scale);
    }
    out->scene.cloths = out->cloths;
    out->scene.cloth_count = count;
    if (c->what == FAR_PIN && out->cloths[0].pin_count == 0) {
        out->pins[0][0] = 0;
        out->pins[0][1] = 0;
        out->cloths[0].pins = (const uint32_t(*)[2])out->pins;
        out->cloths[0].pin_count = 1;
    }
}

/* Moves particles of the first cloth (user order: it comes first) for the extremes. */
static void disturb(const scene_copy* sc, extreme what, float* xyz)
{
    const cvk_cloth_desc* cloth = &sc->cloths[0];
    uint32_t nu = cloth->grid[0], nv = cloth->grid[1];
    if (what == FAR_PIN) {
        uint32_t at = cloth->pins[0][1] * nu + cloth->pins[0][0];
        double len = sqrt((double)cloth->u_axis[0] * cloth->u_axis[0] +
                          (double)cloth->u_axis[1] * cloth->u_axis[1] +
                          (double)cloth->u_axis[2] * cloth->u_axis[2]);
        for (int c = 0; c < 3; c++)
            xyz[3 * at + c] += (float)(PIN_OFFSET * cloth->u_axis[c] / len);
    } else if (what == COINCIDENT && nv > 1) {
        memcpy(&xyz[3 * nu], &xyz[0], 3 * (size_t)nu * sizeof(float));
    } else if (what == COLLAPSED) {
        double centre[3] = {0, 0, 0};
        for (uint32_t p = 0; p < nu * nv; p++)
            for (int c = 0; c < 3; c++)
                centre[c] += xyz[3 * p + c] / (double)(nu * nv);
        for (uint32_t p = 0; p < nu * nv; p++)
            for (int c = 0; c < 3; c++)
                xyz[3 * p + c] = (float)centre[c];
    }
}

static uint64_t steps_for(const bench* b, double dt)
{
    double steps = ceil(b->o->time / dt - 1e-9);
    return steps < b->o->min_steps ? b->o->min_steps : (uint64_t)fmin(steps, 1e9);
}

static bool run_config(bench* b, const config* c, bench_stability_run* out)
{
    scene_copy sc;
    make_scene(b, c, &sc);
    cvk_sim* sim = bench_sim_create(b, &sc.scene);
    if (!sim)
        return false;
    cvk_error err;
    bool ok = true;
    if (c->what == FAR_PIN || c->what == COINCIDENT || c->what == COLLAPSED) {
        uint64_t n = cvk_sim_particle_count(sim);
        float* xyz = malloc(3 * n * sizeof(float));
        ok = xyz && cvk_sim_read_positions(sim, xyz, n, &err) == CVK_SUCCESS;
        if (ok) {
            disturb(&sc, c->what, xyz);
            ok = cvk_sim_write_positions(sim, xyz, n, &err) == CVK_SUCCESS;
        }
        if (!xyz)
            snprintf(err.message, sizeof err.message, "out of memory");
        free(xyz);
    }
    if (ok)
        ok = bench_run_stability(sim, &sc.scene, steps_for(b, c->dt), b->o->energy_bound,
                                 b->o->stretch_bound, out, &err);
    if (!ok)
        bench_fail(&err);
    cvk_sim_destroy(sim);
    return ok;
}

static void add_row(bench* b, const char* kind, const config* c, const bench_stability_run* r,
                    double dt_unstable)
{
    bench_table* t = &b->table;
    const cvk_solver_desc* d = &c->s->desc;
    bench_table_row(t);
    bench_table_str(t, "kind", kind);
    bench_table_str(t, "case", c->what == NONE ? "" : extreme_names[c->what]);
    bench_table_str(t, "label", c->s->solver->label);
    bench_table_str(t, "solver", cvk_linear_solver_name(d->linear));
    bench_table_num(t, "omega", d->omega);
    bench_table_int(t, "iterations", bench_sweeps(d));
    bench_table_int(t, "outer", d->outer_iterations);
    bench_table_int(t, "inner", d->inner_iterations);
    bench_table_num(t, "dt", c->dt);
    bench_table_num(t, "dt_unstable", dt_unstable);
    bench_table_int(t, "substeps", 1);
    bench_table_num(t, "stiffness", c->stiffness);
    bench_table_num(t, "damping", c->damping);
    if (!r)
        return;
    bench_table_int(t, "steps", steps_for(b, c->dt));
    bench_table_int(t, "stable", r->verdict == BENCH_STABLE);
    bench_table_str(t, "reason", bench_verdict_name(r->verdict));
    if (r->verdict != BENCH_STABLE)
        bench_table_int(t, "failed_at_step", r->steps_done);
    bench_table_num(t, "max_stretch", r->max_stretch);
    bench_table_num(t, "energy_growth", r->growth);
    bench_table_int(t, "nan_count", r->nan_count);
}

/* Largest stable h of a config between a stable lo and an unstable hi, by bisection in
   log h; returns false on a failure to run. */
static bool bisect(bench* b, config c, double* lo, double* hi)
{
    while (*hi / *lo > b->o->limit_ratio) {
        c.dt = sqrt(*lo * *hi);
        bench_stability_run r;
        if (!run_config(b, &c, &r))
            return false;
        if (r.verdict == BENCH_STABLE)
            *lo = c.dt;
        else
            *hi = c.dt;
    }
    return true;
}

static char symbol(bench_verdict v)
{
    static const char symbols[] = {'.', 'N', 'E', 'S'};
    return symbols[v];
}

/* The grid of one setting and damping: a map printed as it fills, then the limits. */
static bool run_grid(bench* b, const setting* s, double damping)
{
    const bench_options* o = b->o;
    printf("%s, damping %g: stable region ('.' stable, N NaN/inf, E energy, S stretch)\n",
           s->name, damping);
    printf("  stiffness \\ h (ms)");
    for (uint32_t i = 0; i < o->dt_count; i++)
        printf(" %6.3g", o->dts[i] * 1e3);
    printf("   largest stable h\n");
    double lo[BENCH_MAX_LIST], hi[BENCH_MAX_LIST];
    for (uint32_t k = 0; k < o->stiffness_count; k++) {
        config c = {s, 0.0, o->stiffness[k], damping, NONE};
        lo[k] = hi[k] = NAN;
        printf("  %18.3g", c.stiffness);
        fflush(stdout);
        for (uint32_t i = 0; i < o->dt_count; i++) {
            c.dt = o->dts[i];
            bench_stability_run r;
            if (!run_config(b, &c, &r))
                return false;
            add_row(b, "grid", &c, &r, NAN);
            bool stable = r.verdict == BENCH_STABLE;
            if (stable && isnan(hi[k]))
                lo[k] = c.dt;
            else if (!stable && isnan(hi[k]))
                hi[k] = c.dt;
            printf(" %6c", symbol(r.verdict));
            fflush(stdout);
        }
        if (!isnan(lo[k]) && !isnan(hi[k]) && !bisect(b, c, &lo[k], &hi[k]))
            return false;
        if (isnan(lo[k]))
            printf("   below %.3g ms\n", o->dts[0] * 1e3);
        else if (isnan(hi[k]))
            printf("   at least %.3g ms (all stable)\n", lo[k] * 1e3);
        else
            printf("   %.3g ms (unstable at %.3g)\n", lo[k] * 1e3, hi[k] * 1e3);
    }
    /* one block per setting, so the plot draws the limits as one line */
    for (uint32_t k = 0; k < o->stiffness_count; k++) {
        config c = {s, lo[k], o->stiffness[k], damping, NONE};
        add_row(b, "limit", &c, NULL, hi[k]);
    }
    return true;
}

static bool run_extremes(bench* b, const setting* settings, uint32_t count)
{
    printf("extremes (stiffness %g unless named, h = %g s unless named):\n",
           b->scene->cloths[0].stiffness.structural, (double)b->scene->dt);
    printf("  %-30s", "case");
    for (uint32_t s = 0; s < count; s++)
        printf(" %18s", settings[s].name);
    printf("\n");
    for (int e = LONG_STEP; e < EXTREME_COUNT; e++) {
        printf("  %-30s", extreme_names[e]);
        for (uint32_t s = 0; s < count; s++) {
            config c = {&settings[s], b->scene->dt, b->scene->cloths[0].stiffness.structural,
                        b->o->damping[0], (extreme)e};
            if (e == LONG_STEP)
                c.dt = 1.0 / 30.0;
            if (e == STIFF)
                c.stiffness = EXTREME_STIFFNESS;
            bench_stability_run r;
            if (!run_config(b, &c, &r))
                return false;
            add_row(b, "extreme", &c, &r, NAN);
            char cell[32];
            snprintf(cell, sizeof cell, "%s %.3g%%", bench_verdict_name(r.verdict),
                     100.0 * r.max_stretch);
            printf(" %18s", cell);
            fflush(stdout);
        }
        printf("\n");
    }
    printf("  (cells: verdict and the largest stretch at the end)\n");
    return true;
}

static void plot_panel(bench* b, const setting* s, double damping)
{
    bench_text* t = &b->plot;
    char filter[256];
    snprintf(filter, sizeof filter,
             "strcol(\"label\") eq \"%s\" && column(\"iterations\") == %u && column(\"damping\") == %g",
             s->solver->label, bench_sweeps(&s->desc), damping);
    bench_text_add(t, "set title \"%s, damping %g\"\n", s->name, damping);
    bench_text_add(t,
        "plot \"stability.csv\" using \"dt\":(strcol(\"kind\") eq \"grid\" && %s && "
        "column(\"stable\") == 1 ? column(\"stiffness\") : NaN) with points pointtype 7 "
        "linecolor rgb \"#2ca02c\" title \"stable\", \\\n"
        "     \"\" using \"dt\":(strcol(\"kind\") eq \"grid\" && %s && strcol(\"reason\") eq \"nan\" "
        "? column(\"stiffness\") : NaN) with points pointtype 2 linecolor rgb \"#d62728\" "
        "title \"NaN\", \\\n"
        "     \"\" using \"dt\":(strcol(\"kind\") eq \"grid\" && %s && strcol(\"reason\") eq "
        "\"energy\" ? column(\"stiffness\") : NaN) with points pointtype 9 linecolor rgb "
        "\"#ff7f0e\" title \"energy\", \\\n"
        "     \"\" using \"dt\":(strcol(\"kind\") eq \"grid\" && %s && strcol(\"reason\") eq "
        "\"stretch\" ? column(\"stiffness\") : NaN) with points pointtype 5 linecolor rgb "
        "\"#9467bd\" title \"stretch\", \\\n"
        "     \"\" using \"dt\":(strcol(\"kind\") eq \"limit\" && %s ? column(\"stiffness\") : NaN) "
        "with linespoints linecolor rgb \"black\" pointtype 1 title \"largest stable h\"\n",
        filter, filter, filter, filter, filter);
}

static void write_plot(bench* b, const setting* settings, uint32_t count)
{
    bench_text* t = &b->plot;
    uint32_t panels = count * b->o->damping_count;
    uint32_t across = panels < 4 ? panels : 4;
    uint32_t down = (panels + across - 1) / across;
    /* the key sits in room left free below the lowest stiffness */
    bench_text_add(t, "set multiplot layout %u,%u title \"%s: stable region over h and stiffness "
                      "(%g s simulated, at least %u steps), on %s\"\n"
                      "set logscale xy\nset format x \"%%.0e\"\nset format y \"%%.0e\"\n"
                      "set xlabel \"h (s)\"\nset ylabel \"stiffness (N/m)\"\n"
                      "set offsets graph 0.05, graph 0.05, graph 0.05, graph 0.45\n"
                      "set key bottom center horizontal maxcols 3 font \",8\"\n",
                   down, across, b->scene_name, b->o->time, b->o->min_steps, b->device);
    b->plot_height = 60 + 330 * (int)down;
    for (uint32_t s = 0; s < count; s++)
        for (uint32_t d = 0; d < b->o->damping_count; d++)
            plot_panel(b, &settings[s], b->o->damping[d]);
    bench_text_add(t, "unset multiplot\n");
}

/* One setting per solver and --iterations entry (the scene's outer x inner without). */
static uint32_t make_settings(const bench* b, setting* out)
{
    const bench_options* o = b->o;
    uint32_t n = 0, counts = o->iteration_count ? o->iteration_count : 1;
    for (uint32_t s = 0; s < o->solver_count; s++)
        for (uint32_t k = 0; k < counts && n < BENCH_MAX_LIST; k++) {
            setting* st = &out[n];
            st->solver = &o->solvers[s];
            if (o->iteration_count)
                st->desc = bench_solver_desc(&b->scene->solver, st->solver, o->iterations[k], o->inner);
            else
                st->desc = bench_solver_desc(&b->scene->solver, st->solver,
                                             bench_sweeps(&b->scene->solver),
                                             b->scene->solver.inner_iterations);
            snprintf(st->name, sizeof st->name, "%s %ux%u", st->solver->label,
                     st->desc.outer_iterations, st->desc.inner_iterations);
            n++;
        }
    return n;
}

int bench_stability(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    if (b->scene->cloth_count > MAX_CLOTHS) {
        app_error("clothvk-bench", "stability handles scenes of up to %d cloths", MAX_CLOTHS);
        return APP_EXIT_FAILURE;
    }
    setting settings[BENCH_MAX_LIST];
    uint32_t count = make_settings(b, settings);
    printf("from rest, one substep per frame, %g s simulated (at least %u steps); unstable: "
           "NaN/inf, energy growth > %g energy scales, stretch > %g%%\n",
           b->o->time, b->o->min_steps, b->o->energy_bound, 100.0 * b->o->stretch_bound);
    bool ok = true;
    for (uint32_t s = 0; ok && s < count; s++)
        for (uint32_t d = 0; ok && d < b->o->damping_count; d++)
            ok = run_grid(b, &settings[s], b->o->damping[d]);
    if (ok)
        ok = run_extremes(b, settings, count);
    if (ok)
        write_plot(b, settings, count);
    return ok ? APP_EXIT_OK : APP_EXIT_FAILURE;
}
