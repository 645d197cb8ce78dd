/* Scene descriptions: defaults and validation with messages that name the key path. */
#include "scene/scene.h"

#include "core/cookie.h"
#include "core/error.h"

#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>

cvk_scene_desc cvk_default_scene_desc(void)
{
    return (cvk_scene_desc){
        .name = NULL,
        .dt = 0.002f,
        .substeps = 8,
        .frames = 240,
        .integrate = true,
        .gravity = {0.0f, -9.81f, 0.0f},
        .damping = 0.0f,
        .solver = {
            .method = CVK_METHOD_PD,
            .linear = CVK_LINEAR_RBGS,
            .outer_iterations = 4,
            .inner_iterations = 4,
            .omega = 1.0f,
            .chebyshev_rho = 0.0f,
            .chebyshev_delay = 2,
            .tether_every = 1,
            .tolerance = 0.0f,     /* the family's: none for pd, 1e-3 for implicit */
            .max_iterations = 0,   /* the family's: outer × inner for pd, 100 for implicit */
            .kd = 0.0f,
        },
        .cloths = NULL,
        .cloth_count = 0,
        .render = cvk_default_render_desc(),
        /* thickness 0: half the shortest structural rest length, resolved by the simulation. */
        /* radius 0: 1.3 thicknesses (CVK_RADIUS_THICKNESSES). */
        .collision = {.self = false, .thickness = 0.0f, .radius = 0.0f, .friction = 0.3f,
                      .static_friction = 0.4f, .allow_intersecting_start = false,
                      .detection_interval = 1, .detect_every = 0, .exclusion = 0.0f, .edges = false},
        .colliders = NULL,
        .collider_count = 0,
        .attachments = NULL,
        .attachment_count = 0,
        .wind = {.enabled = false, .velocity = {0.0f, 0.0f, 0.0f},
                 .gusts = {.amplitude = 0.0f, .period = 2.0f, .jitter = 0.0f}},
        .air_density = 1.2f,
        .cookie_ = CVK_COOKIE_SCENE,
    };
}

/* A warm key light high in front and to the right, a cool dim fill from the front left (the
   camera's side, so what the camera sees of the key light's dark side is lit too): the lit
   side reads warm, the shaded side cool, and neither goes black. */
cvk_render_desc cvk_default_render_desc(void)
{
    return (cvk_render_desc){
        .size = {1280, 720},
        .auto_eye = true,
        .eye = {0.0f, 0.0f, 0.0f},
        .auto_target = true,
        .target = {0.0f, 0.0f, 0.0f},
        .up = {0.0f, 1.0f, 0.0f},
        .fov_y = 35.0f,
        .key = {.direction = {0.45f, 1.0f, 0.6f}, .color = {1.0f, 0.95f, 0.85f}},
        .fill = {.direction = {-0.8f, 0.3f, 0.5f}, .color = {0.28f, 0.32f, 0.4f}},
        .ambient = {0.1f, 0.105f, 0.12f},
        .background = {0.55f, 0.62f, 0.72f},
        .ground = true,
        .auto_ground_height = true,
        .ground_height = 0.0f,
        .ground_color = {0.6f, 0.6f, 0.58f},
        .shadow_map_size = 2048,
        .samples = 4,
        .wireframe = false,
        .camera_keyframes = NULL, /* camera_keyframe_count: 0 */
        .camera_loop = false,
        .soft_shadows = true,
        .key_angle = 3.0f,
        .sky_light = true,
        .ao = true, .ao_radius = 0.0f,
        .smooth = 0, .tone_map = true,
        .fit_margin = 0.06f, /* fit and overlay: false */
        .vertex_lighting = 12.0f,
        .cookie_ = CVK_COOKIE_RENDER,
    };
}

cvk_cloth_desc cvk_default_cloth_desc(void)
{
    return (cvk_cloth_desc){
        .name = NULL,
        .grid = {100, 100},
        .size = {1.0f, 1.0f},
        .origin = {-0.5f, 1.0f, 0.0f},
        .u_axis = {1.0f, 0.0f, 0.0f},
        .v_axis = {0.0f, 0.0f, 1.0f},
        .mesh = NULL,
        .transform = {.scale = {1.0f, 1.0f, 1.0f}, .rotation = {1.0f, 0.0f, 0.0f, 0.0f},
                      .translation = {0.0f, 0.0f, 0.0f}},
        .rest_scale = 1.0f,
        .mass = 0.1f,
        .density = 0.0f,
        .stiffness = {.structural = 1e6f, .shear = 0.0f, .bend = 0.0f},
        .pins = NULL,
        .pin_count = 0,
        .pin_vertices = NULL,
        .pin_vertex_count = 0,
        .use_pin_box = false,
        .pin_box = {.min = {0.0f, 0.0f, 0.0f}, .max = {0.0f, 0.0f, 0.0f}},
        .color = {0.9f, 0.35f, 0.3f},
        .texture = NULL,
        .texture_scale = {1.0f, 1.0f},
        .back_color = {-1.0f, -1.0f, -1.0f},
        .sheen = 0.4f,
        .roughness = 0.5f,
        .normal_strength = 1.0f,
        .velocity = {0.0f, 0.0f, 0.0f},
        .tethers = 0.0f,
        .aero = {.drag = 1.0f, .lift = 0.2f, .friction = 0.02f},
        .tearing = {.max_stretch = 0.0f},
        .cookie_ = CVK_COOKIE_CLOTH,
    };
}

