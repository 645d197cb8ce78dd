#include "solvers/reference.h"

#include <math.h>

#include "topology/build.h"

cvk_ref_params cvk_ref_params_of(const cvk_step_params* step)
{
    double h = step->dt;
    cvk_ref_params p = {.inv_h2 = 1.0 / (h * h)};
    if (step->integrate) {
        p.keep = 1.0 - step->damping;
        for (int k = 0; k < 3; k++)
            p.gravity_h2[k] = (double)step->gravity[k] * h * h;
        /* none with contact (solve_pd.h) */
        p.rest_rate = step->contact ? 0.0 : CVK_REST_RATE_PER_DAMPING * step->damping;
    }
    return p;
}

void cvk_ref_predict(const cvk_build* b, const cvk_ref_params* params, double* x, double* prev,
                     double* y)
{
    for (size_t i = 0; i < 3 * (size_t)b->free_count; i++) {
        double xi = x[i];
        y[i] = xi + (xi - prev[i]) * params->keep + params->gravity_h2[i % 3];
        prev[i] = xi;
        x[i] = y[i];
    }
}

void cvk_ref_rest_start(const cvk_build* b, const cvk_ref_params* params, const double* rest,
                        double* x)
{
    if (params->rest_rate > 0.0)
        for (size_t i = 0; i < 3 * (size_t)b->free_count; i++)
            x[i] += rest[i];
}

void cvk_ref_rest_update(const cvk_build* b, const cvk_ref_params* params, const double* x,
                         const double* y, double* rest)
{
    if (params->rest_rate > 0.0)
        for (size_t i = 0; i < 3 * (size_t)b->free_count; i++)
            rest[i] += params->rest_rate * ((x[i] - y[i]) - rest[i]);
}

void cvk_ref_rhs(const cvk_build* b, const cvk_ref_params* params, const double* t,
                 const double* y, double* rhs)
{
    uint32_t nf = b->free_count;
    for (uint32_t p = 0; p < nf; p++) {
        double mh = b->mass[p] * params->inv_h2;
        double sum[4] = {mh * y[3 * p], mh * y[3 * p + 1], mh * y[3 * p + 2], mh};
        for (uint32_t s = 0; s < b->degree[p]; s++) {
            size_t e = (size_t)s * nf + p;
            const double* tp = &t[3 * (size_t)p];
            const double* tn = &t[3 * (size_t)b->adj_index[e]];
            double d[3] = {tp[0] - tn[0], tp[1] - tn[1], tp[2] - tn[2]};
            double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            double k = b->adj_k[e];
            if (len > 0.0)
                for (int c = 0; c < 3; c++)
                    sum[c] += k * b->adj_rest[e] / len * d[c];
            sum[3] += k;
        }
        for (int c = 0; c < 3; c++)
            rhs[4 * (size_t)p + c] = sum[c];
        rhs[4 * (size_t)p + 3] = 1.0 / sum[3];
    }
}

/* (b_p + Σ k x_c) / diag for particle p, reading neighbours from x. */
static void solve_one(const cvk_build* b, const double* rhs, const double* x, uint32_t p,
                      double out[3])
{
    uint32_t nf = b->free_count;
    double acc[3] = {0, 0, 0};
    for (uint32_t s = 0; s < b->degree[p]; s++) {
        size_t e = (size_t)s * nf + p;
        const double* xn = &x[3 * (size_t)b->adj_index[e]];
        for (int c = 0; c < 3; c++)
            acc[c] += b->adj_k[e] * xn[c];
    }
    for (int c = 0; c < 3; c++)
        out[c] = (rhs[4 * (size_t)p + c] + acc[c]) * rhs[4 * (size_t)p + 3];
}

float cvk_gs_sweep_omega(uint32_t sweep, uint32_t inner, uint32_t outer, float omega)
{
    if (outer >= 2 && inner >= 2 && sweep + 1 == inner && omega > 1.0f)
        return 1.0f;
    return omega;
}

