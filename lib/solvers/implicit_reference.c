/* The implicit Euler substep on the host, in double precision: the ground truth the device's
   assembly, CG and Jacobi are compared with (same formulas as shaders/solvers/implicit_assemble.comp,
   same iteration and stopping rule as implicit_scalars.comp). Never on the fast path. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "solvers/solve_implicit.h"

/* A symmetric 3×3 block: xx, yy, zz, xy, xz, yz. */
typedef struct sym {
    double m[6];
} sym;

static void sym_mul(const sym* a, const double* w, double* out)
{
    const double* m = a->m;
    out[0] = m[0] * w[0] + m[3] * w[1] + m[4] * w[2];
    out[1] = m[3] * w[0] + m[1] * w[1] + m[5] * w[2];
    out[2] = m[4] * w[0] + m[5] * w[1] + m[2] * w[2];
}

/* a n nᵀ + t (I − n nᵀ) added to s. */
static void add_outer(sym* s, const double* n, double a, double t)
{
    double d = a - t;
    s->m[0] += d * n[0] * n[0] + t;
    s->m[1] += d * n[1] * n[1] + t;
    s->m[2] += d * n[2] * n[2] + t;
    s->m[3] += d * n[0] * n[1];
    s->m[4] += d * n[0] * n[2];
    s->m[5] += d * n[1] * n[2];
}

/* The block-Jacobi preconditioner as L D Lᵀ with pivots clamped at m (see
   shaders/solvers/implicit_common.glsl): m[0..2] = l10, l20, l21; m[3..5] = 1/d. */
static sym factor(const sym* a, double mass)
{
    const double* m = a->m;
    double d0 = fmax(m[0], mass);
    double l10 = m[3] / d0, l20 = m[4] / d0;
    double d1 = fmax(m[1] - l10 * l10 * d0, mass);
    double l21 = (m[5] - l20 * l10 * d0) / d1;
    double d2 = fmax(m[2] - l20 * l20 * d0 - l21 * l21 * d1, mass);
    return (sym){{l10, l20, l21, 1.0 / d0, 1.0 / d1, 1.0 / d2}};
}

/* z = P⁻¹ r; returns rᵀz as a sum of squares. */
static double precondition(const sym* f, const double* r, double* z)
{
    const double* l = f->m;
    const double* g = f->m + 3;
    double y[3] = {r[0], r[1] - l[0] * r[0], 0.0};
    y[2] = r[2] - l[1] * r[0] - l[2] * y[1];
    double w[3] = {y[0] * g[0], y[1] * g[1], y[2] * g[2]};
    z[2] = w[2];
    z[1] = w[1] - l[2] * z[2];
    z[0] = w[0] - l[0] * z[1] - l[1] * z[2];
    return y[0] * y[0] * g[0] + y[1] * y[1] * g[1] + y[2] * y[2] * g[2];
}

/* cᵀ A_pp c with the clamped factors: |D^½ Lᵀ c|². */
static double block_norm(const sym* f, const double* c)
{
    const double* l = f->m;
    const double* g = f->m + 3;
    double u[3] = {c[0] + l[0] * c[1] + l[1] * c[2], c[1] + l[2] * c[2], c[2]};
    return u[0] * u[0] / g[0] + u[1] * u[1] / g[1] + u[2] * u[2] / g[2];
}

