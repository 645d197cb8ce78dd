/* scaling: GPU time per frame and per pass against particle count and iteration count
   (seed 000 §6.1 and appendix C.1: particles x iterations -> frame rate). Square grids from
   32 x 32 up to the largest the device and the host memory hold; the cloth hangs from the two
   corners of its first row like hanging.json, or follows the scene given (its first cloth,
   its pins moved to the same relative places). With colliders or self-contact in the scene,
   the collision passes are timed too (colliders, hash, contacts, contact; not a number when
   the scene records none), so the cost of contact against particle count is one run:
   `clothvk-bench scaling assets/scenes/hanging.json --set collision.self=true`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"
#include "plot.h"

static const char* const columns[] = {
    "label", "solver", "omega", "grid", "particles", "iterations", "outer", "inner", "substeps",
    "frame_ms", "frame_ms_min", "frame_ms_max", "predict_ms", "solve_ms", "finalize_ms",
    "colliders_ms", "hash_ms", "contacts_ms", "contact_ms", "ms_per_iteration", "ns_per_particle_iteration", "fps", "wall_ms", "dispatches_per_frame",
};

/* Host memory a particle costs (simulation, build and this tool), measured on lavapipe where
   device memory is host memory too; the largest grid keeps within half the machine. */
#define BYTES_PER_PARTICLE 600.0
#define MAX_PINS 64

/* The collision passes (lib/contact/collide_passes.c, the families' contact pass) and their columns. */
#define CONTACT_PASSES 4
static const char* const contact_pass[CONTACT_PASSES] = {"colliders", "hash", "contacts",
                                                          "contact"};
static const char* const contact_column[CONTACT_PASSES] = {"colliders_ms", "hash_ms",
                                                            "contacts_ms", "contact_ms"};

typedef struct template_scene {
    cvk_scene_desc scene;
    cvk_cloth_desc cloth;
    uint32_t pins[MAX_PINS][2];
} template_scene;

static void make_scene(const bench* b, uint32_t n, template_scene* out)
{
    if (!b->scene) {
        /* hanging.json's cloth, pinned at the two corners of its first row */
        out->scene = cvk_default_scene_desc();
        out->scene.name = "built-in hanging";
        out->cloth = cvk_default_cloth_desc();
        out->cloth.origin[2] = -0.5f;
        out->pins[0][0] = 0;
        out->pins[0][1] = 0;
        out->pins[1][0] = n - 1;
        out->pins[1][1] = 0;
        out->cloth.pin_count = 2;
    } else {
        /* the scene's first cloth, its pins at the same relative places */
        out->scene = *b->scene;
        out->cloth = b->scene->cloths[0];
        if (out->cloth.pin_count > MAX_PINS)
            out->cloth.pin_count = MAX_PINS;
        for (uint32_t p = 0; p < out->cloth.pin_count; p++)
            for (int a = 0; a < 2; a++) {
                uint32_t size = out->cloth.grid[a];
                out->pins[p][a] = size > 1 ? (uint32_t)lround((double)out->cloth.pins[p][a] *
                                                              (n - 1) / (size - 1))
                                           : 0;
            }
    }
    out->cloth.pins = (const uint32_t(*)[2])out->pins;
    out->cloth.grid[0] = out->cloth.grid[1] = n;
    out->scene.cloths = &out->cloth;
    out->scene.cloth_count = 1;
}

static uint32_t default_grids(const bench* b, uint32_t* out)
{
    double pages = (double)sysconf(_SC_PHYS_PAGES) * (double)sysconf(_SC_PAGESIZE);
    double by_memory = pages > 0 ? 0.5 * pages / BYTES_PER_PARTICLE : 1e7;
    double by_device = (double)cvk_context_get_info(b->ctx).max_particles;
    uint32_t largest = (uint32_t)floor(sqrt(fmin(by_memory, by_device)));
    uint32_t n = 0;
    for (uint32_t g = 32; g <= largest && n < BENCH_MAX_LIST - 1; g *= 2)
        out[n++] = g;
    if (n == 0 || out[n - 1] != largest)
        out[n++] = largest;
    return n;
}

