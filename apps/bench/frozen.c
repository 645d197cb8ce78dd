/* Solver settings, simulations, and one substep frozen in time: the state a convergence or
   budget experiment replays again and again, and its converged solution x* from the
   double-precision host solver (lib/solvers/reference.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "sim/internal.h"

/* With integration, the substep frozen by default is the first of this frame: on
   hanging.json 80 ms into the fall, when the cloth moves and the springs near the pins are
   stretched by ~3%. Later, the truncated solve has stretched the cloth so far (25% at frame
   10, 300% at frame 30) that the converged substep has to undo it all at once: a hard,
   non-convex problem on which Newton needs hundreds of steps. */
#define DEFAULT_FRAME 5

/* Gauss-Seidel iterations run from x* to show it is their fixed point. */
#define STAR_CHECK_SWEEPS 10

cvk_solver_desc bench_solver_desc(const cvk_solver_desc* base, const bench_solver* s,
                                  uint32_t sweeps, uint32_t inner)
{
    cvk_solver_desc d = *base;
    d.method = s->method;
    d.linear = s->linear;
    if (s->method == CVK_METHOD_IMPLICIT) {
        /* a fixed iteration count, as seed 000's tables: a tolerance never reached */
        d.max_iterations = sweeps ? sweeps : 1;
        d.tolerance = 1e-9f;
        return d;
    }
    if (s->method == CVK_METHOD_EXPLICIT) {
        d.integrator = s->integrator;
        d.max_iterations = 0; /* no solve: nothing to stop */
        d.tolerance = 0.0f;
        return d;
    }
    if (s->omega > 0.0f)
        d.omega = s->omega;
    if (sweeps == 0)
        sweeps = 1;
    if (inner == 0 || inner > sweeps)
        inner = inner == 0 ? 1 : sweeps;
    d.inner_iterations = inner;
    d.outer_iterations = (sweeps + inner - 1) / inner;
    d.max_iterations = 0; /* the sweeps are outer × inner, every one of them run */
    d.tolerance = 0.0f;
    return d;
}

uint32_t bench_sweeps(const cvk_solver_desc* solver)
{
    if (solver->method == CVK_METHOD_IMPLICIT)
        return solver->max_iterations;
    return solver->outer_iterations * solver->inner_iterations;
}

void bench_fail(const cvk_error* err)
{
    app_error("clothvk-bench", "%s", err->message);
}

cvk_sim* bench_sim_create_desc(bench* b, const cvk_sim_desc* desc)
{
    cvk_error err;
    cvk_sim* sim = NULL;
    if (cvk_sim_create(b->ctx, desc, &sim, &err) != CVK_SUCCESS) {
        bench_fail(&err);
        return NULL;
    }
    return sim;
}

cvk_sim* bench_sim_create(bench* b, const cvk_scene_desc* scene)
{
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = scene;
    return bench_sim_create_desc(b, &desc);
}

static bool alloc_frozen(bench_frozen* f)
{
    size_t n3 = 3 * (size_t)f->n;
    f->x0 = malloc(n3 * sizeof(float));
    f->v0 = malloc(n3 * sizeof(float));
    f->out = malloc(n3 * sizeof(float));
    f->x_star = malloc(n3 * sizeof(double));
    f->x_star_f = malloc(n3 * sizeof(float));
    if (f->x0 && f->v0 && f->out && f->x_star && f->x_star_f)
        return true;
    app_error("clothvk-bench", "out of memory for %llu particles", (unsigned long long)f->n);
    return false;
}

/* The state at the start of frame `frame` of the scene run with its own solver. */
static bool frozen_state(bench* b, bench_frozen* f, uint32_t frame)
{
    cvk_error err;
    if (frame == 0) {
        if (cvk_sim_read_state(f->sim, f->x0, f->v0, f->n, &err) == CVK_SUCCESS)
            return true;
        bench_fail(&err);
        return false;
    }
    cvk_sim* warm = bench_sim_create(b, b->scene);
    if (!warm)
        return false;
    cvk_result r = cvk_sim_step(warm, frame, &err);
    if (r == CVK_SUCCESS)
        r = cvk_sim_read_state(warm, f->x0, f->v0, f->n, &err);
    cvk_sim_destroy(warm);
    if (r != CVK_SUCCESS)
        bench_fail(&err);
    return r == CVK_SUCCESS;
}

bool bench_host_create(const cvk_scene_desc* scene, const float* x0, const float* v0, bench_host* h)
{
    memset(h, 0, sizeof *h);
    cvk_error err;
    if (cvk_build_create(scene, &h->build, &err) != CVK_SUCCESS) {
        bench_fail(&err);
        return false;
    }
    size_t n = h->build.particle_count;
    h->x = malloc(3 * n * sizeof(double));
    h->prev = malloc(3 * n * sizeof(double));
    h->y = malloc(3 * n * sizeof(double));
    h->xf = malloc(3 * n * sizeof(float));
    if (!h->x || !h->prev || !h->y || !h->xf) {
        app_error("clothvk-bench", "out of memory for the host reference");
        return false;
    }
    cvk_step_params step_params = cvk_step_params_of(scene);
    h->params = cvk_ref_params_of(&step_params);
    for (uint32_t p = 0; p < n; p++) {
        size_t user = 3 * (size_t)h->build.user_of[p];
        for (int c = 0; c < 3; c++) {
            /* the last displacement from Verlet's velocity, as cvk_sim_write_state makes it:
               at rest it is -1/2 h^2 g, so the first step falls as x0 + 1/2 g t^2 */
            double v = v0 ? v0[user + c] : 0.0;
            double u = p < h->build.free_count ? v * scene->dt - 0.5 * h->params.gravity_h2[c] : 0.0;
            h->x[3 * p + c] = x0 ? x0[user + c] : h->build.position[3 * p + c];
            h->prev[3 * p + c] = h->x[3 * p + c] - u;
        }
    }
    return true;
}