static double dot3(const double* a, const double* b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

typedef struct lin_system {
    const cvk_build* b;
    size_t nf;
    sym *diag, *inv, *off; /* inv: P's factors (factor()); off: H per slot, slot-major */
    double *rhs, *dv, *dv2, *r, *z, *p, *q;
    double* held; /* the contact normal per free particle, 0 when not held (the filter) */
} lin_system;

static void system_free(lin_system* s)
{
    free(s->diag);
    free(s->inv);
    free(s->off);
    free(s->rhs);
}

static bool system_alloc(lin_system* s, const cvk_build* b)
{
    size_t nf = b->free_count, slots = (size_t)b->max_degree * nf;
    *s = (lin_system){.b = b, .nf = nf};
    s->diag = calloc(nf + 1, sizeof(sym));
    s->inv = calloc(nf + 1, sizeof(sym));
    s->off = calloc(slots + 1, sizeof(sym));
    s->rhs = calloc(24 * nf + 1, sizeof(double)); /* rhs, dv, dv2, r, z, p, q, held */
    if (!s->diag || !s->inv || !s->off || !s->rhs) {
        system_free(s);
        return false;
    }
    double** arrays[] = {&s->dv, &s->dv2, &s->r, &s->z, &s->p, &s->q, &s->held};
    for (size_t i = 0; i < 7; i++)
        *arrays[i] = s->rhs + 3 * nf * (i + 1);
    return true;
}

/* w less its part along p's contact normal: the filter S = I − n nᵀ (S = I when not held). */
static void filter(const lin_system* s, size_t p, double* w)
{
    const double* n = &s->held[3 * p];
    double along = dot3(w, n);
    for (int i = 0; i < 3; i++)
        w[i] -= along * n[i];
}

/* A held particle's preconditioner block: S A S + m n nᵀ = A − n aᵀ − a nᵀ + (n·a + m) n nᵀ,
   a = A n. */
static sym tangent_block(const sym* a, const double* n, double m)
{
    double an[3];
    sym_mul(a, n, an);
    double c = dot3(n, an) + m;
    const int row[6] = {0, 1, 2, 0, 0, 1}, col[6] = {0, 1, 2, 1, 2, 2};
    sym out = *a;
    for (int k = 0; k < 6; k++) {
        int i = row[k], j = col[k];
        out.m[k] -= n[i] * an[j] + an[i] * n[j] - c * n[i] * n[j];
    }
    return out;
}

/* Contact at the substep's start (implicit_contact.comp): each free particle that would end
   the substep within HOLD_SLACK thicknesses of a plane's offset surface at its velocity is
   held on the nearest such plane: moved out onto it if inside, its normal velocity set to end
   on it, its filter the plane's normal. */
#define HOLD_SLACK 0.01
static void contact(lin_system* s, const cvk_implicit_params* ip, double* x, double* v)
{
    double h = ip->h;
    for (size_t p = 0; p < s->nf; p++) {
        double best = HOLD_SLACK * ip->thickness, gap = 0.0, speed = 0.0;
        const double* normal = NULL;
        for (uint32_t k = 0; k < ip->plane_count; k++) {
            const double* plane = ip->planes[k];
            double rel[3] = {x[3 * p] - plane[0], x[3 * p + 1] - plane[1], x[3 * p + 2] - plane[2]};
            double g = dot3(rel, plane + 3) - ip->thickness, u = dot3(&v[3 * p], plane + 3);
            if (g + h * u < best) {
                best = g + h * u;
                gap = g;
                speed = u;
                normal = plane + 3;
            }
        }
        double* held = &s->held[3 * p];
        held[0] = held[1] = held[2] = 0.0;
        if (!normal)
            continue;
        for (int i = 0; i < 3; i++) {
            held[i] = normal[i];
            x[3 * p + i] -= fmin(gap, 0.0) * normal[i];
            v[3 * p + i] += (-fmax(gap, 0.0) / h - speed) * normal[i];
        }
    }
}

/* The blocks, b, dv = 0 and r = S b (implicit_assemble.comp). */
static void assemble(lin_system* s, const cvk_implicit_params* ip, const double* x, const double* v)
{
    const cvk_build* b = s->b;
    double h = ip->h;
    for (size_t p = 0; p < s->nf; p++) {
        double m = b->mass[p], f[3], kv[3] = {0, 0, 0};
        for (int c = 0; c < 3; c++)
            f[c] = m * ip->gravity[c];
        sym a = {{m, m, m, 0, 0, 0}};
        for (uint32_t slot = 0; slot < b->max_degree; slot++) {
            size_t e = (size_t)slot * s->nf + p;
            uint32_t c = b->adj_index[e];
            double k = b->adj_k[e], rest = b->adj_rest[e], d[3], dvel[3], n[3] = {0, 0, 0};
            for (int i = 0; i < 3; i++) {
                d[i] = x[3 * p + i] - x[3 * (size_t)c + i];
                dvel[i] = v[3 * p + i] - v[3 * (size_t)c + i];
            }
            double l = sqrt(dot3(d, d)), t = 0.0;
            if (l > 0.0) {
                for (int i = 0; i < 3; i++)
                    n[i] = d[i] / l;
                t = 1.0 - rest / l;
            }
            if (ip->clamp && t < 0.0)
                t = 0.0;
            double scale = k * (l - rest) + ip->kd * dot3(dvel, n), kvs[3];
            sym kb = {{0}}, hb;
            add_outer(&kb, n, k, k * t);
            sym_mul(&kb, dvel, kvs);
            for (int i = 0; i < 3; i++) {
                f[i] -= scale * n[i];
                kv[i] += kvs[i];
            }
            for (int i = 0; i < 6; i++)
                hb.m[i] = h * h * kb.m[i];
            add_outer(&hb, n, h * ip->kd, 0.0);
            for (int i = 0; i < 6; i++)
                a.m[i] += hb.m[i];
            s->off[e] = hb;
        }
        s->diag[p] = a;
        sym pre = tangent_block(&a, &s->held[3 * p], m);
        s->inv[p] = factor(&pre, m);
        for (int i = 0; i < 3; i++) {
            s->rhs[3 * p + i] = h * f[i] - h * h * kv[i];
            s->r[3 * p + i] = s->rhs[3 * p + i];
            s->dv[3 * p + i] = 0.0;
        }
        filter(s, p, &s->r[3 * p]);
    }
}

/* out_p = Σ H_pc w_c over p's unknown neighbours. */
static void neighbour_sum(const lin_system* s, size_t p, const double* w, double* out)
{
    out[0] = out[1] = out[2] = 0.0;
    for (uint32_t slot = 0; slot < s->b->max_degree; slot++) {
        size_t e = (size_t)slot * s->nf + p;
        uint32_t c = s->b->adj_index[e];
        if (c >= s->nf)
            continue;
        double t[3];
        sym_mul(&s->off[e], &w[3 * (size_t)c], t);
        for (int i = 0; i < 3; i++)
            out[i] += t[i];
    }
}

static void solve_cg(lin_system* s, const cvk_implicit_params* ip, cvk_implicit_report* rep)
{
    size_t nf = s->nf;
    double rho = 0.0;
    for (size_t p = 0; p < nf; p++) {
        rho += precondition(&s->inv[p], &s->r[3 * p], &s->z[3 * p]);
        filter(s, p, &s->z[3 * p]);
        memcpy(&s->p[3 * p], &s->z[3 * p], 3 * sizeof(double));
    }
    double rho0 = rho, tol2 = ip->tolerance * ip->tolerance;
    rep->residual = rho0 > 0.0 ? 1.0 : 0.0;
    if (!(rho0 >= 0.0) || isinf(rho0))
        rep->breakdown = true;
    if (!(rho0 > 0.0) || rep->breakdown)
        return;
    while (rep->iterations < ip->max_iterations) {
        double pq = 0.0;
        for (size_t p = 0; p < nf; p++) {
            double m = s->b->mass[p];
            for (int i = 0; i < 3; i++)
                s->q[3 * p + i] = m * s->p[3 * p + i];
            pq += m * dot3(&s->p[3 * p], &s->p[3 * p]);
            for (uint32_t slot = 0; slot < s->b->max_degree; slot++) {
                size_t e = (size_t)slot * nf + p;
                uint32_t c = s->b->adj_index[e];
                double d[3], hd[3];
                for (int i = 0; i < 3; i++)
                    d[i] = s->p[3 * p + i] - (c < nf ? s->p[3 * (size_t)c + i] : 0.0);
                sym_mul(&s->off[e], d, hd);
                for (int i = 0; i < 3; i++)
                    s->q[3 * p + i] += hd[i];
                pq += (c < nf ? 0.5 : 1.0) * dot3(d, hd);
            }
            filter(s, p, &s->q[3 * p]);
        }
        if (!(pq > 0.0) || isinf(pq)) { /* negative, zero or not finite */
            rep->breakdown = true;
            return;
        }
        double alpha = rho / pq, next = 0.0;
        for (size_t i = 0; i < 3 * nf; i++) {
            s->dv[i] += alpha * s->p[i];
            s->r[i] -= alpha * s->q[i];
        }
        for (size_t p = 0; p < nf; p++) {
            next += precondition(&s->inv[p], &s->r[3 * p], &s->z[3 * p]);
            filter(s, p, &s->z[3 * p]);
        }
        rep->iterations++;
        if (!(next >= 0.0) || isinf(next)) {
            rep->breakdown = true;
            return;
        }
        rep->residual = sqrt(next / rho0);
        double beta = next / rho;
        rho = next;
        if (!(next > tol2 * rho0))
            return;
        for (size_t i = 0; i < 3 * nf; i++)
            s->p[i] = s->z[i] + beta * s->p[i];
    }
}

/* Block Jacobi between dv and dv2; the solution ends in s->dv. */
static void solve_jacobi(lin_system* s, const cvk_implicit_params* ip, cvk_implicit_report* rep)
{
    size_t nf = s->nf;
    double delta0 = 0.0, tol2 = ip->tolerance * ip->tolerance;
    while (rep->iterations < ip->max_iterations) {
        double delta = 0.0;
        for (size_t p = 0; p < nf; p++) {
            double acc[3], next[3], change[3];
            neighbour_sum(s, p, s->dv, acc);
            for (int i = 0; i < 3; i++)
                acc[i] += s->rhs[3 * p + i];
            filter(s, p, acc);
            precondition(&s->inv[p], acc, next);
            filter(s, p, next);
            for (int i = 0; i < 3; i++)
                change[i] = next[i] - s->dv[3 * p + i];
            delta += block_norm(&s->inv[p], change);
            memcpy(&s->dv2[3 * p], next, sizeof next);
        }
        if (!(delta >= 0.0) || isinf(delta)) {
            rep->breakdown = true; /* a diagonal block is not positive definite */
            return;
        }
        if (rep->iterations == 0)
            delta0 = delta;
        rep->iterations++;
        rep->residual = delta0 > 0.0 ? sqrt(delta / delta0) : 0.0;
        double* t = s->dv;
        s->dv = s->dv2;
        s->dv2 = t;
        if (!(delta > tol2 * delta0))
            return;
    }
}

/* A held particle whose residual along its normal, n·(b − A dv), is positive (the surface
   would have to pull) leaves with the normal velocity one block-Jacobi step gives it; one that
   stays loses tangential velocity to Coulomb friction for the impulse −n·(b − A dv) on its
   mass (static planes: relative to rest). implicit_integrate.comp. Reads the neighbours' dv,
   so s->dv2 receives the velocity change. */
static void contact_response(lin_system* s, const cvk_implicit_params* ip, const double* v,
                             size_t p)
{
    const double* n = &s->held[3 * p];
    double* dv = &s->dv[3 * p];
    double res[3], an[3];
    neighbour_sum(s, p, s->dv, res); /* Σ H dv_c over unknown neighbours */
    double m = s->b->mass[p];
    for (int i = 0; i < 3; i++)
        res[i] += s->rhs[3 * p + i] - m * dv[i];
    for (uint32_t slot = 0; slot < s->b->max_degree; slot++) {
        double hd[3];
        sym_mul(&s->off[(size_t)slot * s->nf + p], dv, hd);
        for (int i = 0; i < 3; i++)
            res[i] -= hd[i];
    }
    sym_mul(&s->diag[p], n, an);
    double pull = dot3(n, res), stiffness = dot3(n, an);
    double* out = &s->dv2[3 * p];
    for (int i = 0; i < 3; i++)
        out[i] = dv[i] + (pull > 0.0 ? pull / stiffness * n[i] : 0.0);
    if (pull > 0.0 || stiffness == 0.0) /* released, or not held */
        return;
    double vel[3], t[3];
    for (int i = 0; i < 3; i++)
        vel[i] = v[3 * p + i] + out[i];
    double along = dot3(vel, n);
    for (int i = 0; i < 3; i++)
        t[i] = vel[i] - along * n[i];
    double speed = sqrt(dot3(t, t)), push = -pull;
    double keep = speed * m <= ip->static_friction * push
                      ? 0.0
                      : 1.0 - fmin(1.0, ip->friction * push / (m * speed));
    for (int i = 0; i < 3; i++)
        out[i] -= (1.0 - keep) * t[i];
}

cvk_implicit_params cvk_implicit_params_of(const cvk_step_params* step,
                                           const cvk_solver_desc* solver)
{
    cvk_solver_desc resolved = cvk_solver_desc_resolve(solver); /* 0: the defaults */
    cvk_implicit_params ip = {
        .h = step->dt,
        .keep = 1.0 - step->damping,
        .kd = solver->kd,
        .tolerance = resolved.tolerance,
        .max_iterations = resolved.max_iterations,
        .linear = solver->linear,
        .clamp = true,
    };
    for (int c = 0; c < 3; c++)
        ip.gravity[c] = step->integrate ? step->gravity[c] : 0.0;
    return ip;
}

bool cvk_ref_implicit_substep(const cvk_build* b, const cvk_implicit_params* ip, double* x,
                              double* v, cvk_implicit_report* report)
{
    cvk_implicit_report rep = {0};
    lin_system s;
    if (!system_alloc(&s, b))
        return false;
    contact(&s, ip, x, v);
    assemble(&s, ip, x, v);
    if (ip->linear == CVK_LINEAR_JACOBI)
        solve_jacobi(&s, ip, &rep);
    else
        solve_cg(&s, ip, &rep);
    for (size_t p = 0; p < s.nf; p++)
        contact_response(&s, ip, v, p);
    double* released = s.dv2;
    s.dv2 = s.dv;
    s.dv = released;
    for (size_t p = 0; p < s.nf; p++) {
        /* damping leaves a held particle's component along its normal alone */
        const double* n = &s.held[3 * p];
        double vel[3];
        for (int i = 0; i < 3; i++)
            vel[i] = v[3 * p + i] + s.dv[3 * p + i];
        double along = dot3(vel, n);
        for (int i = 0; i < 3; i++) {
            v[3 * p + i] = ip->keep * vel[i] + (1.0 - ip->keep) * along * n[i];
            x[3 * p + i] += ip->h * v[3 * p + i];
        }
    }
    system_free(&s);
    if (report)
        *report = rep;
    return true;
}
