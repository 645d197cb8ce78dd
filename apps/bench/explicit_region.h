/* Stability regions of the explicit integrators on one linear mode (explicit_region.c). */
#ifndef CVK_BENCH_EXPLICIT_REGION_H
#define CVK_BENCH_EXPLICIT_REGION_H

#include "clothvk.h"

/* The largest growth factor per step of the mode x'' = −k x − d x' (d in 1/s, k in 1/s²)
   under `integrator` at step h: at most 1 (to rounding) is stable. */
double cvk_explicit_mode_radius(cvk_integrator integrator, double h, double d, double k);

#endif
