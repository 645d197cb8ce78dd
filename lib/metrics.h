/* The metrics of DESIGN.md "Metrics", one definition used by the library, tools and tests. */
#ifndef CVK_METRICS_H
#define CVK_METRICS_H

#include "build.h"

typedef struct cvk_metrics {
    double residual[3];       /* Σ (|xa − xb| − L)² per spring type (seed 002 eq. 4.1), m² */
    double residual_normalized; /* structural residual / (structural springs · mean L²) */
    double max_stretch;       /* max over springs of |xa − xb| / L − 1 */
    uint64_t nan_count;       /* coordinates that are NaN or infinite */
} cvk_metrics;

/* xyz: 3 floats per particle in internal order. */
void cvk_metrics_compute(const cvk_build* build, const float* xyz, cvk_metrics* out);

#endif