typedef struct measured {
    bench_timing frame_ms;
    double pass_ms[CVK_MAX_PASSES];
    double wall_ms;
    cvk_sim_stats timing; /* names and dispatch counts */
} measured;

/* Times one point; *diverged is set (with the reason in *err, and true returned) when the
   scene ran away during it: a timing experiment reports that and goes on to the next point. */
static bool time_point(bench* b, cvk_sim* sim, measured* out, bool* diverged, cvk_error* err)
{
    uint32_t total = b->o->warmup + b->o->repeat;
    double frame[1000], wall[1000], pass[CVK_MAX_PASSES][1000];
    uint32_t m = 0, walls = 0;
    *diverged = false;
    for (uint32_t f = 0; f < total; f++) {
        double t0 = app_now_ms();
        cvk_result r = cvk_sim_step(sim, 1, err);
        if (r == CVK_ERROR_DIVERGED) {
            *diverged = true;
            return true;
        }
        if (r != CVK_SUCCESS) {
            bench_fail(err);
            return false;
        }
        double elapsed = app_now_ms() - t0;
        cvk_sim_get_timing(sim, &out->timing);
        if (f < b->o->warmup)
            continue;
        wall[walls++] = elapsed; /* the only measure on a device without timestamps */
        if (out->timing.gpu_ms_per_frame < 0.0)
            continue;
        frame[m] = out->timing.gpu_ms_per_frame;
        for (uint32_t p = 0; p < out->timing.pass_count && p < CVK_MAX_PASSES; p++)
            pass[p][m] = out->timing.passes[p].gpu_ms;
        m++;
    }
    out->frame_ms = bench_timing_of(frame, m);
    out->wall_ms = bench_timing_of(wall, walls).median;
    for (uint32_t p = 0; p < CVK_MAX_PASSES; p++)
        out->pass_ms[p] = p < out->timing.pass_count ? bench_timing_of(pass[p], m).median : NAN;
    return true;
}

static double pass_of(const measured* m, const char* name)
{
    for (uint32_t p = 0; p < m->timing.pass_count && p < CVK_MAX_PASSES; p++)
        if (!strcmp(m->timing.passes[p].name, name))
            return m->pass_ms[p];
    return NAN;
}

static void add_row(bench* b, const bench_solver* s, const cvk_solver_desc* d, uint32_t grid,
                    uint32_t substeps, const measured* m)
{
    bench_table* t = &b->table;
    double particles = (double)grid * grid, sweeps = bench_sweeps(d);
    double solve = pass_of(m, "solve");
    bench_table_row(t);
    bench_table_str(t, "label", s->label);
    bench_table_str(t, "solver", cvk_linear_solver_name(s->linear));
    bench_table_num(t, "omega", d->omega);
    bench_table_int(t, "grid", grid);
    bench_table_int(t, "particles", (uint64_t)particles);
    bench_table_int(t, "iterations", (uint64_t)sweeps);
    bench_table_int(t, "outer", d->outer_iterations);
    bench_table_int(t, "inner", d->inner_iterations);
    bench_table_int(t, "substeps", substeps);
    bench_table_num(t, "frame_ms", m->frame_ms.median);
    bench_table_num(t, "frame_ms_min", m->frame_ms.min);
    bench_table_num(t, "frame_ms_max", m->frame_ms.max);
    /* implicit Euler's passes around the solve: assemble before, integrate after */
    bool implicit = d->method == CVK_METHOD_IMPLICIT;
    bench_table_num(t, "predict_ms", pass_of(m, implicit ? "assemble" : "predict"));
    bench_table_num(t, "solve_ms", solve);
    bench_table_num(t, "finalize_ms", pass_of(m, implicit ? "integrate" : "finalize"));
    for (uint32_t c = 0; c < CONTACT_PASSES; c++)
        bench_table_num(t, contact_column[c], pass_of(m, contact_pass[c]));
    bench_table_num(t, "ms_per_iteration", solve / (sweeps * substeps));
    bench_table_num(t, "ns_per_particle_iteration", 1e6 * solve / (sweeps * substeps * particles));
    bench_table_num(t, "fps", 1e3 / m->frame_ms.median);
    bench_table_num(t, "wall_ms", m->wall_ms);
    bench_table_int(t, "dispatches_per_frame", m->timing.dispatches_per_frame);
}

