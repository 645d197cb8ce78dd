/* Implicit Euler with colliders (shaders/solvers/implicit_contact.comp, the contact filter S = I − n nᵀ
   in shaders/solvers/implicit_common.glsl, the release in implicit_integrate.comp):
   - device CG and block Jacobi equal the host double-precision reference, iteration count by
     iteration count, on small random cloths that start partly inside a tilted plane and move
     at random (holding, moving out, the filtered solve and the release), and over four
     substeps;
   - a cloth dropped on a plane (level and tilted), with CG and with Jacobi: after every frame
     no free particle is deeper than DEEPEST thicknesses into the plane's thickness, every held
     particle lies at the thickness to float rounding, the pinned corner keeps its bits, and
     the cloth comes to rest;
   - a cloth dropped on a sphere and on a box stays out of it, its held particles at the
     thickness;
   - a plane moved up by keyframes lifts the cloth lying on it, which stays on it;
   - a snapshot taken on a moving tilted plane steps on to the same bits;
   - friction on a 30° incline: held above tan 30°, sliding at g (sin θ − μ cos θ) below;
   - self-contact (implicit_self.comp): two cloths dropped onto a third pinned at its corners,
     with CG and with Jacobi, have no intersecting pair at any frame (without self-contact the
     same drop has some), and every free particle ends every substep within its bound; so too
     when the drop starts with rbgs and switches to implicit halfway. */
#include "topology/build.h"
#include "harness.h"
#include "solvers/solve_implicit.h"
#include "contact/collide.h"

/* Float rounding over one substep with up to 5 iterations, relative to the largest change of
   the substep (as tests/solvers/test_implicit.c). */
#define SAME_TO_ROUNDING 1e-4
/* m: a held particle ends its substep on the surface (thickness away) to float rounding of
   coordinates near 1 m (a few ulps of 6e-8). */
#define ON_SURFACE 1e-6
/* A free particle can enter the thickness during one substep by what the solve adds to its
   velocity along n times h; the next substep holds it and moves it out. At most this many
   thicknesses (measured: below 1e-3; printed for each run). */
#define DEEPEST 0.05
#define THICKNESS 0.01f
#define PI 3.14159265358979323846

