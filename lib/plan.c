#include "plan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "error.h"

const char* cvk_pass_name(cvk_pass_id pass)
{
    switch (pass) {
    case CVK_PASS_PREDICT: return "predict";
    case CVK_PASS_SOLVE: return "solve";
    case CVK_PASS_FINALIZE: return "finalize";
    case CVK_PASS_COUNT: break;
    }
    return "?";
}

uint32_t cvk_sweep_cycle(const cvk_solver_desc* solver)
{
    uint32_t sweeps = solver->outer_iterations * solver->inner_iterations;
    if (solver->linear == CVK_LINEAR_CHEBYSHEV && solver->inner_iterations > 1)
        return solver->inner_iterations;
    return sweeps;
}

float cvk_jacobi_sweep_omega(uint32_t sweep, uint32_t cycle, float omega)
{
    if (sweep == 0 && cycle % 2 == 1 && omega > CVK_STABLE_FIRST_OMEGA)
        return CVK_STABLE_FIRST_OMEGA;
    return omega;
}

double cvk_chebyshev_stable_rho(uint32_t m)
{
    if (m == 0)
        return 0.0;
    return 1.0 / cosh(acosh(3.0) / m);
}

static uint32_t effective_delay(uint32_t delay)
{
    return delay < 1 ? 1 : delay; /* the first Chebyshev step needs an older iterate */
}

double cvk_chebyshev_weight(uint32_t sweep, uint32_t delay, double rho)
{
    delay = effective_delay(delay);
    if (sweep < delay)
        return 1.0;
    double w = 2.0 / (2.0 - rho * rho);
    for (uint32_t s = delay; s < sweep; s++)
        w = 4.0 / (4.0 - rho * rho * w);
    return w;
}

double cvk_estimate_jacobi_rho(const cvk_build* b, double inv_h2, double omega)
{
    uint32_t nf = b->free_count;
    if (nf == 0)
        return 0.0;
    double* diag = malloc(nf * sizeof(double));
    double* v = malloc(nf * sizeof(double));
    double* w = malloc(nf * sizeof(double));
    if (!diag || !v || !w) {
        free(diag);
        free(v);
        free(w);
        return 0.0;
    }
    for (uint32_t p = 0; p < nf; p++) {
        diag[p] = b->mass[p] * inv_h2;
        for (uint32_t s = 0; s < b->degree[p]; s++)
            diag[p] += b->adj_k[(size_t)s * nf + p];
    }
    /* A deterministic start vector with components along every mode. */
    uint32_t seed = 12345u;
    for (uint32_t p = 0; p < nf; p++) {
        seed = seed * 1664525u + 1013904223u;
        v[p] = (double)(seed >> 8) / (double)(1u << 24) - 0.5;
    }
    /* G v = (1 − ω) v + ω D⁻¹ Σ k v_c over free neighbours. The spectrum of G can be
       symmetric (bipartite grids), so iterate on G² and take the square root. */
    double rho = 0.0;
    uint32_t iterations = (uint32_t)fmin(400.0, fmax(50.0, 2e8 / ((double)nf * (b->max_degree + 1))));
    for (uint32_t it = 0; it < iterations; it++) {
        double norm_before = 0.0, norm_after = 0.0;
        for (uint32_t p = 0; p < nf; p++)
            norm_before += v[p] * v[p];
        for (int twice = 0; twice < 2; twice++) {
            for (uint32_t p = 0; p < nf; p++) {
                double sum = 0.0;
                for (uint32_t s = 0; s < b->degree[p]; s++) {
                    size_t e = (size_t)s * nf + p;
                    uint32_t n = b->adj_index[e];
                    if (n < nf)
                        sum += b->adj_k[e] * v[n];
                }
                w[p] = (1.0 - omega) * v[p] + omega * sum / diag[p];
            }
            double* t = v;
            v = w;
            w = t;
        }
        for (uint32_t p = 0; p < nf; p++)
            norm_after += v[p] * v[p];
        if (norm_before <= 0.0 || norm_after <= 0.0)
            break;
        rho = pow(norm_after / norm_before, 0.25);
        double scale = 1.0 / sqrt(norm_after);
        for (uint32_t p = 0; p < nf; p++)
            v[p] *= scale;
    }
    free(diag);
    free(v);
    free(w);
    return rho < 1.0 ? rho : 0.999999;
}

