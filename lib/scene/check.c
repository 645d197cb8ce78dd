/* The checks every part of the scene check shares (scene/check.h). */
#include "scene/check.h"

#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

__attribute__((format(printf, 3, 4)))
bool cvk_issue_at(cvk_scene_issue* issue, const char* path, const char* format, ...)
{
    cvk_key_path(issue->path, "%s", path);
    va_list args;
    va_start(args, format);
    vsnprintf(issue->problem, sizeof issue->problem, format, args);
    va_end(args);
    return false;
}

void cvk_key_path(char out[CVK_KEY_PATH_MAX], const char* format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(out, CVK_KEY_PATH_MAX, format, args);
    va_end(args);
}

const char* cvk_key_join(char out[CVK_KEY_PATH_MAX], const char* base, const char* key)
{
    cvk_key_path(out, "%s.%s", base, key);
    return out;
}

const char* cvk_key_join_index(char out[CVK_KEY_PATH_MAX], const char* base, uint32_t index)
{
    cvk_key_path(out, "%s.%" PRIu32, base, index);
    return out;
}

static cvk_number_text shortest_text(double v, bool single)
{
    cvk_number_text t;
    for (int digits = 6; digits <= 17; digits++) {
        snprintf(t.text, sizeof t.text, "%.*g", digits, v);
        double back = strtod(t.text, NULL);
        if (single ? (float)back == (float)v : back == v)
            break;
    }
    return t;
}

cvk_number_text cvk_float_text(double v)
{
    return shortest_text(v, true);
}

cvk_number_text cvk_double_text(double v)
{
    return shortest_text(v, false);
}

bool cvk_check_finite(cvk_scene_issue* issue, const char* path, double v)
{
    if (isfinite(v))
        return true;
    /* glibc prints a NaN with its sign bit set as "-nan"; the sign of a NaN means nothing. */
    const char* text = isnan(v) ? "nan" : v > 0 ? "inf" : "-inf";
    return cvk_issue_at(issue, path, "must be a finite number, got %s", text);
}

bool cvk_check_finite_array(cvk_scene_issue* issue, const char* path, const float* v, uint32_t n)
{
    char element[CVK_KEY_PATH_MAX];
    for (uint32_t i = 0; i < n; i++) {
        if (!cvk_check_finite(issue, cvk_key_join_index(element, path, i), v[i]))
            return false;
    }
    return true;
}

bool cvk_check_greater(cvk_scene_issue* issue, const char* path, double v, double low)
{
    if (!cvk_check_finite(issue, path, v))
        return false;
    return v > low || cvk_issue_at(issue, path, "must be greater than %s, got %s",
                                   cvk_float_text(low).text, cvk_float_text(v).text);
}

bool cvk_check_at_least(cvk_scene_issue* issue, const char* path, double v, double low)
{
    if (!cvk_check_finite(issue, path, v))
        return false;
    return v >= low || cvk_issue_at(issue, path, "must be at least %s, got %s",
                                    cvk_float_text(low).text, cvk_float_text(v).text);
}

bool cvk_check_position(cvk_scene_issue* issue, const char* path, const float* v, uint32_t n)
{
    char element[CVK_KEY_PATH_MAX];
    for (uint32_t i = 0; i < n; i++) {
        cvk_key_join_index(element, path, i);
        if (!cvk_check_finite(issue, element, v[i]))
            return false;
        if (fabs(v[i]) > CVK_MAX_COORDINATE)
            return cvk_issue_at(issue, element, "must be at most %g m from the origin "
                                "(single-precision metres), got %s", CVK_MAX_COORDINATE,
                                cvk_float_text(v[i]).text);
    }
    return true;
}

bool cvk_check_length(cvk_scene_issue* issue, const char* path, double v)
{
    if (!cvk_check_greater(issue, path, v, 0.0))
        return false;
    return v <= CVK_MAX_COORDINATE ||
           cvk_issue_at(issue, path, "must be at most %g m (single-precision metres), got %s",
                        CVK_MAX_COORDINATE, cvk_float_text(v).text);
}

