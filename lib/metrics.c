#include "metrics.h"

#include <math.h>
#include <string.h>

void cvk_metrics_compute(const cvk_build* b, const float* xyz, cvk_metrics* out)
{
    memset(out, 0, sizeof *out);
    for (size_t i = 0; i < 3 * (size_t)b->particle_count; i++)
        if (!isfinite(xyz[i]))
            out->nan_count++;
    double rest2 = 0.0;
    out->max_stretch = b->spring_count ? -INFINITY : 0.0;
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        const float* pa = &xyz[3 * (size_t)sp->a];
        const float* pb = &xyz[3 * (size_t)sp->b];
        double d[3] = {(double)pa[0] - pb[0], (double)pa[1] - pb[1], (double)pa[2] - pb[2]};
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        double e = len - sp->rest;
        out->residual[sp->type] += e * e;
        if (sp->rest > 0.0f) {
            double stretch = len / sp->rest - 1.0;
            if (stretch > out->max_stretch || isnan(stretch))
                out->max_stretch = stretch;
        }
        if (sp->type == CVK_SPRING_STRUCTURAL)
            rest2 += (double)sp->rest * sp->rest;
    }
    if (rest2 > 0.0)
        out->residual_normalized = out->residual[CVK_SPRING_STRUCTURAL] / rest2;
}