/* A plane through the origin facing +y: the ground. Every position is the origin and every
   size positive, so that changing only the type gives a valid shape (a capsule with a = b is
   a sphere); only a mesh needs its file. */
cvk_collider_desc cvk_default_collider_desc(void)
{
    return (cvk_collider_desc){
        .type = CVK_COLLIDER_PLANE,
        .name = NULL,
        .point = {0.0f, 0.0f, 0.0f},
        .normal = {0.0f, 1.0f, 0.0f},
        .center = {0.0f, 0.0f, 0.0f},
        .radius = 0.25f,
        .half_extents = {0.25f, 0.25f, 0.25f},
        .rotation = {1.0f, 0.0f, 0.0f, 0.0f},
        .a = {0.0f, 0.0f, 0.0f},
        .b = {0.0f, 0.0f, 0.0f},
        .apex = {0.0f, 0.0f, 0.0f},
        .funnel_a = 0.5f,
        .height = 1.0f,
        .file = NULL,
        .transform = {.scale = {1.0f, 1.0f, 1.0f}, .rotation = {1.0f, 0.0f, 0.0f, 0.0f},
                      .translation = {0.0f, 0.0f, 0.0f}},
        .friction = -1.0f,
        .static_friction = -1.0f,
        .motion = {.keyframes = NULL, .keyframe_count = 0, .loop = false},
        .color = {0.55f, 0.55f, 0.6f},
        .roughness = 0.5f,
        .texture = NULL,
        .texture_scale = 1.0f,
        .cookie_ = CVK_COOKIE_COLLIDER,
    };
}

cvk_attachment_desc cvk_default_attachment_desc(void)
{
    return (cvk_attachment_desc){
        .cloth = 0,
        .pins = NULL,
        .pin_count = 0,
        .pin_vertices = NULL,
        .pin_vertex_count = 0,
        .use_pin_box = false,
        .pin_box = {.min = {0.0f, 0.0f, 0.0f}, .max = {0.0f, 0.0f, 0.0f}},
        .motion = {.keyframes = NULL, .keyframe_count = 0, .loop = false},
        .cookie_ = CVK_COOKIE_ATTACHMENT,
    };
}

/* ---- the scene ---- */

static bool check_timing(const cvk_scene_desc* d, cvk_scene_issue* issue)
{
    if (!cvk_check_greater(issue, "dt", d->dt, 0.0))
        return false;
    /* dt is a float: 1e-6 written in a scene is the float nearest it, a little less. */
    if (d->dt < (float)CVK_MIN_DT)
        return cvk_issue_at(issue, "dt", "must be at least %g s (1/dt² must fit single precision "
                        "with room for masses and stiffnesses), got %s", CVK_MIN_DT,
                        cvk_float_text(d->dt).text);
    return cvk_check_count_range(issue, "substeps", d->substeps, 1, CVK_MAX_SUBSTEPS) &&
           cvk_check_count(issue, "frames", d->frames, 1) &&
           cvk_check_finite_array(issue, "gravity", d->gravity, 3) &&
           cvk_check_half_open(issue, "damping", d->damping, 0.0, 1.0);
}

/* The implicit method's linear solvers are its own (cg) or shared by name (jacobi). */
static bool check_implicit(const cvk_solver_desc* s, cvk_scene_issue* issue)
{
    bool implicit = s->method == CVK_METHOD_IMPLICIT;
    if (implicit && s->linear != CVK_LINEAR_CG && s->linear != CVK_LINEAR_JACOBI)
        return cvk_issue_at(issue, "solver.linear", "%s is not a linear solver of the implicit "
                        "method; use cg or jacobi", cvk_linear_solver_name(s->linear));
    if (!implicit && s->linear == CVK_LINEAR_CG)
        return cvk_issue_at(issue, "solver.linear", "cg solves the implicit method only; use rbgs, "
                        "jacobi, chebyshev or gs-cpu with %s", cvk_method_name(s->method));
    return cvk_check_at_least(issue, "solver.kd", s->kd, 0.0);
}

/* solver.tolerance and solver.max_iterations: one rule for the two methods that stop when
   converged (0: the method's default), and keys of theirs only. */
