/* Validation of the air: the scene's wind block and air density, a cloth's aero coefficients. */
#include <math.h>

#include "scene/scene.h"

static bool check_at_most(cvk_scene_issue* issue, const char* path, double v, double low,
                          double high)
{
    if (!cvk_check_at_least(issue, path, v, low))
        return false;
    return v <= high || cvk_issue_at(issue, path, "must be at most %g, got %s", high, cvk_float_text(v).text);
}

bool cvk_aero_check(const cvk_aero_desc* a, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    cvk_key_path(path, "%s.aero.drag", base);
    if (!check_at_most(issue, path, a->drag, 0.0, 100.0))
        return false;
    cvk_key_path(path, "%s.aero.lift", base);
    if (!check_at_most(issue, path, a->lift, 0.0, 100.0))
        return false;
    cvk_key_path(path, "%s.aero.friction", base);
    return check_at_most(issue, path, a->friction, 0.0, 100.0);
}

bool cvk_wind_solver_check(const cvk_solver_desc* solver, bool wind, cvk_scene_issue* issue)
{
    if (!wind)
        return true;
    if (solver->method == CVK_METHOD_IMPLICIT)
        return cvk_issue_at(issue, "solver.method", "implicit does not apply wind yet; remove "
                            "\"wind\", or use pd");
    if (solver->linear == CVK_LINEAR_GS_CPU)
        return cvk_issue_at(issue, "solver.linear", "gs-cpu (the host reference) does not apply "
                            "wind; remove \"wind\", or use rbgs, jacobi or chebyshev");
    return true;
}

bool cvk_wind_check(const cvk_scene_desc* d, cvk_scene_issue* issue)
{
    const cvk_wind_desc* w = &d->wind;
    if (!cvk_check_greater(issue, "air_density", d->air_density, 0.0) ||
        !check_at_most(issue, "air_density", d->air_density, 0.0, 1e4))
        return false;
    if (!cvk_check_finite_array(issue, "wind.velocity", w->velocity, 3))
        return false;
    double speed = sqrt((double)w->velocity[0] * w->velocity[0] +
                        (double)w->velocity[1] * w->velocity[1] +
                        (double)w->velocity[2] * w->velocity[2]);
    if (speed > CVK_MAX_WIND)
        return cvk_issue_at(issue, "wind.velocity", "must be at most %g m/s fast, got %s m/s",
                            CVK_MAX_WIND, cvk_float_text(speed).text);
    return check_at_most(issue, "wind.gusts.amplitude", w->gusts.amplitude, 0.0, 1.0) &&
           cvk_check_greater(issue, "wind.gusts.period", w->gusts.period, 0.0) &&
           check_at_most(issue, "wind.gusts.jitter", w->gusts.jitter, 0.0, 90.0) &&
           cvk_wind_solver_check(&d->solver, w->enabled, issue);
}
