/* At rest, a damped cloth is at its true static equilibrium: a chain pinned at both ends and a
   cloth pinned at two corners settle to the exact discrete equilibrium of their springs and
   gravity, computed on the host to convergence in double precision (Newton's method on the
   static energy, lib/solvers/newton.c), within float rounding of the positions:
   - projective dynamics with every linear solver (rbgs at omega 1 and 1.7, jacobi, chebyshev,
     gs-cpu) and every iteration count from 1 x 1 to 8 x 8 for the cloth, 1 x 1 and 4 x 4 for
     the chain (the rest memory, lib/solvers/solve_pd.h);
   - the implicit and explicit methods, whose fixed points are force balance already;
   - a damped free fall is not slowed by the memory.
   Without the rest memory a truncated projective-dynamics solve rests up to centimetres off. */
#include "topology/build.h"
#include "harness.h"
#include "solvers/reference.h"


typedef struct rest_scene {
    const char* name;
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    uint32_t pins[10][2];
    uint32_t pin_count;
    uint32_t frames;  /* of 50 substeps: enough for the slowest solver to come to rest */
    uint32_t frames_many_sweeps; /* the same with 16 sweeps a substep */
    uint32_t implicit_frames, explicit_frames; /* the same for those methods */
    bool every_count; /* every iteration count, or only 1 x 1 and 4 x 4 */
    double tolerance; /* float rounding of its resting positions, m (see make_chain, make_cloth) */
} rest_scene;

/* A 17-particle chain 1.2 times as long as the 0.8 m between its pins. Its swinging modes are
   soft (a substep's implicit solve takes only s = (omega h)^2 ~ 1e-4 of the way to the
   equilibrium, and damping 2 % of the velocity), and a float state rests off the exact
   equilibrium: after 80,000 substeps 1.2e-7 to 1.7e-6 m with 16 sweeps a substep (at rest
   after 30,000), up to 4e-6 m with one sweep (9e-6 m on an NVIDIA H200; not at rest, see
   below); gs-cpu, in double, 2.6e-8 m (the float rounding of the positions read).
   Before the spring term was written as a difference (shaders/solvers/pd_common.glsl spring_rhs:
   a few ulp of k L of force in every spring, which the soft modes cannot tell from stretch)
   1.9e-6 to 1.4e-5 m, 2.7e-5 m on the H200. One sweep a substep does not come to rest at all
   but sticks and slips (README "At rest, at the equilibrium"): the figure at the frame below
   is a phase of that cycle. Without the rest memory: 3.0e-3 to
   5.4e-2 m. */
static void make_chain(rest_scene* r)
{
    r->name = "chain";
    r->cloth = cvk_default_cloth_desc();
    r->cloth.grid[0] = 17;
    r->cloth.grid[1] = 1;
    r->cloth.size[0] = 0.8f;
    r->cloth.origin[0] = -0.4f;
    r->cloth.origin[1] = 1.0f;
    r->cloth.origin[2] = 0.0f;
    r->cloth.rest_scale = 1.2f;
    r->cloth.mass = 0.05f;
    r->cloth.stiffness.structural = 1e5f;
    r->pins[0][0] = 0;
    r->pins[0][1] = 0;
    r->pins[1][0] = 16;
    r->pins[1][1] = 0;
    r->pin_count = 2;
    r->frames = 1600;
    r->frames_many_sweeps = 600;
    r->implicit_frames = 60;
    r->explicit_frames = 1200;
    r->every_count = false; /* the cloth runs them all; a chain of 8 x 8 sweeps costs 10 s */
    r->tolerance = 2e-5;
}

/* A 10 x 10 cloth hanging from its top edge, stretched by its weight: no soft mode, so it rests
   within 3e-8 to 9e-8 m of the equilibrium after 3,000 substeps with every solver (below an
   ulp, 1.2e-7 m, of its coordinates). Without the rest memory: 4.2e-6 to 1.1e-2 m. */
static void make_cloth(rest_scene* r)
{
    r->name = "cloth";
    r->cloth = cvk_default_cloth_desc();
    r->cloth.grid[0] = 10;
    r->cloth.grid[1] = 10;
    r->cloth.size[0] = 0.5f;
    r->cloth.size[1] = 0.5f;
    r->cloth.origin[0] = -0.25f;
    r->cloth.origin[1] = 1.0f;
    r->cloth.origin[2] = 0.0f;
    r->cloth.v_axis[1] = -1.0f;
    r->cloth.v_axis[2] = 0.0f;
    r->cloth.mass = 0.1f;
    r->cloth.stiffness.structural = 1e5f;
    r->cloth.stiffness.shear = 1e4f;
    r->cloth.stiffness.bend = 1e2f;
    r->pin_count = 10;
    for (uint32_t i = 0; i < 10; i++) {
        r->pins[i][0] = i;
        r->pins[i][1] = 0;
    }
    r->frames = r->frames_many_sweeps = 60;
    r->implicit_frames = 30;
    r->explicit_frames = 600;
    r->every_count = true;
    r->tolerance = 2e-7;
}