static bool check_stopping(const cvk_solver_desc* s, cvk_scene_issue* issue)
{
    if (s->tolerance != 0.0f && !cvk_check_open(issue, "solver.tolerance", s->tolerance, 0.0, 1.0))
        return false;
    if (s->max_iterations > CVK_MAX_SWEEPS)
        return cvk_issue_at(issue, "solver.max_iterations", "must be at most %u, got %" PRIu32,
                        CVK_MAX_SWEEPS, s->max_iterations);
    if (s->method == CVK_METHOD_EXPLICIT && (s->tolerance > 0.0f || s->max_iterations > 0))
        return cvk_issue_at(issue, s->tolerance > 0.0f ? "solver.tolerance"
                                                       : "solver.max_iterations",
                        "the explicit method solves no linear system; remove it");
    if (s->method != CVK_METHOD_PD)
        return true;
    if (s->max_iterations % s->inner_iterations != 0)
        return cvk_issue_at(issue, "solver.max_iterations", "pd runs whole outer iterations of "
                        "inner_iterations (%" PRIu32 ") sweeps: must be a multiple of %" PRIu32
                        ", got %" PRIu32, s->inner_iterations, s->inner_iterations,
                        s->max_iterations);
    if (s->linear == CVK_LINEAR_GS_CPU && s->tolerance > 0.0f)
        return cvk_issue_at(issue, "solver.tolerance", "gs-cpu (the host reference) runs every "
                        "sweep; remove tolerance or use rbgs, jacobi or chebyshev");
    return true;
}

cvk_solver_desc cvk_solver_desc_resolve(const cvk_solver_desc* solver)
{
    cvk_solver_desc r = *solver;
    if (r.method == CVK_METHOD_IMPLICIT) {
        if (r.tolerance == 0.0f)
            r.tolerance = 1e-3f;
        if (r.max_iterations == 0)
            r.max_iterations = 100;
    } else if (r.method == CVK_METHOD_PD) {
        if (r.max_iterations > 0 && r.inner_iterations > 0)
            r.outer_iterations = r.max_iterations / r.inner_iterations;
        r.max_iterations = r.outer_iterations * r.inner_iterations;
    }
    return r;
}

/* The explicit method's keys belong to it (kd to it and implicit), and it solves no linear
   system: a key of another method is a mistake, not something to ignore. */
static bool check_explicit(const cvk_solver_desc* s, cvk_scene_issue* issue)
{
    bool explicit_method = s->method == CVK_METHOD_EXPLICIT;
    if (!cvk_integrator_name(s->integrator))
        return cvk_issue_at(issue, "solver.integrator", "unknown integrator %d", (int)s->integrator);
    if (!cvk_damping_model_name(s->damping_model))
        return cvk_issue_at(issue, "solver.damping_model", "unknown damping model %d",
                        (int)s->damping_model);
    if (!cvk_fuse_name(s->fuse))
        return cvk_issue_at(issue, "solver.fuse", "unknown fuse mode %d", (int)s->fuse);
    if (!explicit_method && s->integrator != CVK_INTEGRATOR_NONE)
        return cvk_issue_at(issue, "solver.integrator", "is a key of the explicit method; remove it "
                        "or set \"method\": \"explicit\" (method is %s)",
                        cvk_method_name(s->method));
    if (!explicit_method && s->damping_model != CVK_DAMPING_NONE)
        return cvk_issue_at(issue, "solver.damping_model", "is a key of the explicit method; remove "
                        "it or set \"method\": \"explicit\" (method is %s)",
                        cvk_method_name(s->method));
    if (s->method == CVK_METHOD_PD && s->kd != 0.0f)
        return cvk_issue_at(issue, "solver.kd", "is a key of the implicit and explicit methods; pd "
                        "damps with \"damping\" (remove kd or change the method)");
    if (explicit_method && s->linear != CVK_LINEAR_RBGS)
        return cvk_issue_at(issue, "solver.linear", "the explicit method solves no linear system; "
                        "remove \"linear\" (got %s)", cvk_linear_solver_name(s->linear));
    return true;
}

/* m/m: a spring allowed past ten times its rest length is no limit (a typo for a percentage). */
#define MAX_STRAIN_LIMIT 10.0

static bool check_strain_limit(const cvk_solver_desc* s, cvk_scene_issue* issue)
{
    if (!cvk_check_finite(issue, "solver.strain_limit", s->strain_limit))
        return false;
    if (s->strain_limit < 0.0f || s->strain_limit > MAX_STRAIN_LIMIT)
        return cvk_issue_at(issue, "solver.strain_limit", "must be between 0 and %g, got %s",
                            MAX_STRAIN_LIMIT, cvk_float_text(s->strain_limit).text);
    if (s->strain_limit > 0.0f &&
        (s->method != CVK_METHOD_PD || s->linear == CVK_LINEAR_GS_CPU))
        return cvk_issue_at(issue, "solver.strain_limit", "only the pd solvers on the device "
                            "(rbgs, jacobi, chebyshev) limit strain; this scene uses %s",
                            s->method != CVK_METHOD_PD ? cvk_method_name(s->method)
                                                       : cvk_linear_solver_name(s->linear));
    return true;
}

