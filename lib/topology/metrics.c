#include "topology/metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double distance(const float* pa, const float* pb)
{
    double d[3] = {(double)pa[0] - pb[0], (double)pa[1] - pb[1], (double)pa[2] - pb[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

static void spring_metrics(const cvk_build* b, const float* xyz, const uint32_t* alive,
                           cvk_metrics* out)
{
    double rest2 = 0.0;
    out->max_stretch = b->spring_count ? -INFINITY : 0.0;
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        if (alive && !alive[s])
            continue;
        double len = distance(&xyz[3 * (size_t)sp->a], &xyz[3 * (size_t)sp->b]);
        double e = len - sp->rest;
        out->residual[sp->type] += e * e;
        out->elastic += 0.5 * sp->k * e * e;
        if (sp->rest > 0.0f) {
            double stretch = len / sp->rest - 1.0;
            if (stretch > out->max_stretch || isnan(stretch))
                out->max_stretch = stretch;
        }
        if (sp->type == CVK_SPRING_STRUCTURAL)
            rest2 += (double)sp->rest * sp->rest;
    }
    if (out->max_stretch == -INFINITY) /* every spring torn */
        out->max_stretch = 0.0;
    if (rest2 > 0.0)
        out->residual_normalized = out->residual[CVK_SPRING_STRUCTURAL] / rest2;
}

static void particle_energy(const cvk_build* b, const float* xyz, const float* velocity,
                            const float gravity[3], cvk_metrics* out)
{
    for (uint32_t p = 0; p < b->free_count; p++) {
        double m = b->mass[p];
        for (int c = 0; c < 3; c++) {
            size_t i = 3 * (size_t)p + c;
            if (velocity)
                out->kinetic += 0.5 * m * (double)velocity[i] * velocity[i];
            if (gravity)
                out->gravitational -= m * (double)gravity[c] * xyz[i];
        }
    }
}

static int by_value(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

bool cvk_metrics_structural_stretch_quantile(const cvk_build* b, const float* xyz, double q,
                                             double* out)
{
    return cvk_metrics_live_stretch_quantile(b, xyz, NULL, q, out);
}

bool cvk_metrics_live_stretch_quantile(const cvk_build* b, const float* xyz,
                                       const uint32_t* alive, double q, double* out)
{
    *out = 0.0;
    uint64_t n = b->springs_by_type[CVK_SPRING_STRUCTURAL];
    if (n == 0)
        return true;
    double* stretch = malloc(n * sizeof *stretch);
    if (!stretch)
        return false;
    size_t count = 0;
    bool nonfinite = false;
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        if (sp->type != CVK_SPRING_STRUCTURAL || !(sp->rest > 0.0f) || (alive && !alive[s]))
            continue;
        double e = distance(&xyz[3 * (size_t)sp->a], &xyz[3 * (size_t)sp->b]) / sp->rest - 1.0;
        nonfinite |= !isfinite(e);
        stretch[count++] = e;
    }
    if (nonfinite)
        *out = NAN; /* no order among NaN: the quantile of a broken state is not a number */
    else if (count > 0) {
        size_t rank = (size_t)ceil(q * (double)count);
        qsort(stretch, count, sizeof *stretch, by_value);
        *out = stretch[(rank > 0 ? rank : 1) - 1];
    }
    free(stretch);
    return true;
}

void cvk_metrics_compute(const cvk_build* b, const float* xyz, const float* velocity,
                         const float gravity[3], cvk_metrics* out)
{
    cvk_metrics_compute_live(b, xyz, velocity, gravity, NULL, out);
}

void cvk_metrics_compute_live(const cvk_build* b, const float* xyz, const float* velocity,
                              const float gravity[3], const uint32_t* alive, cvk_metrics* out)
{
    memset(out, 0, sizeof *out);
    for (size_t i = 0; i < 3 * (size_t)b->particle_count; i++)
        if (!isfinite(xyz[i]))
            out->nan_count++;
    spring_metrics(b, xyz, alive, out);
    particle_energy(b, xyz, velocity, gravity, out);
}

double cvk_metrics_solve_error(const float* x, const double* x_star, const float* x0,
                               uint64_t count)
{
    double off = 0.0, motion = 0.0;
    for (uint64_t i = 0; i < 3 * count; i++) {
        double d = (double)x[i] - x_star[i];
        double m = x_star[i] - (double)x0[i];
        off += d * d;
        motion += m * m;
    }
    if (motion == 0.0)
        return off == 0.0 ? 0.0 : INFINITY;
    return sqrt(off / motion);
}

double cvk_metrics_rms_distance(const float* a, const float* b, uint64_t count)
{
    if (count == 0)
        return 0.0;
    double sum = 0.0;
    for (uint64_t p = 0; p < count; p++) {
        double d = distance(&a[3 * p], &b[3 * p]);
        sum += d * d;
    }
    return sqrt(sum / (double)count);
}