static double dot3d(const double* a, const double* b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* ---- the device against the host reference ------------------------------------------------ */

typedef struct plane_case {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    cvk_collider_desc plane;
    uint32_t pins[2][2];
    double host_plane[1][6]; /* point, unit normal, in double */
} plane_case;

static void make_plane_case(cvk_context* ctx, harness_rng* rng, plane_case* pc,
                            cvk_linear_solver linear, float** x0, float** v0, uint64_t* n)
{
    pc->cloth = cvk_default_cloth_desc();
    pc->cloth.grid[0] = 3 + harness_next(rng) % 6;
    pc->cloth.grid[1] = 3 + harness_next(rng) % 6;
    pc->cloth.size[0] = (float)harness_uniform(rng, 0.3, 1.0);
    pc->cloth.size[1] = (float)harness_uniform(rng, 0.3, 1.0);
    pc->cloth.stiffness.structural = (float)harness_uniform(rng, 1e2, 1e4);
    pc->cloth.stiffness.shear = (float)harness_uniform(rng, 1e1, 1e3);
    pc->cloth.stiffness.bend = (float)harness_uniform(rng, 1e0, 1e2);
    uint32_t pins = harness_next(rng) % 3;
    for (uint32_t p = 0; p < pins; p++) {
        pc->pins[p][0] = harness_next(rng) % pc->cloth.grid[0];
        pc->pins[p][1] = harness_next(rng) % pc->cloth.grid[1];
    }
    pc->cloth.pins = (const uint32_t(*)[2])pc->pins;
    pc->cloth.pin_count = pins;
    pc->scene = cvk_default_scene_desc();
    pc->scene.cloths = &pc->cloth;
    pc->scene.cloth_count = 1;
    pc->scene.substeps = 1;
    pc->scene.dt = (float)harness_uniform(rng, 0.002, 0.01);
    pc->scene.damping = (float)harness_uniform(rng, 0.0, 0.02);
    pc->scene.solver.method = CVK_METHOD_IMPLICIT;
    pc->scene.solver.linear = linear;
    pc->scene.solver.kd = (float)harness_uniform(rng, 0.0, 0.5);
    pc->scene.solver.tolerance = 1e-7f; /* runs every iteration it is given */
    pc->scene.collision.thickness = THICKNESS;
    /* The plane below starts through the cloth on purpose: a start inside a collider is
       refused otherwise (cvk_sim_check_collider_start). */
    pc->scene.collision.allow_intersecting_start = true;
    *n = (uint64_t)pc->cloth.grid[0] * pc->cloth.grid[1];
    harness_random_start(ctx, &pc->scene, rng, 0.01, 0.5, *n, x0, v0);
    /* A tilted plane through the cloth's middle: about half the particles start inside. */
    double mid[3] = {0, 0, 0}, normal[3];
    for (uint64_t p = 0; p < *n; p++)
        for (int c = 0; c < 3; c++)
            mid[c] += (*x0)[3 * p + c] / (double)*n;
    for (int c = 0; c < 3; c++)
        normal[c] = harness_uniform(rng, -1.0, 1.0);
    normal[1] += 2.0;
    double len = sqrt(dot3d(normal, normal));
    pc->plane = cvk_default_collider_desc();
    pc->plane.type = CVK_COLLIDER_PLANE;
    for (int c = 0; c < 3; c++) {
        pc->plane.point[c] = (float)mid[c];
        pc->plane.normal[c] = (float)(normal[c] / len);
    }
    double flen = sqrt((double)pc->plane.normal[0] * pc->plane.normal[0] +
                       (double)pc->plane.normal[1] * pc->plane.normal[1] +
                       (double)pc->plane.normal[2] * pc->plane.normal[2]);
    for (int c = 0; c < 3; c++) {
        pc->host_plane[0][c] = pc->plane.point[c];
        pc->host_plane[0][3 + c] = pc->plane.normal[c] / flen;
    }
    pc->scene.colliders = &pc->plane;
    pc->scene.collider_count = 1;
}

/* `substeps` reference substeps from (x0, v0) into (hx, hv), user order; the iterations in
   all. */
static uint32_t host_substeps(const plane_case* pc, const float* x0, const float* v0,
                              uint32_t substeps, double* hx, double* hv)
{
    cvk_error err;
    cvk_build b;
    REQUIRE_OK(cvk_build_create(&pc->scene, &b, &err), err);
    size_t n = b.particle_count;
    double* x = malloc(3 * n * sizeof(double));
    double* v = malloc(3 * n * sizeof(double));
    for (uint32_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++) {
            x[3 * p + c] = x0[3 * b.user_of[p] + c];
            v[3 * p + c] = p < b.free_count ? v0[3 * b.user_of[p] + c] : 0.0;
        }
    cvk_step_params step_params = cvk_step_params_of(&pc->scene);
    cvk_implicit_params ip = cvk_implicit_params_of(&step_params, &pc->scene.solver);
    ip.planes = (const double(*)[6])pc->host_plane;
    ip.plane_count = 1;
    ip.thickness = THICKNESS;
    ip.friction = pc->scene.collision.friction;
    ip.static_friction = pc->scene.collision.static_friction;
    uint32_t iterations = 0;
    for (uint32_t k = 0; k < substeps; k++) {
        cvk_implicit_report rep;
        CHECK(cvk_ref_implicit_substep(&b, &ip, x, v, &rep), "out of memory");
        CHECK(!rep.breakdown, "the reference broke down");
        iterations += rep.iterations;
    }
    for (uint32_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++) {
            hx[3 * b.user_of[p] + c] = x[3 * p + c];
            hv[3 * b.user_of[p] + c] = v[3 * p + c];
        }
    free(x);
    free(v);
    cvk_build_destroy(&b);
    return iterations;
}

/* Largest |a − b| over the largest |b − before|. */
static double relative_diff(const float* a, const double* b, const float* before, size_t n)
{
    double diff = 0.0, scale = 1e-30;
    for (size_t i = 0; i < n; i++) {
        double d = fabs(a[i] - b[i]);
        diff = isnan(d) || d > diff ? d : diff;
        scale = fmax(scale, fabs(b[i] - before[i]));
    }
    return diff / scale;
}

/* The device's state after one frame of `substeps` from (x, v), in place; its statistics and
   its filter (4 floats per particle). */
static void device_frame(cvk_context* ctx, const cvk_scene_desc* scene, float* x, float* v,
                         cvk_sim_stats* st, float* held)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    uint64_t n = cvk_sim_particle_count(sim);
    REQUIRE_OK(cvk_sim_write_state(sim, x, v, n, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
    REQUIRE_OK(cvk_sim_read_state(sim, x, v, n, &err), err);
    REQUIRE_OK(cvk_sim_get_stats(sim, st, &err), err);
    REQUIRE_OK(cvk_implicit_read_held(sim, held, &err), err);
    cvk_sim_destroy(sim);
}

static void reference_with_plane(cvk_context* ctx, cvk_linear_solver linear)
{
    harness_rng rng = {0x6a09e667u + (uint32_t)linear};
    const char* name = cvk_linear_solver_name(linear);
    uint32_t held_seen = 0, released_seen = 0, free_seen = 0;
    for (int trial = 0; trial < 5; trial++) {
        plane_case pc;
        float *x0, *v0;
        uint64_t n;
        make_plane_case(ctx, &rng, &pc, linear, &x0, &v0, &n);
        float* x = malloc(3 * n * sizeof(float));
        float* v = malloc(3 * n * sizeof(float));
        float* held = malloc(4 * n * sizeof(float));
        double* hx = malloc(3 * n * sizeof(double));
        double* hv = malloc(3 * n * sizeof(double));
        double* hv_previous = calloc(3 * n, sizeof(double));
        const uint32_t counts[] = {1, 2, 3, 5};
        for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
            pc.scene.solver.max_iterations = counts[k];
            memcpy(x, x0, 3 * n * sizeof(float));
            memcpy(v, v0, 3 * n * sizeof(float));
            cvk_sim_stats st;
            device_frame(ctx, &pc.scene, x, v, &st, held);
            uint32_t iterations = host_substeps(&pc, x0, v0, 1, hx, hv);
            double dv = relative_diff(v, hv, v0, 3 * n), dx = relative_diff(x, hx, x0, 3 * n);
            CHECK(dv < SAME_TO_ROUNDING && dx < SAME_TO_ROUNDING,
                  "%s trial %d (%ux%u, %u pins, h %g) after %u iterations: velocities differ by "
                  "%g, positions by %g of the step", name, trial, pc.cloth.grid[0],
                  pc.cloth.grid[1], pc.cloth.pin_count, pc.scene.dt, counts[k], dv, dx);
            CHECK(st.solver_iterations == iterations && st.solver_breakdowns == 0,
                  "%s trial %d: the device did %u iterations (%u breakdowns), the host %u", name,
                  trial, st.solver_iterations, st.solver_breakdowns, iterations);
            if (k > 0 && iterations == counts[k]) {
                double apart = 0.0, scale = 1e-30;
                for (uint64_t i = 0; i < 3 * n; i++) {
                    apart = fmax(apart, fabs(hv[i] - hv_previous[i]));
                    scale = fmax(scale, fabs(hv[i] - v0[i]));
                }
                CHECK(apart / scale > 10 * SAME_TO_ROUNDING,
                      "%s trial %d: %u and %u iterations differ by only %g", name, trial,
                      counts[k - 1], counts[k], apart / scale);
            }
            memcpy(hv_previous, hv, 3 * n * sizeof(double));
            for (uint64_t p = 0; p < n; p++) {
                held_seen += held[4 * p + 3] > 0.0f;
                released_seen += held[4 * p + 3] < 0.0f;
                free_seen += held[4 * p + 3] == 0.0f;
            }
        }
        /* Four substeps: holding and releasing carry from one substep to the next. */
        pc.scene.substeps = 4;
        pc.scene.solver.max_iterations = 5;
        memcpy(x, x0, 3 * n * sizeof(float));
        memcpy(v, v0, 3 * n * sizeof(float));
        cvk_sim_stats st;
        device_frame(ctx, &pc.scene, x, v, &st, held);
        uint32_t iterations = host_substeps(&pc, x0, v0, 4, hx, hv);
        double dv = relative_diff(v, hv, v0, 3 * n), dx = relative_diff(x, hx, x0, 3 * n);
        CHECK(dv < 10 * SAME_TO_ROUNDING && dx < 10 * SAME_TO_ROUNDING &&
                  st.solver_iterations == iterations,
              "%s trial %d, 4 substeps: velocities differ by %g, positions by %g of the step; "
              "%u iterations on the device, %u on the host", name, trial, dv, dx,
              st.solver_iterations, iterations);
        free(x0);
        free(v0);
        free(x);
        free(v);
        free(held);
        free(hx);
        free(hv);
        free(hv_previous);
    }
    /* The comparison covers each case. */
    CHECK(held_seen > 0 && released_seen > 0 && free_seen > 0,
          "%s: %u held, %u released and %u free particles over the trials: a case is missing",
          name, held_seen, released_seen, free_seen);
    printf("%s against the reference with a plane: %u held, %u released, %u free\n", name,
           held_seen, released_seen, free_seen);
}

/* ---- physics: dropped on colliders -------------------------------------------------------- */

typedef struct drop_run {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    cvk_collider_desc collider;
    cvk_keyframe keys[2];
    uint32_t pin[1][2];
    double rise; /* m/s: the collider moves up at this speed (keyframes) */
} drop_run;

/* A horizontal 10 × 10 cloth of 0.5 m at height `height`, its corner [0, 0] pinned when `pin`,
   over `collider`, with implicit Euler and `linear`. */
static void make_drop(drop_run* d, cvk_linear_solver linear, float height, bool pin)
{
    d->cloth = cvk_default_cloth_desc();
    d->cloth.grid[0] = d->cloth.grid[1] = 10;
    d->cloth.size[0] = d->cloth.size[1] = 0.5f;
    const float origin[3] = {-0.25f, height, -0.25f}, u[3] = {1, 0, 0}, v[3] = {0, 0, 1};
    memcpy(d->cloth.origin, origin, sizeof origin);
    memcpy(d->cloth.u_axis, u, sizeof u);
    memcpy(d->cloth.v_axis, v, sizeof v);
    d->cloth.stiffness.structural = 1e3f;
    d->cloth.stiffness.shear = 1e3f;
    d->cloth.stiffness.bend = 10.0f;
    d->pin[0][0] = d->pin[0][1] = 0;
    d->cloth.pins = (const uint32_t(*)[2])d->pin;
    d->cloth.pin_count = pin ? 1 : 0;
    d->scene = cvk_default_scene_desc();
    d->scene.cloths = &d->cloth;
    d->scene.cloth_count = 1;
    d->scene.dt = 0.004f;
    d->scene.substeps = 4;
    d->scene.damping = 0.01f;
    d->scene.solver.method = CVK_METHOD_IMPLICIT;
    d->scene.solver.linear = linear;
    d->scene.solver.kd = 0.05f;
    d->scene.solver.tolerance = 1e-3f;
    d->scene.solver.max_iterations = linear == CVK_LINEAR_JACOBI ? 200 : 100;
    d->scene.collision.thickness = THICKNESS;
    d->scene.colliders = &d->collider;
    d->scene.collider_count = 1;
    d->rise = 0.0;
}

static void set_plane(drop_run* d, const float point[3], const float normal[3])
{
    d->collider = cvk_default_collider_desc();
    d->collider.type = CVK_COLLIDER_PLANE;
    memcpy(d->collider.point, point, 3 * sizeof(float));
    memcpy(d->collider.normal, normal, 3 * sizeof(float));
}

/* Signed distance (m) of p from the collider's surface at time t. */
static double surface_distance(const drop_run* d, const float* p, double t)
{
    const cvk_collider_desc* c = &d->collider;
    if (c->type == CVK_COLLIDER_BOX) { /* axis-aligned here */
        double outside = 0.0, inside = -INFINITY;
        for (int k = 0; k < 3; k++) {
            double q = fabs(p[k] - c->center[k]) - c->half_extents[k];
            outside += q > 0.0 ? q * q : 0.0;
            inside = fmax(inside, q);
        }
        return sqrt(outside) + fmin(inside, 0.0);
    }
    if (c->type == CVK_COLLIDER_SPHERE) {
        double r[3] = {p[0] - c->center[0], p[1] - c->center[1], p[2] - c->center[2]};
        return sqrt(dot3d(r, r)) - c->radius;
    }
    double n[3] = {c->normal[0], c->normal[1], c->normal[2]};
    double len = sqrt(dot3d(n, n));
    double r[3] = {p[0] - c->point[0], p[1] - c->point[1] - d->rise * t, p[2] - c->point[2]};
    return dot3d(r, n) / len;
}

typedef struct drop_report {
    double deepest;     /* thicknesses: the deepest a free particle was into the thickness */
    double off_surface; /* m: the farthest a held particle was from the thickness */
    uint32_t held;      /* held particles at the last frame */
    double speed;       /* m/s: the fastest free particle at the last frame */
    double height;      /* m: the free particles' mean distance from the surface, last frame */
} drop_report;

/* Runs `frames` frames and checks after each: no free particle deeper than DEEPEST
   thicknesses, held particles within [−below, +above] m of the thickness, pinned ones at
   their exact start. */
static drop_report run_drop(cvk_context* ctx, const drop_run* d, uint32_t frames,
                            double above, const char* what)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &d->scene, &sim, &err), err);
    uint64_t n = cvk_sim_particle_count(sim);
    const cvk_build* b = &sim->build;
    float* x0 = harness_read_all(sim);
    float* x = malloc(3 * n * sizeof(float));
    float* v = malloc(3 * n * sizeof(float));
    float* held = malloc(4 * n * sizeof(float));
    drop_report rep = {0};
    uint32_t failures = 0;
    for (uint32_t f = 1; f <= frames; f++) {
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_sim_read_state(sim, x, v, n, &err), err);
        REQUIRE_OK(cvk_implicit_read_held(sim, held, &err), err);
        double t = (double)f * d->scene.substeps * d->scene.dt;
        rep = (drop_report){.deepest = rep.deepest, .off_surface = rep.off_surface};
        for (uint32_t ip = 0; ip < b->particle_count; ip++) {
            uint32_t p = b->user_of[ip];
            const float* xp = &x[3 * p];
            if (ip >= b->free_count) {
                if (memcmp(xp, &x0[3 * p], 3 * sizeof(float)) != 0 && failures++ < 3)
                    CHECK(false, "%s frame %u: pinned particle %u moved to (%g %g %g)", what, f,
                          p, xp[0], xp[1], xp[2]);
                continue;
            }
            double dist = surface_distance(d, xp, t);
            double depth = (THICKNESS - dist) / THICKNESS;
            rep.deepest = fmax(rep.deepest, depth);
            rep.height += dist / b->free_count;
            rep.speed = fmax(rep.speed, sqrt((double)v[3 * p] * v[3 * p] +
                                             (double)v[3 * p + 1] * v[3 * p + 1] +
                                             (double)v[3 * p + 2] * v[3 * p + 2]));
            if (!(depth <= DEEPEST) && failures++ < 3)
                CHECK(false, "%s frame %u: free particle %u is %g m from the surface, %g "
                      "thicknesses into it", what, f, p, dist, depth);
            if (held[4 * p + 3] > 0.0f) {
                rep.held++;
                double off = dist - THICKNESS;
                rep.off_surface = fmax(rep.off_surface, fabs(off));
                if (!(off >= -ON_SURFACE && off <= above) && failures++ < 3)
                    CHECK(false, "%s frame %u: held particle %u is %g m off the thickness",
                          what, f, p, off);
            }
        }
    }
    CHECK(failures == 0, "%s: %u failures in all", what, failures);
    CHECK(rep.held > 0, "%s: no particle is held at the end: the checks of held ones are void",
          what);
    printf("%s: deepest %.3g thicknesses, held particles within %.3g m of the thickness, %u "
           "held at the end, fastest %.3g m/s, mean distance %.4g m\n", what, rep.deepest,
           rep.off_surface, rep.held, rep.speed, rep.height);
    free(x0);
    free(x);
    free(v);
    free(held);
    cvk_sim_destroy(sim);
    return rep;
}