bool cvk_solver_desc_check(const cvk_solver_desc* s, cvk_scene_issue* issue)
{
    if (!cvk_method_name(s->method))
        return cvk_issue_at(issue, "solver.method", "unknown method %d", (int)s->method);
    if (!cvk_linear_solver_name(s->linear))
        return cvk_issue_at(issue, "solver.linear", "unknown linear solver %d", (int)s->linear);
    if (!cvk_check_count_range(issue, "solver.outer_iterations", s->outer_iterations, 1,
                           CVK_MAX_SWEEPS) ||
        !cvk_check_count_range(issue, "solver.inner_iterations", s->inner_iterations, 1,
                           CVK_MAX_SWEEPS) ||
        !cvk_check_count_range(issue, "solver.tether_every", s->tether_every, 0, CVK_MAX_SWEEPS))
        return false;
    uint64_t sweeps = (uint64_t)s->outer_iterations * s->inner_iterations;
    if (sweeps > CVK_MAX_SWEEPS)
        return cvk_issue_at(issue, "solver", "%" PRIu32 " outer × %" PRIu32 " inner iterations are "
                        "%" PRIu64 " sweeps per substep; at most %u", s->outer_iterations,
                        s->inner_iterations, sweeps, CVK_MAX_SWEEPS);
    return cvk_check_open(issue, "solver.omega", s->omega, 0.0, 2.0) &&
           cvk_check_half_open(issue, "solver.chebyshev_rho", s->chebyshev_rho, 0.0, 1.0) &&
           check_strain_limit(s, issue) && check_implicit(s, issue) &&
           check_stopping(s, issue) && check_explicit(s, issue);
}

/* ---- one cloth; base is "cloths.N" ---- */

static bool check_grid(const cvk_cloth_desc* c, const char* base, uint64_t* total,
                       cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    cvk_key_join(path, base, "grid");
    if (c->grid[0] < 1 || c->grid[1] < 1)
        return cvk_issue_at(issue, path, "each dimension must be at least 1, got [%" PRIu32 ", %" PRIu32 "]",
                        c->grid[0], c->grid[1]);
    /* Both factors are below 2^32 and the running total stays at most 2^30 before this add,
       so the sum cannot wrap. */
    *total += (uint64_t)c->grid[0] * c->grid[1];
    if (*total > CVK_MAX_PARTICLES)
        return cvk_issue_at(issue, path, "%" PRIu64 " particles in all is more than clothvk supports (%" PRIu64 ")",
                        *total, CVK_MAX_PARTICLES);
    return true;
}

/* A side with one particle has no spacing, so its length may be 0. */
static bool check_size(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    char element[CVK_KEY_PATH_MAX];
    cvk_key_join(path, base, "size");
    for (uint32_t i = 0; i < 2; i++) {
        cvk_key_join_index(element, path, i);
        if (!cvk_check_finite(issue, element, c->size[i]))
            return false;
        if (c->grid[i] == 1 && c->size[i] < 0)
            return cvk_issue_at(issue, element, "must be at least 0, got %s", cvk_float_text(c->size[i]).text);
        if (c->grid[i] > 1 && c->size[i] <= 0)
            return cvk_issue_at(issue, element,
                            "must be greater than 0 (the grid has %" PRIu32 " particles along it), got %s",
                            c->grid[i], cvk_float_text(c->size[i]).text);
        if (c->size[i] > 0 && !cvk_check_length(issue, element, c->size[i]))
            return false;
    }
    return true;
}

