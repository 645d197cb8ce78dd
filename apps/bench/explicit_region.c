/* The explicit integrators' stability on one mode of the linearised cloth, for
   explicit-stability's predictions: a mode with damping rate d (1/s) and stiffness k (1/s²),
   x'' = −k x − d x', as the methods of lib/solvers/solve_explicit.c advance it. */
#include <complex.h>
#include <math.h>

#include "explicit_region.h"

/* The roots of ζ⁴ − (1 + 55z/24) ζ³ + (59z/24) ζ² − (37z/24) ζ + 9z/24 (Adams-Bashforth 4 on
   y' = s y, z = h s), by Durand-Kerner; the largest modulus. */
static double ab4_radius(double complex z)
{
    double complex c[4] = {-(1.0 + 55.0 * z / 24.0), 59.0 * z / 24.0, -37.0 * z / 24.0,
                           9.0 * z / 24.0};
    double complex r[4] = {1.0, 0.4 + 0.9 * I, -0.65 + 0.72 * I, -0.3 - 0.8 * I};
    for (int it = 0; it < 500; it++) {
        double moved = 0.0;
        for (int i = 0; i < 4; i++) {
            double complex p = ((((r[i] + c[0]) * r[i] + c[1]) * r[i] + c[2]) * r[i]) + c[3];
            double complex q = 1.0;
            for (int j = 0; j < 4; j++)
                if (j != i)
                    q *= r[i] - r[j];
            double complex step = p / q;
            r[i] -= step;
            moved = fmax(moved, cabs(step));
        }
        if (moved < 1e-14)
            break;
    }
    double radius = 0.0;
    for (int i = 0; i < 4; i++)
        radius = fmax(radius, cabs(r[i]));
    return radius;
}

/* Growth factor per step of y' = s y under the method (Euler, RK2, AB4). */
static double growth(cvk_integrator integrator, double complex z)
{
    switch (integrator) {
    case CVK_INTEGRATOR_RK2: return cabs(1.0 + z + z * z / 2.0);
    case CVK_INTEGRATOR_AB4: return ab4_radius(z);
    default: return cabs(1.0 + z);
    }
}

/* Position Verlet with velocity damping, v' = v + h(−k x − d v), x' = x + h v': the step
   matrix has trace 2 − h²k − h d and determinant 1 − h d; its spectral radius. */
static double verlet_radius(double h, double d, double k)
{
    double trace = 2.0 - h * h * k - h * d, det = 1.0 - h * d;
    double complex root = csqrt(trace * trace / 4.0 - det + 0.0 * I);
    return fmax(cabs(trace / 2.0 + root), cabs(trace / 2.0 - root));
}

double cvk_explicit_mode_radius(cvk_integrator integrator, double h, double d, double k)
{
    if (integrator == CVK_INTEGRATOR_VERLET)
        return verlet_radius(h, d, k);
    /* eigenvalues of [[0, 1], [−k, −d]]: s = −d/2 ± √(d²/4 − k) */
    double complex root = csqrt(d * d / 4.0 - k + 0.0 * I);
    double complex s1 = -d / 2.0 + root, s2 = -d / 2.0 - root;
    return fmax(growth(integrator, h * s1), growth(integrator, h * s2));
}