typedef struct plan_builder {
    cvk_plan* plan;
    cvk_pd_push base;
} plan_builder;

/* Appends a dispatch over particles [first, first + count); none when count is 0 (a scene
   whose particles are all pinned has nothing to solve). Returns the op, or NULL. */
static cvk_op* add_op(plan_builder* pb, cvk_pipeline_id pipeline, cvk_set_id set, cvk_pass_id pass,
                   uint32_t first, uint32_t count, float cheb, uint32_t outer, uint32_t inner,
                   uint32_t colour)
{
    if (count == 0)
        return NULL;
    cvk_plan* plan = pb->plan;
    uint32_t groups = (count + plan->workgroup_size - 1) / plan->workgroup_size;
    if (groups > plan->max_groups)
        groups = plan->max_groups;
    cvk_op* op = &plan->ops[plan->op_count++];
    *op = (cvk_op){
        .pipeline = pipeline,
        .set = set,
        .pass = pass,
        .groups = groups,
        .push = pb->base,
        .outer = outer,
        .inner = inner,
        .colour = colour,
    };
    op->push.first = first;
    op->push.count = count;
    op->push.cheb = cheb;
    plan->uses[pipeline] = true;
    plan->pass_dispatches[pass]++;
    return op;
}

/* Sets reading U[src] and writing U[dst]. */
static cvk_set_id set_for(uint32_t src, uint32_t dst)
{
    if (src == 0 && dst == 0)
        return CVK_SET_U0_TO_U0;
    return src == 0 ? CVK_SET_U0_TO_U1 : CVK_SET_U1_TO_U0;
}

/* x += u: the substep's displacement, which the solve left in U0, moves the positions. */
static void add_finalize(plan_builder* pb, const cvk_build* b)
{
    add_op(pb, CVK_PIPE_FINALIZE, CVK_SET_U0_TO_U0, CVK_PASS_FINALIZE, 0, b->free_count, 1.0f, 0,
           0, 0);
}

/* Gauss-Seidel: every outer iteration reads the previous iterate from one displacement buffer
   (T) and sweeps in place in the other (W); buffers alternate so the last outer iteration
   writes U0, where finalize and the next prediction find it. */
static void plan_gauss_seidel(plan_builder* pb, const cvk_scene_desc* scene, const cvk_build* b)
{
    uint32_t outer = scene->solver.outer_iterations;
    uint32_t start = outer % 2; /* buffer holding the first iterate */
    add_op(pb, CVK_PIPE_PREDICT, set_for(0, start), CVK_PASS_PREDICT, 0, b->free_count, 1.0f,
           0, 0, 0);
    for (uint32_t o = 0; o < outer; o++) {
        uint32_t t = (outer - o) % 2, w = 1 - t;
        for (uint32_t i = 0; i < scene->solver.inner_iterations; i++)
            for (uint32_t c = 0; c < b->colour_count; c++)
                add_op(pb, i == 0 ? CVK_PIPE_GS_FIRST : CVK_PIPE_GS, set_for(t, w),
                       CVK_PASS_SOLVE, b->colour_start[c],
                       b->colour_start[c + 1] - b->colour_start[c], 1.0f, o, i, c);
    }
    add_finalize(pb, b);
}