static void finish_scene(rest_scene* r)
{
    r->cloth.pins = (const uint32_t(*)[2])r->pins;
    r->cloth.pin_count = r->pin_count;
    r->scene = cvk_default_scene_desc();
    r->scene.cloths = &r->cloth;
    r->scene.cloth_count = 1;
    r->scene.dt = 0.002f;
    r->scene.substeps = 50;
    r->scene.damping = 0.02f;
}

/* The static equilibrium of `scene` near `start` (user order): proximal Newton steps on the
   static energy E(x) − Σ m g·x, each the substep energy of lib/solvers/newton.c with a step H = 1 s and
   prediction x_k + H² g (whose mass term then adds exactly −m g), until a step moves no
   coordinate by more than 1e-13 m. Returns user-order doubles. */
static double* host_equilibrium(const cvk_scene_desc* scene, const float* start)
{
    cvk_error err;
    cvk_build b;
    REQUIRE_OK(cvk_build_create(scene, &b, &err), err);
    size_t n = b.particle_count;
    double* x = malloc(3 * n * sizeof(double));
    double* y = malloc(3 * n * sizeof(double));
    double* before = malloc(3 * n * sizeof(double));
    double* out = malloc(3 * n * sizeof(double));
    for (size_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++)
            x[3 * p + c] = start[3 * (size_t)b.user_of[p] + c];
    const double H = 1.0;
    cvk_ref_params params = {.inv_h2 = 1.0 / (H * H)};
    double moved = INFINITY;
    cvk_ref_newton_report report = {0};
    int rounds = 0;
    for (; rounds < 200 && moved > 1e-13; rounds++) {
        memcpy(before, x, 3 * n * sizeof(double));
        memcpy(y, x, 3 * n * sizeof(double));
        for (size_t i = 0; i < 3 * (size_t)b.free_count; i++)
            y[i] += scene->gravity[i % 3] * H * H;
        CHECK(cvk_ref_solve_newton(&b, &params, y, 1e-15, 100, 0, x, &report), "out of memory");
        moved = 0.0;
        for (size_t i = 0; i < 3 * n; i++)
            moved = fmax(moved, fabs(x[i] - before[i]));
    }
    CHECK(moved <= 1e-13, "the host equilibrium still moves %g m after %d rounds", moved, rounds);
    for (size_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++)
            out[3 * (size_t)b.user_of[p] + c] = x[3 * p + c];
    free(x);
    free(y);
    free(before);
    cvk_build_destroy(&b);
    return out;
}

/* Positions (user order) after `frames` frames of `scene` from its built state. */
static float* settle(cvk_context* ctx, const cvk_scene_desc* scene, uint32_t frames)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, frames, &err), err);
    float* xyz = harness_read_all(sim);
    cvk_sim_destroy(sim);
    return xyz;
}

static double distance(const float* x, const double* eq, uint64_t coordinates)
{
    double worst = 0.0;
    for (uint64_t i = 0; i < coordinates; i++) {
        double d = fabs((double)x[i] - eq[i]);
        if (d > worst || isnan(d))
            worst = d;
    }
    return worst;
}

typedef struct pd_setting {
    cvk_linear_solver linear;
    float omega;
} pd_setting;

static void pd_rests_at_equilibrium(cvk_context* ctx, rest_scene* r)
{
    /* rbgs at omega 1.7 with one sweep per substep diverges in the first frame (a single SOR
       sweep overshoots), with or without the rest memory: left out. */
    static const pd_setting settings[] = {
        {CVK_LINEAR_RBGS, 1.0f},   {CVK_LINEAR_RBGS, 1.7f},      {CVK_LINEAR_JACOBI, 1.0f},
        {CVK_LINEAR_CHEBYSHEV, 0.9f}, {CVK_LINEAR_GS_CPU, 1.0f},
    };
    static const uint32_t counts[][2] = {{1, 1}, {1, 4}, {4, 4}, {8, 8}};
    uint64_t n = (uint64_t)r->cloth.grid[0] * r->cloth.grid[1];
    cvk_scene_desc scene = r->scene;
    scene.solver.linear = CVK_LINEAR_GS_CPU;
    float* start = settle(ctx, &scene, r->frames);
    double* eq = host_equilibrium(&scene, start);
    free(start);
    for (size_t s = 0; s < sizeof settings / sizeof settings[0]; s++) {
        for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++) {
            uint32_t sweeps = counts[c][0] * counts[c][1];
            bool one_sor_sweep = settings[s].omega > 1.0f && sweeps == 1;
            bool counted = r->every_count || (counts[c][0] == counts[c][1] && sweeps <= 16);
            if (one_sor_sweep || !counted)
                continue;
            scene = r->scene;
            scene.solver.linear = settings[s].linear;
            scene.solver.omega = settings[s].omega;
            scene.solver.outer_iterations = counts[c][0];
            scene.solver.inner_iterations = counts[c][1];
            float* x = settle(ctx, &scene, sweeps >= 16 ? r->frames_many_sweeps : r->frames);
            double d = distance(x, eq, 3 * n);
            CHECK(d < r->tolerance,
                  "%s, %s omega %g, %ux%u: at rest %.3g m from the equilibrium", r->name,
                  cvk_linear_solver_name(settings[s].linear), settings[s].omega, counts[c][0],
                  counts[c][1], d);
            printf("%s, %-9s omega %.1f, %ux%u: %.3g m from the equilibrium\n", r->name,
                   cvk_linear_solver_name(settings[s].linear), settings[s].omega, counts[c][0],
                   counts[c][1], d);
            free(x);
        }
    }
    free(eq);
}