static void drop_on_plane(cvk_context* ctx, cvk_linear_solver linear)
{
    char what[96];
    drop_run d;
    make_drop(&d, linear, 0.1f, true);
    set_plane(&d, (const float[3]){0, 0, 0}, (const float[3]){0, 1, 0});
    snprintf(what, sizeof what, "%s on a level plane", cvk_linear_solver_name(linear));
    drop_report rep = run_drop(ctx, &d, 90, ON_SURFACE, what);
    CHECK(rep.speed < 0.05, "%s: still moving at %g m/s after 1.5 s", what, rep.speed);
    /* Tilted by about 17 degrees: the normal is along no axis. */
    make_drop(&d, linear, 0.2f, true);
    set_plane(&d, (const float[3]){0, 0, 0}, (const float[3]){0.3f, 1, 0.1f});
    snprintf(what, sizeof what, "%s on a tilted plane", cvk_linear_solver_name(linear));
    rep = run_drop(ctx, &d, 60, ON_SURFACE, what);
    CHECK(rep.speed < 0.05, "%s: still moving at %g m/s after 1 s", what, rep.speed);
}

static void drop_on_sphere(cvk_context* ctx)
{
    drop_run d;
    make_drop(&d, CVK_LINEAR_CG, 0.3f, false);
    d.collider = cvk_default_collider_desc();
    d.collider.type = CVK_COLLIDER_SPHERE;
    d.collider.radius = 0.15f;
    /* A held particle moves along the tangent plane of its substep's start, which leaves the
       sphere by (h |v_t|)² / 2R: 1e-4 m allows 1.4 m/s along it. */
    run_drop(ctx, &d, 60, 1e-4, "cg on a sphere");
}