double cvk_ref_gauss_seidel_sweep(const cvk_build* b, const double* rhs, double omega, double* x)
{
    double largest = 0.0;
    for (uint32_t p = 0; p < b->free_count; p++) {
        double gs[3];
        solve_one(b, rhs, x, p, gs);
        for (int c = 0; c < 3; c++) {
            double change = omega * (gs[c] - x[3 * (size_t)p + c]);
            x[3 * (size_t)p + c] += change;
            largest = fmax(largest, fabs(change));
        }
    }
    return largest;
}

void cvk_ref_jacobi_sweep(const cvk_build* b, const double* rhs, double omega, double cheb,
                          const double* src, double* dst)
{
    for (uint32_t p = 0; p < b->free_count; p++) {
        double jac[3];
        solve_one(b, rhs, src, p, jac);
        for (int c = 0; c < 3; c++) {
            size_t i = 3 * (size_t)p + c;
            double z = src[i] + omega * (jac[c] - src[i]);
            dst[i] = cheb != 1.0 ? cheb * (z - dst[i]) + dst[i] : z;
        }
    }
}

void cvk_ref_tethers(const cvk_build* b, double* x)
{
    if (!b->tether_anchor)
        return;
    for (uint32_t p = 0; p < b->free_count; p++) {
        double* xp = &x[3 * (size_t)p];
        const uint32_t* anchor = &b->tether_anchor[CVK_TETHER_SLOTS * (size_t)p];
        const float* limit = &b->tether_length[CVK_TETHER_SLOTS * (size_t)p];
        uint32_t count = 0;
        while (count < CVK_TETHER_SLOTS && anchor[count] != CVK_TETHER_NONE)
            count++;
        for (uint32_t j = 0; j < count * CVK_TETHER_ROUNDS; j++) {
            const double* xa = &x[3 * (size_t)anchor[j % count]];
            double t[3] = {xp[0] - xa[0], xp[1] - xa[1], xp[2] - xa[2]};
            double far = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
            if (far > limit[j % count])
                for (int c = 0; c < 3; c++)
                    xp[c] = xa[c] + t[c] * (limit[j % count] / far);
        }
    }
}

void cvk_ref_solve_gauss_seidel(const cvk_build* b, const cvk_ref_params* params,
                                const cvk_solver_desc* solver, const double* y, double* x,
                                double* scratch)
{
    uint32_t every = solver->tether_every ? solver->tether_every : 1;
    for (uint32_t o = 0; o < solver->outer_iterations; o++) {
        cvk_ref_rhs(b, params, x, y, scratch);
        for (uint32_t i = 0; i < solver->inner_iterations; i++)
            cvk_ref_gauss_seidel_sweep(b, scratch,
                                       cvk_gs_sweep_omega(i, solver->inner_iterations,
                                                          solver->outer_iterations, solver->omega),
                                       x);
        if ((o + 1) % every == 0 || o + 1 == solver->outer_iterations)
            cvk_ref_tethers(b, x); /* as the device's tether pass (lib/solvers/pd_passes.c) */
    }
}

void cvk_ref_substep_gauss_seidel(const cvk_build* b, const cvk_ref_params* params,
                                  const cvk_solver_desc* solver, double* x, double* prev,
                                  double* y, double* rest, double* scratch)
{
    cvk_ref_predict(b, params, x, prev, y);
    if (rest)
        cvk_ref_rest_start(b, params, rest, x);
    cvk_ref_solve_gauss_seidel(b, params, solver, y, x, scratch);
    if (rest)
        cvk_ref_rest_update(b, params, x, y, rest);
}

uint64_t cvk_ref_solve_converged(const cvk_build* b, const cvk_ref_params* params,
                                 const double* y, double omega, double tolerance,
                                 uint64_t max_iterations, double* x, double* scratch,
                                 double* last_change)
{
    double change = INFINITY;
    uint64_t it = 0;
    while (it < max_iterations && !(change <= tolerance)) {
        cvk_ref_rhs(b, params, x, y, scratch);
        change = cvk_ref_gauss_seidel_sweep(b, scratch, omega, x);
        it++;
        if (isnan(change))
            break;
    }
    if (last_change)
        *last_change = change;
    return it;
}