/* True when any point ran a collision pass. */
static bool any_contact(const bench_table* t)
{
    for (uint32_t r = 0; r < t->rows; r++)
        for (uint32_t c = 0; c < CONTACT_PASSES; c++)
            if (!isnan(bench_table_get(t, r, contact_column[c])))
                return true;
    return false;
}

/* One measured point, kept until every grid has run: the CSV lists each series (solver and
   iteration count) in one block, so the plot draws it as one line. */
typedef struct point {
    uint32_t solver, iterations, grid, substeps;
    cvk_solver_desc desc;
    measured m;
} point;

typedef struct points {
    point* items;
    uint32_t count, capacity;
} points;

static bool keep(points* all, const point* p)
{
    if (all->count == all->capacity) {
        uint32_t capacity = all->capacity ? 2 * all->capacity : 64;
        point* grown = realloc(all->items, capacity * sizeof *grown);
        if (!grown) {
            app_error("clothvk-bench", "out of memory");
            return false;
        }
        all->items = grown;
        all->capacity = capacity;
    }
    all->items[all->count++] = *p;
    return true;
}

/* Runs every solver and iteration count on one grid, each from the scene's first state (the
   same work for every point, and a point that ran away does not leave its state to the
   next; such a point is reported and left out); *fits is false when the grid is too large
   for the device or the memory (not a failure: the sweep ends there). */
static bool run_grid(bench* b, uint32_t n, points* all, bool* fits)
{
    template_scene ts;
    make_scene(b, n, &ts);
    cvk_error err;
    cvk_sim* sim = NULL;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = &ts.scene;
    cvk_result r = cvk_sim_create(b->ctx, &desc, &sim, &err);
    *fits = r == CVK_SUCCESS;
    if (r == CVK_ERROR_DEVICE_LIMIT || r == CVK_ERROR_OUT_OF_MEMORY) {
        printf("%u x %u does not fit: %s\n", n, n, err.message);
        return true;
    }
    if (r != CVK_SUCCESS) {
        bench_fail(&err);
        return false;
    }
    uint64_t count = cvk_sim_particle_count(sim);
    float* start = malloc(3 * count * sizeof(float));
    bool ok = start != NULL;
    if (!ok)
        app_error("clothvk-bench", "out of memory for %llu positions", (unsigned long long)count);
    if (ok && cvk_sim_read_positions(sim, start, count, &err) != CVK_SUCCESS) {
        bench_fail(&err);
        ok = false;
    }
    for (uint32_t s = 0; ok && s < b->o->solver_count; s++)
        for (uint32_t k = 0; ok && k < b->o->iteration_count; k++) {
            const bench_solver* solver = &b->o->solvers[s];
            cvk_solver_desc d = bench_solver_desc(&ts.scene.solver, solver, b->o->iterations[k],
                                                  b->o->inner);
            point p = {.solver = s, .iterations = b->o->iterations[k], .grid = n,
                       .substeps = ts.scene.substeps, .desc = d};
            ok = cvk_sim_set_solver(sim, &d, &err) == CVK_SUCCESS &&
                 cvk_sim_write_positions(sim, start, count, &err) == CVK_SUCCESS;
            if (!ok)
                bench_fail(&err);
            bool diverged = false;
            if (ok)
                ok = time_point(b, sim, &p.m, &diverged, &err);
            if (ok && diverged)
                printf("%u x %u, %s, %u sweeps: not timed, %s\n", n, n, solver->label,
                       b->o->iterations[k], err.message);
            else if (ok)
                ok = keep(all, &p);
        }
    free(start);
    cvk_sim_destroy(sim);
    return ok;
}