static void drop_on_box(cvk_context* ctx)
{
    drop_run d;
    make_drop(&d, CVK_LINEAR_CG, 0.3f, false);
    d.collider = cvk_default_collider_desc();
    d.collider.type = CVK_COLLIDER_BOX;
    d.collider.center[1] = 0.1f;
    d.collider.half_extents[0] = d.collider.half_extents[1] = d.collider.half_extents[2] = 0.1f;
    /* on the top face exactly; round its edges as over a sphere */
    run_drop(ctx, &d, 60, 1e-4, "cg on a box");
}

/* A plane rising at 0.2 m/s under a cloth lying on it. */
static void lifted_by_plane(cvk_context* ctx)
{
    drop_run d;
    make_drop(&d, CVK_LINEAR_CG, THICKNESS, false);
    set_plane(&d, (const float[3]){0, 0, 0}, (const float[3]){0, 1, 0});
    d.rise = 0.2;
    d.keys[0] = (cvk_keyframe){.time = 0.0f, .rotation = {1, 0, 0, 0}};
    d.keys[1] = (cvk_keyframe){.time = 1.0f, .translation = {0, 0.2f, 0}, .rotation = {1, 0, 0, 0}};
    d.collider.motion.keyframes = d.keys;
    d.collider.motion.keyframe_count = 2;
    drop_report rep = run_drop(ctx, &d, 45, ON_SURFACE, "cg on a rising plane");
    /* Lying on it, the cloth rose with it (0.15 m in 0.75 s). */
    CHECK(rep.height < 2 * THICKNESS && rep.held == 100,
          "rising plane: the cloth is %g m above it on average, %u particles held", rep.height,
          rep.held);
}