static double dot3(const float* a, const float* b)
{
    return (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
}

static bool check_axes(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    char u_path[CVK_KEY_PATH_MAX];
    char v_path[CVK_KEY_PATH_MAX];
    cvk_key_join(u_path, base, "u_axis");
    cvk_key_join(v_path, base, "v_axis");
    if (!cvk_check_finite_array(issue, u_path, c->u_axis, 3) || !cvk_check_finite_array(issue, v_path, c->v_axis, 3))
        return false;
    const float* u = c->u_axis;
    const float* v = c->v_axis;
    double uu = dot3(u, u);
    double vv = dot3(v, v);
    double uv = dot3(u, v);
    if (!(uu > 0))
        return cvk_issue_at(issue, u_path, "must not be zero, got [%g, %g, %g]", u[0], u[1], u[2]);
    if (!(vv > 0))
        return cvk_issue_at(issue, v_path, "must not be zero, got [%g, %g, %g]", v[0], v[1], v[2]);
    /* |u × v|² = |u|²|v|² − (u·v)²; below 1e-12 of |u|²|v|² the sine of the angle is under 1e-6
       and the grid collapses onto a line. */
    if (uu * vv - uv * uv <= 1e-12 * uu * vv)
        return cvk_issue_at(issue, v_path, "must not be parallel to u_axis, got [%g, %g, %g]", v[0], v[1], v[2]);
    return true;
}

/* A density gives each particle a third of the area of its triangles; a rope has none. Mass
   counts only without a density. */
static bool check_mass(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    if (!cvk_check_at_least(issue, cvk_key_join(path, base, "density"), c->density, 0.0))
        return false;
    if (c->density == 0.0f)
        return cvk_check_greater(issue, cvk_key_join(path, base, "mass"), c->mass, 0.0);
    if (!c->mesh && (c->grid[0] == 1 || c->grid[1] == 1))
        return cvk_issue_at(issue, path, "a %" PRIu32 " x %" PRIu32 " grid is a rope, with no area for a density; "
                        "give its mass instead", c->grid[0], c->grid[1]);
    return true;
}

static bool check_material(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    return cvk_check_greater(issue, cvk_key_join(path, base, "rest_scale"), c->rest_scale, 0.0) && check_mass(c, base, issue) &&
           cvk_check_at_least(issue, cvk_key_join(path, base, "stiffness.structural"),
                          c->stiffness.structural, 0.0) &&
           cvk_check_at_least(issue, cvk_key_join(path, base, "stiffness.shear"), c->stiffness.shear, 0.0) &&
           cvk_check_at_least(issue, cvk_key_join(path, base, "stiffness.bend"), c->stiffness.bend, 0.0);
}

/* Every axis scaled by a finite non-zero factor (negative mirrors); a rotation of any length,
   normalised when the mesh is read, but not zero. */
static bool check_transform(const cvk_transform* t, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    char element[CVK_KEY_PATH_MAX];
    cvk_key_join(path, base, "transform.scale");
    for (uint32_t i = 0; i < 3; i++) {
        if (!cvk_check_scale(issue, cvk_key_join_index(element, path, i), t->scale[i]))
            return false;
    }
    if (!cvk_check_quaternion(issue, cvk_key_join(path, base, "transform.rotation"), t->rotation))
        return false;
    return cvk_check_position(issue, cvk_key_join(path, base, "transform.translation"), t->translation, 3);
}

static bool check_file_name(cvk_scene_issue* issue, const char* path, const char* file)
{
    return file[0] != '\0' || cvk_issue_at(issue, path, "must name a mesh file, got an empty string");
}

/* A mesh cloth's shape comes from its file, so the grid keys are not looked at; its particle
   count is known only once the file is read. */
static bool check_shape(const cvk_cloth_desc* c, const char* base, uint64_t* total, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    if (c->mesh)
        return check_file_name(issue, cvk_key_join(path, base, "mesh"), c->mesh);
    return check_grid(c, base, total, issue) && check_size(c, base, issue) &&
           cvk_check_position(issue, cvk_key_join(path, base, "origin"), c->origin, 3) && check_axes(c, base, issue);
}

/* Names are printed by the tools and written into OBJ files (an "o" line): a control
   character (an ESC sequence, a CR or LF forging a line) has no place in one. */
static bool check_name(cvk_scene_issue* issue, const char* path, const char* name)
{
    for (const unsigned char* c = (const unsigned char*)name; c && *c; c++)
        if (*c < 0x20 || *c == 0x7f)
            return cvk_issue_at(issue, path, "contains the control character \\x%02x at byte %u",
                            *c, (unsigned)(c - (const unsigned char*)name));
    return true;
}

static bool check_velocity(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    const float* v = c->velocity;
    if (!cvk_check_finite_array(issue, cvk_key_join(path, base, "velocity"), v, 3))
        return false;
    double speed = sqrt(dot3(v, v));
    if (speed <= CVK_MAX_VELOCITY)
        return true;
    return cvk_issue_at(issue, path, "must be at most %g m/s in magnitude, got %s m/s ([%s, %s, %s])",
                    CVK_MAX_VELOCITY, cvk_float_text(speed).text, cvk_float_text(v[0]).text,
                    cvk_float_text(v[1]).text, cvk_float_text(v[2]).text);
}

/* 0 (none) or a scale of the rest distance from 1 (exactly) to CVK_MAX_TETHER_SCALE. */
static bool check_tethers(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    cvk_key_join(path, base, "tethers");
    if (!cvk_check_finite(issue, path, c->tethers))
        return false;
    if (c->tethers == 0.0f || (c->tethers >= 1.0f && c->tethers <= CVK_MAX_TETHER_SCALE))
        return true;
    return cvk_issue_at(issue, path, "must be 0 (no tethers) or from 1 to %g (a scale of the rest "
                    "distance to the pins), got %s", CVK_MAX_TETHER_SCALE, cvk_float_text(c->tethers).text);
}

static bool check_texture(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX], element[CVK_KEY_PATH_MAX];
    if (c->texture && c->texture[0] == '\0')
        return cvk_issue_at(issue, cvk_key_join(path, base, "texture"), "must name an image file, got an empty string");
    cvk_key_join(path, base, "texture_scale");
    for (uint32_t i = 0; i < 2; i++)
        if (!cvk_check_greater(issue, cvk_key_join_index(element, path, i), c->texture_scale[i], 0.0))
            return false;
    return true;
}

static bool check_cloth(const cvk_cloth_desc* c, uint32_t index, uint64_t* total, cvk_scene_issue* issue)
{
    char base[CVK_KEY_PATH_MAX];
    char path[CVK_KEY_PATH_MAX];
    cvk_key_join_index(base, "cloths", index);
    if (c->cookie_ != CVK_COOKIE_CLOTH)
        return cvk_issue_at(issue, base, "cloth description was not made by cvk_default_cloth_desc()");
    return check_name(issue, cvk_key_join(path, base, "name"), c->name) &&
           check_shape(c, base, total, issue) && check_transform(&c->transform, base, issue) &&
           check_material(c, base, issue) && cvk_check_pins(c, base, issue) && cvk_check_pin_box(c, base, issue) &&
           cvk_check_closed_array(issue, cvk_key_join(path, base, "color"), c->color, 3, 0.0, 1.0) &&
           check_texture(c, base, issue) && cvk_look_check(c, base, issue) && check_velocity(c, base, issue) &&
           check_tethers(c, base, issue) &&
           cvk_aero_check(&c->aero, base, issue);
}