static int find_row(const bench_table* t, const char* label, uint32_t grid, uint32_t iterations)
{
    for (uint32_t r = 0; r < t->rows; r++)
        if (!strcmp(bench_table_get_str(t, r, "label"), label) &&
            bench_table_get(t, r, "grid") == grid && bench_table_get(t, r, "iterations") == iterations)
            return (int)r;
    return -1;
}

/* Seed 000's table shape: particles down, iterations across, frames per second; the GPU
   time per frame with its min-max follows. */
static void print_tables(const bench* b, const uint32_t* grids, uint32_t grid_count)
{
    const bench_table* t = &b->table;
    for (uint32_t s = 0; s < b->o->solver_count; s++) {
        const char* label = b->o->solvers[s].label;
        printf("%s: frames per second (GPU ms per frame: median [min-max] of %u), by sweeps per "
               "substep\n%12s", label, b->o->repeat, "particles");
        for (uint32_t k = 0; k < b->o->iteration_count; k++)
            printf(" %32u", b->o->iterations[k]);
        printf("\n");
        for (uint32_t g = 0; g < grid_count; g++) {
            bool any = false; /* a point that diverged has no row; its cell shows "-" */
            for (uint32_t k = 0; k < b->o->iteration_count; k++)
                any = any || find_row(t, label, grids[g], b->o->iterations[k]) >= 0;
            if (!any)
                continue;
            printf("%12llu", (unsigned long long)grids[g] * grids[g]);
            for (uint32_t k = 0; k < b->o->iteration_count; k++) {
                int r = find_row(t, label, grids[g], b->o->iterations[k]);
                char cell[64] = "-";
                if (r >= 0)
                    snprintf(cell, sizeof cell, "%.3g (%.4g [%.4g-%.4g])",
                             bench_table_get(t, (uint32_t)r, "fps"),
                             bench_table_get(t, (uint32_t)r, "frame_ms"),
                             bench_table_get(t, (uint32_t)r, "frame_ms_min"),
                             bench_table_get(t, (uint32_t)r, "frame_ms_max"));
                printf(" %32s", cell);
            }
            printf("\n");
        }
    }
}

/* The collision passes' share of the frame, per grid, for the first solver and sweep count. */
static void print_contact(const bench* b, const uint32_t* grids, uint32_t grid_count)
{
    const bench_table* t = &b->table;
    const char* label = b->o->solvers[0].label;
    printf("%s, %u sweeps: collision passes, GPU ms per frame (median)\n%12s %10s", label,
           b->o->iterations[0], "particles", "frame");
    for (uint32_t c = 0; c < CONTACT_PASSES; c++)
        printf(" %10s", contact_pass[c]);
    printf("\n");
    for (uint32_t g = 0; g < grid_count; g++) {
        int r = find_row(t, label, grids[g], b->o->iterations[0]);
        if (r < 0)
            continue;
        printf("%12llu %10.4g", (unsigned long long)grids[g] * grids[g],
               bench_table_get(t, (uint32_t)r, "frame_ms"));
        for (uint32_t c = 0; c < CONTACT_PASSES; c++)
            printf(" %10.4g", bench_table_get(t, (uint32_t)r, contact_column[c]));
        printf("\n");
    }
}