/* A cloth lying on a 30° incline, every particle held from the start: with static friction
   above tan 30° it does not move at all; with μ = μs = 0.2 it slides down with the
   acceleration g (sin θ − μ cos θ) exactly — each substep the surface pushes with m g cos θ h
   and friction takes μ times that off the tangential velocity — so after N substeps it has
   gone a h² N (N + 1) / 2. */
static double slide(cvk_context* ctx, float mu, float mu_s, uint32_t frames)
{
    const double theta = PI / 6.0;
    const float n[3] = {(float)sin(theta), (float)cos(theta), 0.0f};
    const float down[3] = {(float)cos(theta), (float)-sin(theta), 0.0f}, across[3] = {0, 0, 1};
    drop_run d;
    make_drop(&d, CVK_LINEAR_CG, 0.0f, false);
    set_plane(&d, (const float[3]){0, 0, 0}, n);
    d.collider.friction = mu;
    d.collider.static_friction = mu_s;
    d.scene.damping = 0.0f;
    for (int c = 0; c < 3; c++) {
        d.cloth.u_axis[c] = down[c];
        d.cloth.v_axis[c] = across[c];
        d.cloth.origin[c] = THICKNESS * n[c] - 0.25f * down[c] - 0.25f * across[c];
    }
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &d.scene, &sim, &err), err);
    uint64_t count = cvk_sim_particle_count(sim);
    float* x0 = harness_read_all(sim);
    REQUIRE_OK(cvk_sim_step(sim, frames, &err), err);
    float* x = harness_read_all(sim);
    double moved = 0.0;
    for (uint64_t p = 0; p < count; p++)
        for (int c = 0; c < 3; c++)
            moved += (x[3 * p + c] - x0[3 * p + c]) * down[c] / (double)count;
    free(x0);
    free(x);
    cvk_sim_destroy(sim);
    return moved;
}

