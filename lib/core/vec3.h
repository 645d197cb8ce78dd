/* Small vector helpers for host geometry (colliders, their meshes, the air's reference): float,
   and double where a reference wants it. */
#ifndef CVK_VEC3_H
#define CVK_VEC3_H

#include <math.h>
#include <string.h>

static inline float cvk_dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline float cvk_length3(const float a[3])
{
    return sqrtf(cvk_dot3(a, a));
}

static inline void cvk_cross3(const float a[3], const float b[3], float out[3])
{
    float c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(out, c, sizeof c);
}

/* v / |v|, or `fallback` (when not NULL) for a vector too short to have a direction; a zero
   vector without fallback stays zero. */
static inline void cvk_normalize3(float v[3], const float fallback[3])
{
    float len = cvk_length3(v);
    for (int k = 0; k < 3; k++)
        v[k] = len > 1e-12f ? v[k] / len : (fallback ? fallback[k] : v[k]);
}

static inline double cvk_dot3d(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void cvk_cross3d(const double a[3], const double b[3], double out[3])
{
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(out, c, sizeof c);
}

#endif