/* Tethers are a pass of the projective-dynamics solve; the other families have none yet. */
static bool check_tether_solver(const cvk_scene_desc* d, cvk_scene_issue* issue)
{
    if (d->solver.method == CVK_METHOD_PD)
        return true;
    for (uint32_t i = 0; i < d->cloth_count; i++) {
        if (d->cloths[i].tethers == 0.0f)
            continue;
        char base[CVK_KEY_PATH_MAX], path[CVK_KEY_PATH_MAX];
        cvk_key_join_index(base, "cloths", i);
        return cvk_issue_at(issue, cvk_key_join(path, base, "tethers"), "the %s method has no tethers; "
                        "remove them or use pd", cvk_method_name(d->solver.method));
    }
    return true;
}

/* ---- the render block ---- */

static bool check_direction(cvk_scene_issue* issue, const char* path, const float v[3])
{
    if (!cvk_check_finite_array(issue, path, v, 3))
        return false;
    if (v[0] == 0.0f && v[1] == 0.0f && v[2] == 0.0f)
        return cvk_issue_at(issue, path, "must not be zero, got [0, 0, 0]");
    return true;
}

static bool check_light(const cvk_light* light, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    return check_direction(issue, cvk_key_join(path, base, "direction"), light->direction) &&
           cvk_check_closed_array(issue, cvk_key_join(path, base, "color"), light->color, 3, 0.0, 100.0);
}

static bool check_render_size(const cvk_render_desc* r, cvk_scene_issue* issue)
{
    if (r->size[0] < 1 || r->size[1] < 1)
        return cvk_issue_at(issue, "render.size", "each dimension must be at least 1, got [%" PRIu32 ", %" PRIu32 "]",
                        r->size[0], r->size[1]);
    if (r->shadow_map_size < 16 || r->shadow_map_size > 16384)
        return cvk_issue_at(issue, "render.shadow_map_size", "must be from 16 to 16384, got %" PRIu32,
                        r->shadow_map_size);
    if (r->samples != 1 && r->samples != 2 && r->samples != 4 && r->samples != 8)
        return cvk_issue_at(issue, "render.samples", "must be 1, 2, 4 or 8, got %" PRIu32, r->samples);
    return true;
}

static bool check_camera(const cvk_render_desc* r, cvk_scene_issue* issue)
{
    if (!cvk_check_position(issue, "render.eye", r->eye, 3) ||
        !cvk_check_position(issue, "render.target", r->target, 3) ||
        !check_direction(issue, "render.up", r->up) || !cvk_check_open(issue, "render.fov_y", r->fov_y, 0.0, 180.0))
        return false;
    if (r->auto_eye || r->auto_target || r->camera_keyframe_count > 0)
        return true; /* a keyframed camera: check_camera_keyframes */
    float view[3] = {r->target[0] - r->eye[0], r->target[1] - r->eye[1], r->target[2] - r->eye[2]};
    double vv = dot3(view, view);
    double uu = dot3(r->up, r->up);
    double vu = dot3(view, r->up);
    if (!(vv > 0))
        return cvk_issue_at(issue, "render.target", "must differ from render.eye, got [%g, %g, %g] for both",
                        r->target[0], r->target[1], r->target[2]);
    /* As for the cloth axes: the camera needs a sideways direction, up × view. */
    if (vv * uu - vu * vu <= 1e-12 * vv * uu)
        return cvk_issue_at(issue, "render.up", "must not be parallel to the view direction (target - eye), got "
                        "[%g, %g, %g]", r->up[0], r->up[1], r->up[2]);
    return true;
}

/* Each keyframe's eye and target as render.eye and render.target are checked, at increasing times. */
static bool check_camera_keyframes(const cvk_render_desc* r, cvk_scene_issue* issue)
{
    const char* base = "render.camera_keyframes";
    if (r->camera_keyframe_count > CVK_MAX_KEYFRAMES)
        return cvk_issue_at(issue, base, "at most %u keyframes, got %" PRIu32, CVK_MAX_KEYFRAMES, r->camera_keyframe_count);
    if (r->camera_keyframe_count > 0 && !r->camera_keyframes)
        return cvk_issue_at(issue, base, "is NULL but camera_keyframe_count is %" PRIu32, r->camera_keyframe_count);
    char element[CVK_KEY_PATH_MAX], path[CVK_KEY_PATH_MAX];
    for (uint32_t i = 0; i < r->camera_keyframe_count; i++) {
        const cvk_camera_keyframe* k = &r->camera_keyframes[i];
        cvk_key_join_index(element, base, i);
        if (!cvk_check_at_least(issue, cvk_key_join(path, element, "time"), k->time, 0.0))
            return false;
        if (i > 0 && !(k->time > k[-1].time))
            return cvk_issue_at(issue, path, "must be greater than the previous keyframe's time (%s), got %s",
                            cvk_float_text(k[-1].time).text, cvk_float_text(k->time).text);
        if (!cvk_check_position(issue, cvk_key_join(path, element, "eye"), k->eye, 3) ||
            !cvk_check_position(issue, cvk_key_join(path, element, "target"), k->target, 3))
            return false;
        float view[3] = {k->target[0] - k->eye[0], k->target[1] - k->eye[1], k->target[2] - k->eye[2]};
        double vv = dot3(view, view), uu = dot3(r->up, r->up), vu = dot3(view, r->up);
        if (!(vv > 0))
            return cvk_issue_at(issue, path, "must differ from the keyframe's eye, got [%g, %g, %g] for both",
                            k->target[0], k->target[1], k->target[2]);
        if (vv * uu - vu * vu <= 1e-12 * vv * uu)
            return cvk_issue_at(issue, path, "must not lie straight above or below the keyframe's eye (along render.up)");
    }
    if (r->camera_loop && r->camera_keyframe_count < 2)
        return cvk_issue_at(issue, "render.camera_loop", "a looping camera needs at least two keyframes, got %" PRIu32,
                        r->camera_keyframe_count);
    return true;
}