/* The implicit and explicit methods rest where the forces balance. Explicit Euler needs soft
   springs and a short step: the springs at 1 % of the stiffness, h = 0.1 ms, and 0.2 % damping
   (so the chain falls at up to 0.5 m/s, not 0.05); the soft springs make its float resting
   state 100 times as sensitive, so it is held to the chain's bound (measured: chain 4.1e-6 m,
   cloth 9.7e-7 m). */
static void other_method_rests_at_equilibrium(cvk_context* ctx, const rest_scene* given,
                                              cvk_method method)
{
    rest_scene r = *given;
    r.cloth.pins = (const uint32_t(*)[2])r.pins;
    r.scene.cloths = &r.cloth;
    uint64_t n = (uint64_t)r.cloth.grid[0] * r.cloth.grid[1];
    cvk_scene_desc* scene = &r.scene;
    scene->solver.method = method;
    scene->solver.kd = 0.5f;
    if (method == CVK_METHOD_IMPLICIT) {
        scene->solver.linear = CVK_LINEAR_CG;
        scene->solver.tolerance = 1e-6f;
    } else {
        r.cloth.stiffness.structural *= 0.01f;
        r.cloth.stiffness.shear *= 0.01f;
        r.cloth.stiffness.bend *= 0.01f;
        scene->dt = 1e-4f;
        scene->damping = 0.002f;
        r.tolerance = 2e-5;
    }
    float* x = settle(ctx, scene,
                      method == CVK_METHOD_IMPLICIT ? r.implicit_frames : r.explicit_frames);
    double* eq = host_equilibrium(scene, x);
    double d = distance(x, eq, 3 * n);
    CHECK(d < r.tolerance, "%s, %s: at rest %.3g m from the equilibrium", r.name,
          cvk_method_name(method), d);
    printf("%s, %s: %.3g m from the equilibrium\n", r.name, cvk_method_name(method), d);
    free(x);
    free(eq);
}

/* The memory does not slow a free fall: an unpinned damped cloth follows Verlet's damped
   recursion u_{k+1} = (1 - damping) u_k + h^2 g from rest (u_0 = -h^2 g / 2) to the per-step
   rounding bound, as without the memory (a free-falling cloth needs no correction, so the memory
   stays 0; one that learnt the motion instead would run ahead of it). */
static void free_fall_not_slowed(cvk_context* ctx)
{
    cvk_cloth_desc cloth = harness_falling_cloth();
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.damping = 0.02f;
    const uint32_t frames = 50;
    float* start = settle(ctx, &scene, 0);
    float* end = settle(ctx, &scene, frames);
    uint64_t n = (uint64_t)cloth.grid[0] * cloth.grid[1];
    uint32_t steps = frames * scene.substeps;
    double h2 = (double)scene.dt * scene.dt, drop[3] = {0, 0, 0};
    for (int c = 0; c < 3; c++) {
        double u = -0.5 * h2 * scene.gravity[c];
        for (uint32_t k = 0; k < steps; k++) {
            u = (1.0 - scene.damping) * u + h2 * scene.gravity[c];
            drop[c] += u;
        }
    }
    double worst = 0.0, largest = 0.0;
    for (uint64_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++) {
            double expected = start[3 * p + c] + drop[c];
            double d = fabs(end[3 * p + c] - expected);
            if (d > worst || isnan(d))
                worst = d;
            largest = fmax(largest, fabs(expected));
        }
    double bound = steps * (double)(nextafterf((float)largest, INFINITY) - (float)largest);
    CHECK(worst < bound, "free fall with damping: %g m off the damped Verlet recursion (bound %g m)",
          worst, bound);
    printf("free fall with damping %.2f: %.3g m from the damped recursion after %u steps (drop "
           "%.3f m, rounding bound %.3g m)\n", scene.damping, worst, steps, -drop[1], bound);
    free(start);
    free(end);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    free_fall_not_slowed(ctx);
    rest_scene chain, cloth;
    make_chain(&chain);
    finish_scene(&chain);
    make_cloth(&cloth);
    finish_scene(&cloth);
    pd_rests_at_equilibrium(ctx, &chain);
    pd_rests_at_equilibrium(ctx, &cloth);
    cvk_method others[] = {CVK_METHOD_IMPLICIT, CVK_METHOD_EXPLICIT};
    for (int m = 0; m < 2; m++) {
        other_method_rests_at_equilibrium(ctx, &chain, others[m]);
        other_method_rests_at_equilibrium(ctx, &cloth, others[m]);
    }
    return harness_finish(ctx);
}
