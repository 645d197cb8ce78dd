/* The metrics of DESIGN.md "Metrics", one definition used by the library, tools and tests. */
#ifndef CVK_METRICS_H
#define CVK_METRICS_H

#include "topology/build.h"

typedef struct cvk_metrics {
    double residual[3];       /* Σ (|xa − xb| − L)² per spring type (seed 002 eq. 4.1), m² */
    double residual_normalized; /* structural residual / (structural springs · mean L²) */
    double max_stretch;       /* max over springs of |xa − xb| / L − 1 */
    uint64_t nan_count;       /* coordinates that are NaN or infinite */
    double kinetic;           /* Σ ½ m |v|² over free particles, J (0 without velocities) */
    double gravitational;     /* −Σ m g·x over free particles, J (0 at the origin) */
    double elastic;           /* Σ ½ k (|xa − xb| − L)² over all springs, J */
} cvk_metrics;

/* xyz and velocity: 3 floats per particle in internal order; velocity (m/s) may be NULL.
   gravity (m/s²) may be NULL: no gravitational energy. Pinned particles are moved only from
   outside, so they carry no kinetic or gravitational energy. */
void cvk_metrics_compute(const cvk_build* build, const float* xyz, const float* velocity,
                         const float gravity[3], cvk_metrics* out);
/* The same over the live springs only: alive (uint per spring, 0 = torn; lib/features/tear.h) may be
   NULL (all live). A torn spring pulls nothing, so it has no residual, stretch or energy. */
void cvk_metrics_compute_live(const cvk_build* build, const float* xyz, const float* velocity,
                              const float gravity[3], const uint32_t* alive, cvk_metrics* out);

/* The q-quantile (nearest rank: the ceil(q n)-th smallest, 0 < q ≤ 1) of |xa − xb| / L − 1
   over the structural springs, into *out (0 without structural springs). False when out of
   host memory (a copy of the stretches is sorted). */
bool cvk_metrics_structural_stretch_quantile(const cvk_build* build, const float* xyz, double q,
                                             double* out);
/* The same over the live structural springs (alive as above). */
bool cvk_metrics_live_stretch_quantile(const cvk_build* build, const float* xyz,
                                       const uint32_t* alive, double q, double* out);

/* Solve error of one substep: |x − x*| / |x* − x0| over all coordinates, where x* is the
   converged solution and x0 the positions at the start of the substep. The solver's unknown
   is the displacement x − x0, so this is |u − u*| / |u*|: 1 when nothing was solved, 0 when
   the solve is exact, whatever the distance to the origin. 0 when x* = x0 = x. */
double cvk_metrics_solve_error(const float* x, const double* x_star, const float* x0,
                               uint64_t count);

/* Root-mean-square distance between two sets of `count` points (3 floats each), m: the
   trajectory error against a reference at the same simulated time. */
double cvk_metrics_rms_distance(const float* a, const float* b, uint64_t count);

#endif