static bool check_render(const cvk_render_desc* r, cvk_scene_issue* issue)
{
    return check_render_size(r, issue) && check_camera(r, issue) && check_light(&r->key, "render.key", issue) &&
           check_light(&r->fill, "render.fill", issue) &&
           cvk_check_closed_array(issue, "render.ambient", r->ambient, 3, 0.0, 1.0) &&
           cvk_check_closed_array(issue, "render.background", r->background, 3, 0.0, 1.0) &&
           cvk_check_finite(issue, "render.ground_height", r->ground_height) &&
           cvk_check_closed_array(issue, "render.ground_color", r->ground_color, 3, 0.0, 1.0) &&
           cvk_check_closed(issue, "render.key_angle", r->key_angle, 0.0, 20.0) &&
           cvk_check_closed(issue, "render.ao_radius", r->ao_radius, 0.0, CVK_MAX_COORDINATE) &&
           cvk_check_closed(issue, "render.smooth", r->smooth, 0.0, 8.0) &&
           cvk_check_closed(issue, "render.vertex_lighting", r->vertex_lighting, 0.0, 64.0) &&
           check_camera_keyframes(r, issue) && cvk_fit_check(r, issue);
}

bool cvk_render_desc_check(const cvk_render_desc* desc, cvk_scene_issue* issue)
{
    return check_render(desc, issue);
}

/* ---- colliders (the collision block is in scene_collision.c); base is "colliders.N" ---- */

static bool check_box_shape(const cvk_collider_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    char element[CVK_KEY_PATH_MAX];
    if (!cvk_check_position(issue, cvk_key_join(path, base, "center"), c->center, 3))
        return false;
    cvk_key_join(path, base, "half_extents");
    for (uint32_t i = 0; i < 3; i++) {
        if (!cvk_check_length(issue, cvk_key_join_index(element, path, i), c->half_extents[i]))
            return false;
    }
    return cvk_check_quaternion(issue, cvk_key_join(path, base, "rotation"), c->rotation);
}

/* A mesh collider's file is read (and checked for being closed) when the simulation is made. */
static bool check_mesh_shape(const cvk_collider_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    cvk_key_join(path, base, "file");
    if (!c->file)
        return cvk_issue_at(issue, path, "a mesh collider needs a mesh file, got NULL");
    return check_file_name(issue, path, c->file) && check_transform(&c->transform, base, issue);
}

/* Only the fields of the collider's own type are read, so only they are checked. Paths are
   the scene file's keys: a funnel's funnel_a is its "a". */
static bool check_collider_shape(const cvk_collider_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    switch (c->type) {
    case CVK_COLLIDER_PLANE:
        return cvk_check_position(issue, cvk_key_join(path, base, "point"), c->point, 3) &&
               check_direction(issue, cvk_key_join(path, base, "normal"), c->normal);
    case CVK_COLLIDER_SPHERE:
        return cvk_check_position(issue, cvk_key_join(path, base, "center"), c->center, 3) &&
               cvk_check_length(issue, cvk_key_join(path, base, "radius"), c->radius);
    case CVK_COLLIDER_BOX: return check_box_shape(c, base, issue);
    case CVK_COLLIDER_CAPSULE:
        return cvk_check_position(issue, cvk_key_join(path, base, "a"), c->a, 3) &&
               cvk_check_position(issue, cvk_key_join(path, base, "b"), c->b, 3) &&
               cvk_check_length(issue, cvk_key_join(path, base, "radius"), c->radius);
    case CVK_COLLIDER_FUNNEL:
        return cvk_check_position(issue, cvk_key_join(path, base, "apex"), c->apex, 3) &&
               cvk_check_length(issue, cvk_key_join(path, base, "a"), c->funnel_a) &&
               cvk_check_length(issue, cvk_key_join(path, base, "height"), c->height);
    case CVK_COLLIDER_MESH: return check_mesh_shape(c, base, issue);
    case CVK_COLLIDER_TYPE_COUNT: break;
    }
    return cvk_issue_at(issue, cvk_key_join(path, base, "type"), "unknown collider type %d", (int)c->type);
}

/* A coefficient below 0 stands for the scene's (the C API's "default"; a scene file leaves
   the key out instead); the pair in use must have static at least kinetic. */