bool cvk_check_scale(cvk_scene_issue* issue, const char* path, double v)
{
    if (!cvk_check_finite(issue, path, v))
        return false;
    return v != 0.0 || cvk_issue_at(issue, path, "must not be zero, got 0");
}

bool cvk_check_count(cvk_scene_issue* issue, const char* path, uint32_t v, uint32_t low)
{
    return v >= low || cvk_issue_at(issue, path, "must be at least %" PRIu32 ", got %" PRIu32, low, v);
}

/* low <= v <= high, for counts whose products size the plan and the recorded frame. */
bool cvk_check_count_range(cvk_scene_issue* issue, const char* path, uint32_t v, uint32_t low,
                              uint32_t high)
{
    if (v > high)
        return cvk_issue_at(issue, path, "must be at most %" PRIu32 ", got %" PRIu32, high, v);
    return cvk_check_count(issue, path, v, low);
}

/* low <= v < high */
bool cvk_check_half_open(cvk_scene_issue* issue, const char* path, double v, double low,
                            double high)
{
    if (!cvk_check_finite(issue, path, v))
        return false;
    if (v >= low && v < high)
        return true;
    return cvk_issue_at(issue, path, "must be at least %s and less than %s, got %s",
                        cvk_float_text(low).text, cvk_float_text(high).text, cvk_float_text(v).text);
}

/* low < v < high */
bool cvk_check_open(cvk_scene_issue* issue, const char* path, double v, double low, double high)
{
    if (!cvk_check_finite(issue, path, v))
        return false;
    if (v > low && v < high)
        return true;
    return cvk_issue_at(issue, path, "must be greater than %s and less than %s, got %s",
                        cvk_float_text(low).text, cvk_float_text(high).text, cvk_float_text(v).text);
}

/* low <= v <= high, element by element */
bool cvk_check_closed(cvk_scene_issue* issue, const char* path, double v, double low, double high)
{
    if (!cvk_check_finite(issue, path, v))
        return false;
    if (v < low || v > high)
        return cvk_issue_at(issue, path, "must be between %s and %s, got %s", cvk_float_text(low).text,
                            cvk_float_text(high).text, cvk_float_text(v).text);
    return true;
}

bool cvk_check_closed_array(cvk_scene_issue* issue, const char* path, const float* v, uint32_t n,
                               double low, double high)
{
    char element[CVK_KEY_PATH_MAX];
    for (uint32_t i = 0; i < n; i++) {
        cvk_key_join_index(element, path, i);
        if (!cvk_check_finite(issue, element, v[i]))
            return false;
        if (v[i] < low || v[i] > high)
            return cvk_issue_at(issue, element, "must be between %s and %s, got %s",
                                cvk_float_text(low).text, cvk_float_text(high).text,
                                cvk_float_text(v[i]).text);
    }
    return true;
}

/* Vertex indices are checked against the mesh when it is read: its vertex count is not known
   here. */
static bool check_mesh_pins(const cvk_cloth_desc* c, const char* path, cvk_scene_issue* issue)
{
    if (c->pin_count > 0)
        return cvk_issue_at(issue, path, "a mesh cloth takes vertex indices (file order), not [i, j] pairs");
    if (c->pin_vertex_count > 0 && !c->pin_vertices)
        return cvk_issue_at(issue, path, "pin_vertices is NULL but pin_vertex_count is %" PRIu32, c->pin_vertex_count);
    return true;
}