static void friction_on_incline(cvk_context* ctx)
{
    const uint32_t frames = 30, substeps = 4;
    const double h = 0.004, g = 9.81, theta = PI / 6.0;
    double held = slide(ctx, 0.7f, 0.8f, frames);
    CHECK(fabs(held) < 1e-6, "μs 0.8 on 30°: the cloth moved %g m down the slope", held);
    double a = g * (sin(theta) - 0.2 * cos(theta));
    double steps = frames * substeps, want = a * h * h * steps * (steps + 1) / 2;
    double slid = slide(ctx, 0.2f, 0.2f, frames);
    CHECK(fabs(slid - want) < 0.01 * want,
          "μ 0.2 on 30°: the cloth slid %g m, g (sin θ − μ cos θ) gives %g m", slid, want);
    printf("incline 30°: %.3g m held at μs 0.8; %.5g m slid at μ 0.2 (%.5g m predicted)\n", held,
           slid, want);
}

/* The filter is made afresh every substep from the state, so a snapshot taken while the cloth
   lies on a rising plane carries all there is: stepping on from it gives the same bits. */
static void snapshot_on_plane(cvk_context* ctx)
{
    drop_run d;
    make_drop(&d, CVK_LINEAR_CG, 0.05f, true);
    set_plane(&d, (const float[3]){0, 0, 0}, (const float[3]){0.2f, 1, 0});
    d.keys[0] = (cvk_keyframe){.time = 0.0f, .rotation = {1, 0, 0, 0}};
    d.keys[1] = (cvk_keyframe){.time = 1.0f, .translation = {0, 0.2f, 0}, .rotation = {1, 0, 0, 0}};
    d.collider.motion.keyframes = d.keys;
    d.collider.motion.keyframe_count = 2;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &d.scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 20, &err), err);
    uint64_t size = cvk_sim_snapshot_size(sim), n = cvk_sim_particle_count(sim);
    void* snap = malloc(size);
    REQUIRE_OK(cvk_sim_save_snapshot(sim, snap, size, &err), err);
    float* held = malloc(4 * n * sizeof(float));
    REQUIRE_OK(cvk_implicit_read_held(sim, held, &err), err);
    uint32_t count = 0;
    for (uint64_t p = 0; p < n; p++)
        count += held[4 * p + 3] != 0.0f;
    CHECK(count > 0, "snapshot: no particle is held when it is taken: the check is void");
    REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
    float* first = harness_read_all(sim);
    REQUIRE_OK(cvk_sim_load_snapshot(sim, snap, size, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
    float* again = harness_read_all(sim);
    CHECK(memcmp(first, again, 3 * n * sizeof(float)) == 0,
          "snapshot with %u particles held: stepping on from it differs by %g m", count,
          harness_max_diff(first, again, 3 * n));
    free(snap);
    free(held);
    free(first);
    free(again);
    cvk_sim_destroy(sim);
}

/* Two cloths dropped onto a third pinned at its corners, 2 cm apart (the contact radius about
   2.5 cm): the most intersecting pairs at the end of any of `frames` frames, and the free
   particles that ended a frame farther from their bound's centre than the bound. With
   `switch_at` > 0 the drop starts with pd's rbgs and switches to implicit after that frame. */
static uint64_t drop_on_cloth(cvk_context* ctx, cvk_linear_solver linear, bool self,
                              uint32_t frames, uint32_t switch_at, uint32_t* past)
{
    static const uint32_t corners[4][2] = {{0, 0}, {11, 0}, {0, 11}, {11, 11}};
    cvk_cloth_desc cloths[3];
    for (int i = 0; i < 3; i++) {
        cloths[i] = cvk_default_cloth_desc();
        cloths[i].grid[0] = cloths[i].grid[1] = 12;
        cloths[i].size[0] = cloths[i].size[1] = 0.4f;
        cloths[i].origin[0] = -0.2f + 0.011f * (float)i;
        cloths[i].origin[1] = 0.4f + 0.02f * (float)i;
        cloths[i].origin[2] = -0.2f - 0.007f * (float)i;
    }
    cloths[0].pins = corners;
    cloths[0].pin_count = 4;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = 3;
    scene.dt = 1.0f / 120.0f;
    scene.substeps = 1;
    cvk_solver_desc implicit = scene.solver;
    implicit.method = CVK_METHOD_IMPLICIT;
    implicit.linear = linear;
    if (switch_at == 0)
        scene.solver = implicit;
    scene.collision.self = self;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    uint32_t n = sim->build.particle_count, free_count = sim->build.free_count;
    float* x = malloc(16u * n);
    float* seen = malloc(16u * n);
    uint64_t most = 0;
    *past = 0;
    for (uint32_t f = 1; f <= frames; f++) {
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        if (f == switch_at)
            REQUIRE_OK(cvk_sim_set_solver(sim, &implicit, &err), err);
        uint64_t pairs = 0;
        REQUIRE_OK(cvk_sim_count_intersections(sim, &pairs, &err), err);
        most = pairs > most ? pairs : most;
        if (!self)
            continue;
        cvk_gpu_frame state;
        REQUIRE_OK(cvk_buffer_download(ctx, &sim->device.submitter, sim->device.transfer_cmd,
                                       &sim->positions, x, 16u * n, &err), err);
        REQUIRE_OK(cvk_buffer_download(ctx, &sim->device.submitter, sim->device.transfer_cmd,
                                       &sim->collide->searched, seen, 16u * n, &err), err);
        REQUIRE_OK(cvk_buffer_download(ctx, &sim->device.submitter, sim->device.transfer_cmd,
                                       &sim->collide->frame, &state, sizeof state, &err), err);
        const float shift[3] = {state.shift_x, state.shift_y, state.shift_z};
        for (uint32_t p = 0; p < free_count; p++) {
            double d2 = 0.0;
            for (int k = 0; k < 3; k++) {
                double d = (double)x[4 * p + k] - seen[4 * p + k] - shift[k];
                d2 += d * d;
            }
            /* float rounding of x0 + u brought back to the ball */
            *past += sqrt(d2) > seen[4 * p + 3] * (1.0 + 1e-5) + 1e-6 ? 1u : 0u;
        }
    }
    free(x);
    free(seen);
    cvk_sim_destroy(sim);
    return most;
}

static void self_contact(cvk_context* ctx, cvk_linear_solver linear)
{
    const char* name = linear == CVK_LINEAR_CG ? "cg" : "jacobi";
    uint32_t past = 0, unused;
    uint64_t with = drop_on_cloth(ctx, linear, true, 60, 0, &past);
    uint64_t without = drop_on_cloth(ctx, linear, false, 60, 0, &unused);
    printf("%s, two cloths dropped on a pinned one, 60 frames: at most %llu intersecting pairs "
           "with self-contact, %llu without; %u particle-frames ended past their bounds\n", name,
           (unsigned long long)with, (unsigned long long)without, past);
    CHECK(with == 0, "%s: %llu intersecting pairs with self-contact", name,
          (unsigned long long)with);
    CHECK(without > 0, "%s: no intersecting pair without self-contact either: the drop tests "
          "nothing", name);
    CHECK(past == 0, "%s: %u particle-frames ended past their bounds", name, past);
    /* Switched from pd in the middle of the drop: the bounds and pairs carry over. */
    uint64_t switched = drop_on_cloth(ctx, linear, true, 40, 15, &past);
    printf("%s, the same drop switched from rbgs after 15 frames: at most %llu intersecting "
           "pairs, %u particle-frames past their bounds\n", name, (unsigned long long)switched,
           past);
    CHECK(switched == 0 && past == 0, "%s, switched from rbgs: %llu intersecting pairs, %u "
          "particle-frames past their bounds", name, (unsigned long long)switched, past);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    self_contact(ctx, CVK_LINEAR_CG);
    self_contact(ctx, CVK_LINEAR_JACOBI);
    reference_with_plane(ctx, CVK_LINEAR_CG);
    reference_with_plane(ctx, CVK_LINEAR_JACOBI);
    drop_on_plane(ctx, CVK_LINEAR_CG);
    drop_on_plane(ctx, CVK_LINEAR_JACOBI);
    drop_on_sphere(ctx);
    drop_on_box(ctx);
    lifted_by_plane(ctx);
    snapshot_on_plane(ctx);
    friction_on_incline(ctx);
    return harness_finish(ctx);
}