static void write_plot(bench* b, uint32_t substeps)
{
    bench_text* t = &b->plot;
    bench_plot_styles(t);
    bool contact = any_contact(&b->table);
    bench_text_add(t, "set multiplot layout 1,%d title \"scaling, %u substeps per frame, on %s\"\n"
                      "set logscale xy\nset xlabel \"particles\"\nset format x \"%%.0e\"\n"
                      "set key top left font \",8\"\n",
                   contact ? 3 : 2, substeps, b->device);
    const char* panels[2][3] = {
        {"GPU time per frame", "ms per frame", "frame_ms"},
        {"solve time per particle and sweep", "ns", "ns_per_particle_iteration"},
    };
    for (int p = 0; p < 2; p++) {
        bench_text_add(t, "set title \"%s\"\nset ylabel \"%s\"\n", panels[p][0], panels[p][1]);
        const char* sep = "plot ";
        for (uint32_t s = 0; s < b->o->solver_count; s++)
            for (uint32_t k = 0; k < b->o->iteration_count; k++) {
                bench_text_add(t, "%s\"scaling.csv\" using \"particles\":(strcol(\"label\") eq \"%s\" "
                                  "&& column(\"iterations\") == %u ? column(\"%s\") : NaN) with "
                                  "linespoints linestyle %u dashtype %u title \"%s, %u sweeps\"",
                               sep, b->o->solvers[s].label, b->o->iterations[k], panels[p][2], s + 1,
                               k + 1, b->o->solvers[s].title, b->o->iterations[k]);
                sep = ", \\\n     ";
            }
        bench_text_add(t, "\n");
    }
    if (contact) {
        bench_text_add(t, "set title \"collision passes, %s, %u sweeps\"\nset ylabel \"ms per "
                          "frame\"\n", b->o->solvers[0].title, b->o->iterations[0]);
        const char* sep = "plot ";
        for (uint32_t c = 0; c < CONTACT_PASSES; c++) {
            bench_text_add(t, "%s\"scaling.csv\" using \"particles\":(strcol(\"label\") eq \"%s\" "
                              "&& column(\"iterations\") == %u ? column(\"%s\") : NaN) with "
                              "linespoints linestyle %u title \"%s\"",
                           sep, b->o->solvers[0].label, b->o->iterations[0], contact_column[c],
                           c + 1, contact_pass[c]);
            sep = ", \\\n     ";
        }
        bench_text_add(t, "\n");
    }
    bench_text_add(t, "unset multiplot\n");
}

int bench_scaling(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    uint32_t grids[BENCH_MAX_LIST];
    uint32_t count = b->o->grid_count;
    if (count)
        memcpy(grids, b->o->grids, count * sizeof *grids);
    else
        count = default_grids(b, grids);
    printf("grids:");
    for (uint32_t i = 0; i < count; i++)
        printf(" %u", grids[i]);
    printf(" (squared); median of %u timed frames after %u warm-up frames\n", b->o->repeat,
           b->o->warmup);
    bool ok = true, fits = true;
    uint32_t largest = 0;
    points all = {0};
    for (uint32_t i = 0; ok && fits && i < count; i++) {
        ok = run_grid(b, grids[i], &all, &fits);
        if (ok && fits)
            largest = grids[i];
    }
    for (uint32_t s = 0; ok && s < b->o->solver_count; s++)
        for (uint32_t k = 0; k < b->o->iteration_count; k++)
            for (uint32_t i = 0; i < all.count; i++) {
                const point* p = &all.items[i];
                if (p->solver == s && p->iterations == b->o->iterations[k])
                    add_row(b, &b->o->solvers[s], &p->desc, p->grid, p->substeps, &p->m);
            }
    free(all.items);
    if (!ok)
        return APP_EXIT_FAILURE;
    if (largest)
        printf("largest grid run: %u x %u = %llu particles\n", largest, largest,
               (unsigned long long)largest * largest);
    template_scene ts;
    make_scene(b, 2, &ts);
    print_tables(b, grids, count);
    if (any_contact(&b->table))
        print_contact(b, grids, count);
    write_plot(b, ts.scene.substeps);
    return APP_EXIT_OK;
}