bool cvk_check_pins(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    char element[CVK_KEY_PATH_MAX];
    cvk_key_join(path, base, "pins");
    if (c->mesh)
        return check_mesh_pins(c, path, issue);
    if (c->pin_vertex_count > 0)
        return cvk_issue_at(issue, path, "a grid cloth takes [i, j] pairs, not vertex indices");
    if (c->pin_count > 0 && !c->pins)
        return cvk_issue_at(issue, path, "is NULL but pin_count is %" PRIu32, c->pin_count);
    for (uint32_t p = 0; p < c->pin_count; p++) {
        const uint32_t* pin = c->pins[p];
        if (pin[0] < c->grid[0] && pin[1] < c->grid[1])
            continue;
        return cvk_issue_at(issue, cvk_key_join_index(element, path, p),
                        "[%" PRIu32 ", %" PRIu32 "] is outside the %" PRIu32 " x %" PRIu32 " grid", pin[0],
                        pin[1], c->grid[0], c->grid[1]);
    }
    return true;
}

/* The JSON path of a corner is pin_box.0 (min) or pin_box.1 (max). */
bool cvk_check_pin_box(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    static const char axis_names[3] = {'x', 'y', 'z'};
    char path[CVK_KEY_PATH_MAX];
    char corner[CVK_KEY_PATH_MAX];
    if (!c->use_pin_box)
        return true;
    cvk_key_join(path, base, "pin_box");
    if (!cvk_check_finite_array(issue, cvk_key_join_index(corner, path, 0), c->pin_box.min, 3) ||
        !cvk_check_finite_array(issue, cvk_key_join_index(corner, path, 1), c->pin_box.max, 3))
        return false;
    for (int k = 0; k < 3; k++) {
        if (c->pin_box.min[k] > c->pin_box.max[k])
            return cvk_issue_at(issue, path, "min %g is above max %g on axis %c", c->pin_box.min[k], c->pin_box.max[k],
                            axis_names[k]);
    }
    return true;
}

/* A rotation of any length, normalised where it is used, but not zero. */
bool cvk_check_quaternion(cvk_scene_issue* issue, const char* path, const float q[4])
{
    if (!cvk_check_finite_array(issue, path, q, 4))
        return false;
    if (q[0] == 0.0f && q[1] == 0.0f && q[2] == 0.0f && q[3] == 0.0f)
        return cvk_issue_at(issue, path, "must not be zero, got [0, 0, 0, 0]");
    return true;
}

static bool check_keyframe(const cvk_keyframe* k, const char* base, const cvk_keyframe* previous,
                           cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    if (!cvk_check_at_least(issue, cvk_key_join(path, base, "time"), k->time, 0.0))
        return false;
    if (previous && !(k->time > previous->time))
        return cvk_issue_at(issue, path, "must be greater than the previous keyframe's time (%s), "
                            "got %s", cvk_float_text(previous->time).text,
                            cvk_float_text(k->time).text);
    return cvk_check_position(issue, cvk_key_join(path, base, "translation"), k->translation, 3) &&
           cvk_check_quaternion(issue, cvk_key_join(path, base, "rotation"), k->rotation);
}

bool cvk_check_motion(const cvk_motion* m, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    char element[CVK_KEY_PATH_MAX];
    cvk_key_join(path, base, "keyframes");
    if (m->keyframe_count > CVK_MAX_KEYFRAMES)
        return cvk_issue_at(issue, path, "at most %u keyframes, got %" PRIu32, CVK_MAX_KEYFRAMES, m->keyframe_count);
    if (m->keyframe_count > 0 && !m->keyframes)
        return cvk_issue_at(issue, path, "is NULL but keyframe_count is %" PRIu32, m->keyframe_count);
    for (uint32_t i = 0; i < m->keyframe_count; i++) {
        const cvk_keyframe* previous = i > 0 ? &m->keyframes[i - 1] : NULL;
        if (!check_keyframe(&m->keyframes[i], cvk_key_join_index(element, path, i), previous, issue))
            return false;
    }
    if (m->loop && m->keyframe_count < 2)
        return cvk_issue_at(issue, cvk_key_join(path, base, "loop"), "a looping motion needs at least two keyframes, got %" PRIu32,
                        m->keyframe_count);
    return true;
}