double bench_host_residual(bench_host* h)
{
    for (size_t i = 0; i < 3 * (size_t)h->build.particle_count; i++)
        h->xf[i] = (float)h->x[i];
    cvk_metrics m;
    cvk_metrics_compute(&h->build, h->xf, NULL, NULL, &m);
    return m.residual[CVK_SPRING_STRUCTURAL];
}

void bench_host_to_user(bench_host* h, float* out)
{
    for (uint32_t p = 0; p < h->build.particle_count; p++)
        for (int c = 0; c < 3; c++)
            out[3 * (size_t)h->build.user_of[p] + c] = (float)h->x[3 * (size_t)p + c];
}

void bench_host_destroy(bench_host* h)
{
    free(h->x);
    free(h->prev);
    free(h->y);
    free(h->xf);
    cvk_build_destroy(&h->build);
    memset(h, 0, sizeof *h);
}

/* x*: predict from the frozen state as the GPU does, then the host solver to convergence. */
static bool converged_solution(bench* b, bench_frozen* f)
{
    bench_host h;
    bool ok = bench_host_create(&f->scene, f->x0, f->v0, &h);
    if (ok) {
        cvk_ref_predict(&h.build, &h.params, h.x, h.prev, h.y);
        f->residual0 = bench_host_residual(&h);
        bench_host_to_user(&h, f->out);
        /* predict left x = y for the free particles, the start of the solve */
        ok = cvk_ref_solve_newton(&h.build, &h.params, h.y, b->o->reference_tolerance,
                                  b->o->reference_max, STAR_CHECK_SWEEPS, h.x, &f->star);
        if (!ok)
            app_error("clothvk-bench", "out of memory for the converged solution");
    }
    if (ok) {
        f->residual_star = bench_host_residual(&h);
        bench_host_to_user(&h, f->x_star_f);
        for (uint32_t p = 0; p < h.build.particle_count; p++)
            for (int c = 0; c < 3; c++)
                f->x_star[3 * (size_t)h.build.user_of[p] + c] = h.x[3 * (size_t)p + c];
        f->error0 = cvk_metrics_solve_error(f->out, f->x_star, f->x0, f->n);
    }
    bench_host_destroy(&h);
    return ok;
}

bool bench_frozen_create(bench* b, bench_frozen* f)
{
    memset(f, 0, sizeof *f);
    f->scene = *b->scene;
    f->scene.substeps = 1;
    uint32_t frame = b->o->frame_set ? b->o->frame : (b->scene->integrate ? DEFAULT_FRAME : 0);
    f->frame = frame;
    f->sim = bench_sim_create(b, &f->scene);
    if (!f->sim)
        return false;
    f->n = cvk_sim_particle_count(f->sim);
    if (!alloc_frozen(f) || !frozen_state(b, f, frame))
        return false;
    cvk_error err;
    if (frame > 0 && cvk_sim_write_state(f->sim, f->x0, f->v0, f->n, &err) != CVK_SUCCESS) {
        bench_fail(&err);
        return false;
    }
    return converged_solution(b, f);
}

void bench_frozen_destroy(bench_frozen* f)
{
    cvk_sim_destroy(f->sim);
    free(f->x0);
    free(f->v0);
    free(f->out);
    free(f->x_star);
    free(f->x_star_f);
    memset(f, 0, sizeof *f);
}

static double solve_pass_ms(const cvk_sim* sim)
{
    cvk_sim_stats timing;
    cvk_sim_get_timing(sim, &timing);
    for (uint32_t p = 0; p < timing.pass_count; p++)
        if (!strcmp(timing.passes[p].name, "solve"))
            return timing.passes[p].gpu_ms;
    return NAN;
}

bool bench_frozen_run(bench* b, bench_frozen* f, const bench_solver* s, uint32_t sweeps,
                      uint32_t warmup, uint32_t timed, bench_point* out)
{
    cvk_error err;
    cvk_solver_desc d = bench_solver_desc(&f->scene.solver, s, sweeps, b->o->inner);
    double* samples = calloc(timed ? timed : 1, sizeof(double));
    if (!samples) {
        app_error("clothvk-bench", "out of memory");
        return false;
    }
    cvk_result r = cvk_sim_set_solver(f->sim, &d, &err);
    uint32_t runs = warmup + (timed ? timed : 1), measured = 0;
    for (uint32_t run = 0; run < runs && r == CVK_SUCCESS; run++) {
        r = cvk_sim_write_state(f->sim, f->x0, f->v0, f->n, &err);
        if (r == CVK_SUCCESS)
            r = cvk_sim_step(f->sim, 1, &err);
        double ms = r == CVK_SUCCESS ? solve_pass_ms(f->sim) : NAN;
        if (timed && run >= warmup && ms >= 0.0)
            samples[measured++] = ms;
    }
    cvk_sim_stats st;
    if (r == CVK_SUCCESS)
        r = cvk_sim_get_stats(f->sim, &st, &err);
    if (r == CVK_SUCCESS)
        r = cvk_sim_read_positions(f->sim, f->out, f->n, &err);
    if (r != CVK_SUCCESS) {
        bench_fail(&err);
        free(samples);
        return false;
    }
    *out = (bench_point){
        .sweeps = bench_sweeps(&d),
        .residual = st.residual,
        .solve_error = cvk_metrics_solve_error(f->out, f->x_star, f->x0, f->n),
        .distance_rms = cvk_metrics_rms_distance(f->out, f->x_star_f, f->n),
        .nan_count = st.nan_count,
        .solve_ms = bench_timing_of(samples, measured),
    };
    free(samples);
    return true;
}