/* Jacobi and Chebyshev: every sweep reads one buffer and writes the other. */
static void plan_jacobi(plan_builder* pb, const cvk_scene_desc* scene, const cvk_build* b,
                        bool chebyshev)
{
    uint32_t sweeps = scene->solver.outer_iterations * scene->solver.inner_iterations;
    uint32_t cycle = cvk_sweep_cycle(&scene->solver);
    uint32_t start = sweeps % 2;
    add_op(pb, CVK_PIPE_PREDICT, set_for(0, start), CVK_PASS_PREDICT, 0, b->free_count, 1.0f,
           0, 0, 0);
    for (uint32_t s = 0; s < sweeps; s++) {
        uint32_t src = (sweeps - s) % 2, dst = 1 - src;
        uint32_t inner = s % scene->solver.inner_iterations;
        double cheb = chebyshev ? cvk_chebyshev_weight(s % cycle, scene->solver.chebyshev_delay,
                                                       pb->plan->chebyshev_rho)
                                : 1.0;
        cvk_op* op = add_op(pb, inner == 0 ? CVK_PIPE_JACOBI_FIRST : CVK_PIPE_JACOBI,
                            set_for(src, dst), CVK_PASS_SOLVE, 0, b->free_count, (float)cheb,
                            s / scene->solver.inner_iterations, inner, 0);
        if (op)
            op->push.omega = cvk_jacobi_sweep_omega(s % cycle, cycle, scene->solver.omega);
    }
    add_finalize(pb, b);
}

cvk_result cvk_plan_create(const cvk_scene_desc* scene, const cvk_build* b,
                           uint32_t workgroup_size, uint32_t max_groups, cvk_plan* out,
                           cvk_error* error)
{
    return cvk_plan_create_with_rho(scene, b, workgroup_size, max_groups, -1.0, out, error);
}

cvk_result cvk_plan_create_with_rho(const cvk_scene_desc* scene, const cvk_build* b,
                                    uint32_t workgroup_size, uint32_t max_groups,
                                    double estimated_rho, cvk_plan* out, cvk_error* error)
{
    memset(out, 0, sizeof *out);
    const cvk_solver_desc* solver = &scene->solver;
    uint32_t capacity = 2 + solver->outer_iterations * solver->inner_iterations * b->colour_count;
    out->ops = calloc(capacity, sizeof *out->ops);
    if (!out->ops)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the step plan");
    out->substeps = scene->substeps;
    out->workgroup_size = workgroup_size;
    out->max_groups = max_groups ? max_groups : 1;

    double h = scene->dt;
    plan_builder pb = {.plan = out};
    pb.base.stride = b->free_count;
    pb.base.inv_h2 = (float)(1.0 / (h * h));
    pb.base.omega = solver->omega;
    pb.base.keep = scene->integrate ? 1.0f - scene->damping : 0.0f;
    for (int k = 0; k < 3; k++)
        pb.base.gravity_h2[k] = scene->integrate ? (float)(scene->gravity[k] * h * h) : 0.0f;

    switch (solver->linear) {
    case CVK_LINEAR_RBGS:
        plan_gauss_seidel(&pb, scene, b);
        break;
    case CVK_LINEAR_CHEBYSHEV: {
        uint32_t cycle = cvk_sweep_cycle(solver);
        uint32_t delay = effective_delay(solver->chebyshev_delay);
        if (solver->chebyshev_rho > 0.0f)
            out->chebyshev_rho_estimated = solver->chebyshev_rho;
        else if (estimated_rho >= 0.0)
            out->chebyshev_rho_estimated = estimated_rho;
        else
            out->chebyshev_rho_estimated = cvk_estimate_jacobi_rho(b, 1.0 / (h * h), solver->omega);
        double cap = cvk_chebyshev_stable_rho(cycle > delay ? cycle - delay : 0);
        out->chebyshev_rho = fmin(out->chebyshev_rho_estimated, cap);
        plan_jacobi(&pb, scene, b, true);
        break;
    }
    case CVK_LINEAR_JACOBI:
        plan_jacobi(&pb, scene, b, false);
        break;
    case CVK_LINEAR_GS_CPU:
        break; /* runs on the host; no dispatches */
    }
    return CVK_SUCCESS;
}

void cvk_plan_destroy(cvk_plan* plan)
{
    free(plan->ops);
    memset(plan, 0, sizeof *plan);
}