static bool check_collider_friction(const cvk_collider_desc* c, const cvk_collision_desc* scene, const char* base,
                                    cvk_scene_issue* issue)
{
    char kinetic_path[CVK_KEY_PATH_MAX];
    char static_path[CVK_KEY_PATH_MAX];
    if (!cvk_check_finite(issue, cvk_key_join(kinetic_path, base, "friction"), c->friction) ||
        !cvk_check_finite(issue, cvk_key_join(static_path, base, "static_friction"), c->static_friction))
        return false;
    double kinetic = c->friction < 0 ? scene->friction : c->friction;
    double fixed = c->static_friction < 0 ? scene->static_friction : c->static_friction;
    if (fixed >= kinetic)
        return true;
    if (c->static_friction < 0)
        return cvk_issue_at(issue, static_path, "is not given, and collision.static_friction (%s) is below this "
                        "collider's friction (%s): give a static_friction of at least %s", cvk_float_text(fixed).text,
                        cvk_float_text(kinetic).text, cvk_float_text(kinetic).text);
    return cvk_issue_at(issue, static_path, "must be at least %s (%s), got %s",
                    c->friction < 0 ? "collision.friction" : "friction", cvk_float_text(kinetic).text,
                    cvk_float_text(fixed).text);
}

static bool check_collider(const cvk_collider_desc* c, uint32_t index, const cvk_collision_desc* scene,
                           cvk_scene_issue* issue)
{
    char base[CVK_KEY_PATH_MAX];
    char path[CVK_KEY_PATH_MAX];
    cvk_key_join_index(base, "colliders", index);
    if (c->cookie_ != CVK_COOKIE_COLLIDER)
        return cvk_issue_at(issue, base, "collider description was not made by cvk_default_collider_desc()");
    return check_name(issue, cvk_key_join(path, base, "name"), c->name) && check_collider_shape(c, base, issue) &&
           check_collider_friction(c, scene, base, issue) && cvk_collider_look_check(c, base, issue) &&
           cvk_check_motion(&c->motion, base, issue);
}

static bool check_colliders(const cvk_scene_desc* d, cvk_scene_issue* issue)
{
    if (!cvk_collision_check(&d->collision, issue))
        return false;
    if (d->collider_count > CVK_MAX_COLLIDERS)
        return cvk_issue_at(issue, "colliders", "at most %u colliders, got %" PRIu32, CVK_MAX_COLLIDERS,
                        d->collider_count);
    if (d->collider_count > 0 && !d->colliders)
        return cvk_issue_at(issue, "colliders", "is NULL but collider_count is %" PRIu32, d->collider_count);
    for (uint32_t i = 0; i < d->collider_count; i++) {
        if (!check_collider(&d->colliders[i], i, &d->collision, issue))
            return false;
    }
    /* The explicit integrators have no contact response. */
    if (d->solver.method == CVK_METHOD_EXPLICIT && (d->collider_count > 0 || d->collision.self))
        return cvk_issue_at(issue, "solver.method", "explicit does not handle contact; remove "
                        "\"colliders\" and \"collision.self\", or use pd");
    return true;
}

bool cvk_scene_desc_check(const cvk_scene_desc* desc, cvk_scene_issue* issue)
{
    if (desc->cookie_ != CVK_COOKIE_SCENE)
        return cvk_issue_at(issue, "", "scene description was not made by cvk_default_scene_desc()");
    if (!check_name(issue, "name", desc->name) || !check_timing(desc, issue) ||
        !cvk_solver_desc_check(&desc->solver, issue))
        return false;
    if (!desc->cloths || desc->cloth_count < 1)
        return cvk_issue_at(issue, "cloths", "a scene needs at least one cloth");
    uint64_t total = 0;
    for (uint32_t i = 0; i < desc->cloth_count; i++) {
        if (!check_cloth(&desc->cloths[i], i, &total, issue))
            return false;
    }
    return check_tether_solver(desc, issue) && check_colliders(desc, issue) &&
           cvk_attachments_check(desc, issue) && cvk_wind_check(desc, issue) &&
           cvk_tearing_check(desc, issue) && check_render(&desc->render, issue);
}

cvk_step_params cvk_step_params_of(const cvk_scene_desc* scene)
{
    return (cvk_step_params){
        .dt = scene->dt,
        .substeps = scene->substeps,
        .integrate = scene->integrate,
        .gravity = {scene->gravity[0], scene->gravity[1], scene->gravity[2]},
        .damping = scene->damping,
        .contact = scene->collision.self || scene->collider_count > 0,
    };
}

cvk_result cvk_scene_desc_validate(const cvk_scene_desc* desc, cvk_error* error)
{
    if (!desc)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "scene description is NULL");
    cvk_scene_issue issue;
    return cvk_scene_desc_check(desc, &issue) ? CVK_SUCCESS : cvk_fail_issue(error, &issue);
}

cvk_result cvk_fail_issue(cvk_error* error, const cvk_scene_issue* issue)
{
    if (issue->path[0] == '\0')
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s", issue->problem);
    return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s", issue->path, issue->problem);
}

uint32_t cvk_scene_collider_types(const cvk_scene_desc* desc)
{
    uint32_t types = 0;
    for (uint32_t i = 0; i < desc->collider_count; i++)
        types |= 1u << desc->colliders[i].type;
    return types;
}
