/* The explicit substep on the host, in double precision: the ground truth the device's
   explicit_force.comp and explicit_update.comp are compared with. Never on the fast path. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "solvers/solve_explicit.h"

cvk_explicit_params cvk_explicit_params_of(const cvk_step_params* step,
                                           const cvk_solver_desc* solver)
{
    cvk_explicit_params ep = {
        .h = step->dt,
        .keep = 1.0 - step->damping,
        .kd = solver->kd,
        .integrator = solver->integrator == CVK_INTEGRATOR_NONE ? CVK_INTEGRATOR_EULER
                                                                : solver->integrator,
        .damping_model = solver->damping_model == CVK_DAMPING_NONE ? CVK_DAMPING_SPRING
                                                                   : solver->damping_model,
    };
    for (int c = 0; c < 3; c++)
        ep.gravity[c] = step->integrate ? step->gravity[c] : 0.0;
    return ep;
}

bool cvk_ref_explicit_init(const cvk_build* b, cvk_explicit_host* st)
{
    size_t n = b->particle_count, nf = b->free_count;
    *st = (cvk_explicit_host){0};
    st->x = malloc((3 * n + 1) * sizeof(double));
    st->v = calloc(3 * n + 1, sizeof(double));
    st->history = calloc(18 * nf + 1, sizeof(double));
    st->held = calloc(nf + 1, sizeof(uint32_t));
    if (!st->x || !st->v || !st->history || !st->held) {
        cvk_ref_explicit_free(st);
        return false;
    }
    for (size_t i = 0; i < 3 * n; i++)
        st->x[i] = b->position[i];
    return true;
}

void cvk_ref_explicit_free(cvk_explicit_host* st)
{
    free(st->x);
    free(st->v);
    free(st->history);
    free(st->held);
    *st = (cvk_explicit_host){0};
}

/* x, v: the free particles' positions and velocities this evaluation reads; a pinned
   neighbour (index ≥ free_count) is read from x_fixed, v_fixed (the state). */
void cvk_ref_explicit_accel(const cvk_build* b, const cvk_explicit_params* ep, const double* x,
                            const double* v, const double* x_fixed, const double* v_fixed,
                            double* a)
{
    size_t nf = b->free_count;
    bool viscosity = ep->damping_model == CVK_DAMPING_VISCOSITY;
    for (size_t p = 0; p < nf; p++) {
        double m = b->mass[p], f[3];
        for (int c = 0; c < 3; c++)
            f[c] = m * ep->gravity[c];
        for (uint32_t slot = 0; slot < b->max_degree; slot++) {
            size_t e = (size_t)slot * nf + p;
            uint32_t c = b->adj_index[e];
            double k = b->adj_k[e], rest = b->adj_rest[e];
            const double* xc = c < nf ? &x[3 * (size_t)c] : &x_fixed[3 * (size_t)c];
            const double* vc = c < nf ? &v[3 * (size_t)c] : &v_fixed[3 * (size_t)c];
            double d[3], dv[3];
            for (int i = 0; i < 3; i++) {
                d[i] = x[3 * p + i] - xc[i];
                dv[i] = v[3 * p + i] - vc[i];
            }
            double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            double n[3] = {0, 0, 0};
            if (l > 0.0)
                for (int i = 0; i < 3; i++)
                    n[i] = d[i] / l;
            double along = dv[0] * n[0] + dv[1] * n[1] + dv[2] * n[2];
            for (int i = 0; i < 3; i++) {
                f[i] -= k * (l - rest) * n[i];
                f[i] -= viscosity ? ep->kd * dv[i] : ep->kd * along * n[i];
            }
        }
        for (int c = 0; c < 3; c++)
            a[3 * p + c] = f[c] / m;
    }
}

/* Adams-Bashforth of order 4 for particle p once three past values are held; else Euler. */
static void ab4(cvk_explicit_host* st, size_t p, const double* a, double h, double* xn,
                double* vn)
{
    double* hist = &st->history[18 * p];
    const double* x = &st->x[3 * p];
    const double* v = &st->v[3 * p];
    const double* ap = &a[3 * p];
    for (int c = 0; c < 3; c++) {
        if (st->held[p] >= 3) {
            vn[c] = v[c] + h / 24.0 * (55.0 * ap[c] - 59.0 * hist[c] + 37.0 * hist[3 + c] -
                                       9.0 * hist[6 + c]);
            xn[c] = x[c] + h / 24.0 * (55.0 * v[c] - 59.0 * hist[9 + c] +
                                       37.0 * hist[12 + c] - 9.0 * hist[15 + c]);
        } else {
            vn[c] = v[c] + h * ap[c];
            xn[c] = x[c] + h * v[c];
        }
    }
    memmove(&hist[3], &hist[0], 6 * sizeof(double));
    memmove(&hist[12], &hist[9], 6 * sizeof(double));
    for (int c = 0; c < 3; c++) {
        hist[c] = ap[c];
        hist[9 + c] = v[c];
    }
    if (st->held[p] < 3)
        st->held[p]++;
}

/* TVD-RK2 (Shu-Osher): a stage of forward Euler, then the average of the state and a second
   Euler step from the stage. */
static bool rk2(const cvk_build* b, const cvk_explicit_params* ep, cvk_explicit_host* st,
                double* a)
{
    size_t n3 = 3 * (size_t)b->particle_count, nf3 = 3 * (size_t)b->free_count;
    double* xs = malloc((2 * n3 + 1) * sizeof(double));
    if (!xs)
        return false;
    double* vs = xs + n3;
    memcpy(xs, st->x, n3 * sizeof(double));
    memcpy(vs, st->v, n3 * sizeof(double));
    for (size_t i = 0; i < nf3; i++) {
        xs[i] = st->x[i] + ep->h * st->v[i];
        vs[i] = st->v[i] + ep->h * a[i];
    }
    cvk_ref_explicit_accel(b, ep, xs, vs, st->x, st->v, a);
    for (size_t i = 0; i < nf3; i++) {
        st->x[i] = 0.5 * (st->x[i] + xs[i] + ep->h * vs[i]);
        st->v[i] = 0.5 * (st->v[i] + vs[i] + ep->h * a[i]) * ep->keep;
    }
    free(xs);
    return true;
}

bool cvk_ref_explicit_substep(const cvk_build* b, const cvk_explicit_params* ep,
                              cvk_explicit_host* st)
{
    size_t nf = b->free_count;
    double* a = malloc((3 * nf + 1) * sizeof(double));
    if (!a)
        return false;
    cvk_ref_explicit_accel(b, ep, st->x, st->v, st->x, st->v, a);
    bool ok = true;
    double h = ep->h;
    if (ep->integrator == CVK_INTEGRATOR_RK2) {
        ok = rk2(b, ep, st, a);
    } else {
        for (size_t p = 0; p < nf; p++) {
            double xn[3], vn[3];
            double* x = &st->x[3 * p];
            double* v = &st->v[3 * p];
            const double* ap = &a[3 * p];
            if (ep->integrator == CVK_INTEGRATOR_AB4) {
                ab4(st, p, a, h, xn, vn);
            } else {
                for (int c = 0; c < 3; c++) {
                    vn[c] = v[c] + h * ap[c];
                    xn[c] = ep->integrator == CVK_INTEGRATOR_VERLET ? x[c] + h * vn[c]
                                                                     : x[c] + h * v[c];
                }
            }
            for (int c = 0; c < 3; c++) {
                x[c] = xn[c];
                v[c] = vn[c] * ep->keep;
            }
        }
    }
    free(a);
    return ok;
}
