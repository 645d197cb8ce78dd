/* Projective-dynamics solves that stop when converged (solver.tolerance, solver.max_iterations):
   - bad values get one exact message each, with the implicit method's rule;
   - without a tolerance the plan records no check (no residual, convergence or indirect
     dispatch in its text); a tolerance
     never reached (1e-30) runs every sweep and gives the same bits as no tolerance, for rbgs,
     jacobi and chebyshev: the checking sweeps compute what the plain ones do;
   - a tolerance stops the solve early on the device, the same state and sweep count for every
     dispatch shape, and the sweeps used follow the cloth's motion (fewer at rest than while it
     swings, and below the cap; with tethers, falling to under half as it comes to rest);
   - one substep with tolerance ε lands within a bound derived from ε of the converged solve. */
#include <stdint.h>

#include "harness.h"

/* ---- bad values ------------------------------------------------------------------------- */

static void check_messages(void)
{
    harness_expect_scene_message("{\"solver\": {\"tolerance\": -1}, \"cloths\": [{}]}",
                                 "t.json: solver.tolerance: must be greater than 0 and less "
                                 "than 1, got -1");
    harness_expect_scene_message("{\"solver\": {\"tolerance\": 0}, \"cloths\": [{}]}",
                                 "t.json: solver.tolerance: must be greater than 0 and less "
                                 "than 1, got 0");
    harness_expect_scene_message("{\"solver\": {\"tolerance\": 1}, \"cloths\": [{}]}",
                                 "t.json: solver.tolerance: must be greater than 0 and less "
                                 "than 1, got 1");
    harness_expect_scene_message("{\"solver\": {\"tolerance\": \"nan\"}, \"cloths\": [{}]}",
                                 "t.json: solver.tolerance: must be a finite number, got nan");
    harness_expect_scene_message("{\"solver\": {\"max_iterations\": 0}, \"cloths\": [{}]}",
                                 "t.json: solver.max_iterations: must be at least 1, got 0");
    harness_expect_scene_message("{\"solver\": {\"max_iterations\": 10004}, \"cloths\": [{}]}",
                                 "t.json: solver.max_iterations: must be at most 10000, got "
                                 "10004");
    harness_expect_scene_message("{\"solver\": {\"max_iterations\": 10}, \"cloths\": [{}]}",
                                 "t.json: solver.max_iterations: pd runs whole outer iterations "
                                 "of inner_iterations (4) sweeps: must be a multiple of 4, got "
                                 "10");
    harness_expect_scene_message("{\"solver\": {\"linear\": \"gs-cpu\", \"tolerance\": 0.1}, "
                                 "\"cloths\": [{}]}",
                                 "t.json: solver.tolerance: gs-cpu (the host reference) runs "
                                 "every sweep; remove tolerance or use rbgs, jacobi or "
                                 "chebyshev");
    harness_expect_scene_message("{\"solver\": {\"method\": \"explicit\", \"tolerance\": 0.1}, "
                                 "\"cloths\": [{}]}",
                                 "t.json: solver.tolerance: the explicit method solves no linear "
                                 "system; remove it");
    /* The same rule for a description made in C (0 there is the method's default). */
    cvk_scene_desc d = cvk_default_scene_desc();
    cvk_cloth_desc c = cvk_default_cloth_desc();
    d.cloths = &c;
    d.cloth_count = 1;
    d.solver.tolerance = NAN;
    cvk_error err = {0};
    CHECK(cvk_scene_desc_validate(&d, &err) == CVK_ERROR_INVALID_ARGUMENT &&
              strcmp(err.message, "solver.tolerance: must be a finite number, got nan") == 0,
          "NaN tolerance: \"%s\"", err.message);
    d.solver.tolerance = 0.0f;
    d.solver.max_iterations = 8;
    cvk_solver_desc resolved = cvk_solver_desc_resolve(&d.solver);
    CHECK(resolved.outer_iterations == 2 && resolved.max_iterations == 8,
          "max_iterations 8 of 4 inner sweeps: %u outer, at most %u", resolved.outer_iterations,
          resolved.max_iterations);
}

/* ---- scenes and runs -------------------------------------------------------------------- */

#define SIDE 20

/* A SIDE × SIDE cloth pinned at its two top corners, 0.5 m wide, lightly damped: it falls,
   swings and comes to rest. */
static cvk_scene_desc hanging(cvk_cloth_desc* c, float tolerance, uint32_t max_iterations)
{
    static const uint32_t pins[2][2] = {{0, 0}, {SIDE - 1, 0}};
    *c = cvk_default_cloth_desc();
    c->grid[0] = c->grid[1] = SIDE;
    c->size[0] = c->size[1] = 0.5f;
    c->pins = pins;
    c->pin_count = 2;
    cvk_scene_desc d = cvk_default_scene_desc();
    d.cloths = c;
    d.cloth_count = 1;
    d.damping = 0.01f;
    d.solver.tolerance = tolerance;
    d.solver.max_iterations = max_iterations;
    return d;
}

typedef struct run_result {
    float* xyz;
    uint64_t count;
    uint64_t sweeps_total;
    uint32_t sweeps_last_frame;
    uint32_t dispatches_per_substep;
} run_result;

static run_result run(cvk_context* ctx, const cvk_scene_desc* scene, uint32_t frames,
                      uint32_t workgroup_size, uint32_t max_workgroups)
{
    cvk_error err;
    cvk_sim* sim;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = scene;
    desc.workgroup_size = workgroup_size;
    desc.max_workgroups = max_workgroups;
    desc.timing = -1;
    REQUIRE_OK(cvk_sim_create(ctx, &desc, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, frames, &err), err);
    run_result r = {.xyz = harness_read_all(sim), .count = cvk_sim_particle_count(sim)};
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    r.sweeps_total = st.solver_iterations_total;
    r.sweeps_last_frame = st.solver_iterations;
    r.dispatches_per_substep = st.dispatches_per_substep;
    cvk_sim_destroy(sim);
    return r;
}

static bool same_bits(const run_result* a, const run_result* b)
{
    return a->count == b->count && memcmp(a->xyz, b->xyz, 3 * a->count * sizeof(float)) == 0;
}

/* ---- no tolerance: nothing changes ------------------------------------------------------ */

static void check_unreached_tolerance(cvk_context* ctx)
{
    static const cvk_linear_solver solvers[] = {CVK_LINEAR_RBGS, CVK_LINEAR_JACOBI,
                                                CVK_LINEAR_CHEBYSHEV};
    for (size_t k = 0; k < sizeof solvers / sizeof solvers[0]; k++) {
        cvk_cloth_desc c;
        cvk_scene_desc plain = hanging(&c, 0.0f, 0);
        plain.solver.linear = solvers[k];
        plain.damping = 0.0f; /* a checked solve has no rest memory, the plain one with damping */
        /* Stretched by a tenth at the start, so 16 sweeps a substep leave every particle's
           residual above its rounding floor (a solve at the floor stops whatever the
           tolerance: a cloth at rest or falling freely could stop there). */
        c.rest_scale = 0.9f;
        cvk_scene_desc never = plain;
        never.solver.tolerance = 1e-30f;
        run_result a = run(ctx, &plain, 3, 0, 0);
        run_result b = run(ctx, &never, 3, 0, 0);
        const char* name = cvk_linear_solver_name(solvers[k]);
        CHECK(same_bits(&a, &b), "%s: a tolerance never reached changes the state by %.3g m",
              name, harness_max_diff(a.xyz, b.xyz, 3 * a.count));
        uint32_t per_frame = 16u * plain.substeps;
        CHECK(a.sweeps_last_frame == per_frame && b.sweeps_last_frame == per_frame,
              "%s: sweeps in the last frame %u without a tolerance, %u with one never reached; "
              "want %u", name, a.sweeps_last_frame, b.sweeps_last_frame, per_frame);
        CHECK(b.dispatches_per_substep > a.dispatches_per_substep,
              "%s: the checked plan records %u operations per substep, the plain %u", name,
              b.dispatches_per_substep, a.dispatches_per_substep);
        free(a.xyz);
        free(b.xyz);
    }
}

/* Without a tolerance the plan records no check: its description names none of the passes. */
static void check_plain_plan(cvk_context* ctx)
{
    cvk_cloth_desc c;
    cvk_scene_desc d = hanging(&c, 0.0f, 0);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &d, &sim, &err), err);
    char text[16384];
    cvk_sim_describe_plan(sim, text, sizeof text);
    CHECK(!strstr(text, "residual") && !strstr(text, "convergence") && !strstr(text, "indirect"),
          "the plan without a tolerance records a check:\n%s", text);
    cvk_sim_destroy(sim);
    d.solver.tolerance = 0.1f;
    REQUIRE_OK(harness_sim_create(ctx, &d, &sim, &err), err);
    cvk_sim_describe_plan(sim, text, sizeof text);
    CHECK(strstr(text, "residual: stop or go on") && strstr(text, "indirect"),
          "the plan with a tolerance records no check:\n%s", text);
    cvk_sim_destroy(sim);
}

/* ---- a tolerance ------------------------------------------------------------------------ */

/* The same state and the same sweep count for every dispatch shape: the residual's sum is
   taken over fixed partial sums, whatever the workgroups. */
static void check_shapes(cvk_context* ctx)
{
    static const uint32_t shapes[][2] = {{0, 0}, {8, 1}, {32, 3}, {256, 0}, {64, 7}};
    cvk_cloth_desc c;
    cvk_scene_desc d = hanging(&c, 0.05f, 64);
    run_result first = run(ctx, &d, 4, 0, 0);
    CHECK(first.sweeps_total < 64u * d.substeps * 4u, "the tolerance stopped nothing: %llu "
          "sweeps in 4 frames", (unsigned long long)first.sweeps_total);
    for (size_t i = 1; i < sizeof shapes / sizeof shapes[0]; i++) {
        run_result r = run(ctx, &d, 4, shapes[i][0], shapes[i][1]);
        CHECK(same_bits(&first, &r) && r.sweeps_total == first.sweeps_total,
              "workgroups of %u, at most %u: %.3g m from the default shape, %llu sweeps "
              "against %llu", shapes[i][0], shapes[i][1],
              harness_max_diff(first.xyz, r.xyz, 3 * first.count),
              (unsigned long long)r.sweeps_total, (unsigned long long)first.sweeps_total);
        free(r.xyz);
    }
    free(first.xyz);
}

/* Sweeps per frame as the cloth falls, swings and comes to rest (tolerance 0.3, at most 400
   sweeps a substep), without tethers and with them. Each substep starts from the inertial
   prediction, which at rest is off by h² g everywhere, so without tethers the work at rest
   settles at a level rather than vanishing (README, "Solves that stop when converged"): below
   the swinging peak and below the cap. With tethers (which hold the hanging cloth's weight)
   the work falls as it comes to rest: to under half the first ten frames'. */
#define FRAMES_TO_REST 120
static void check_sweeps_follow_motion(cvk_context* ctx, uint32_t tethers)
{
    cvk_cloth_desc c;
    cvk_scene_desc d = hanging(&c, 0.3f, 400);
    c.tethers = tethers;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &d, &sim, &err), err);
    uint32_t sweeps[FRAMES_TO_REST];
    for (uint32_t f = 0; f < FRAMES_TO_REST; f++) {
        cvk_sim_stats st;
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
        sweeps[f] = st.solver_iterations;
    }
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    cvk_sim_destroy(sim);
    uint32_t cap = 400u * d.substeps, swinging_peak = 0, rest_peak = 0;
    double rest_mean = 0.0, early_mean = 0.0;
    for (uint32_t f = 0; f < 30; f++)
        swinging_peak = sweeps[f] > swinging_peak ? sweeps[f] : swinging_peak;
    for (uint32_t f = 0; f < 10; f++)
        early_mean += sweeps[f] / 10.0;
    for (uint32_t f = FRAMES_TO_REST - 20; f < FRAMES_TO_REST; f++) {
        rest_peak = sweeps[f] > rest_peak ? sweeps[f] : rest_peak;
        rest_mean += sweeps[f] / 20.0;
    }
    printf("tethers %u: sweeps per frame (at most %u): first %u, first ten %.0f on average, "
           "swinging peak %u, at rest %.0f on average (peak %u); kinetic energy at the end "
           "%.3g J\n", tethers, cap, sweeps[0], early_mean, swinging_peak, rest_mean, rest_peak,
           st.kinetic_energy);
    CHECK(rest_peak < cap, "tethers %u: at rest the solve never stops early: %u sweeps in a "
          "frame", tethers, rest_peak);
    CHECK(rest_mean < 0.75 * swinging_peak, "tethers %u: at rest %.0f sweeps a frame on "
          "average; while it swings at most %u", tethers, rest_mean, swinging_peak);
    if (tethers)
        CHECK(rest_mean < 0.5 * early_mean, "with tethers: at rest %.0f sweeps a frame on "
              "average, in the first ten frames %.0f", rest_mean, early_mean);
    else
        CHECK(sweeps[0] < swinging_peak, "the first frame (free fall) takes %u sweeps, the "
              "swinging peak %u", sweeps[0], swinging_peak);
}

/* A tether that holds a particle takes the outward part of its residual (pd_common.glsl,
   free_of_tethers): otherwise the springs' pull on the particles the tethers hold never fades
   and the check never passes. peer-hanging.json's settings (ω = 1.7, tethers) on 40 × 40
   particles, tolerance 0.3, at most 128 sweeps: by frame 80 the solve runs fewer than three
   quarters of the cap (448 of 1,024 sweeps in that frame; without the projection the relative
   residual stalls near 0.4 and 959 run). While the cloth still swings the last residual hovers
   about the tolerance (0.29 to 0.53 at frames 20, 40 and 60, with and without an unrelaxed last
   sweep, so a frame there stops or not by chance). */
static void check_tethered_stops(cvk_context* ctx)
{
    static const uint32_t pins[2][2] = {{0, 0}, {39, 0}};
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = c.grid[1] = 40;
    c.pins = pins;
    c.pin_count = 2;
    c.tethers = 1.0f;
    cvk_scene_desc d = cvk_default_scene_desc();
    d.cloths = &c;
    d.cloth_count = 1;
    d.dt = 1.0f / 480.0f;
    d.solver.omega = 1.7f;
    d.solver.tolerance = 0.3f;
    d.solver.max_iterations = 128;
    run_result r = run(ctx, &d, 80, 0, 0);
    printf("tethered 40 x 40 at omega 1.7: %u sweeps in frame 80, at most %u\n",
           r.sweeps_last_frame, 128u * d.substeps);
    CHECK(r.sweeps_last_frame < 96u * d.substeps, "tethered: %u of the %u sweeps of frame 80 "
          "ran", r.sweeps_last_frame, 128u * d.substeps);
    free(r.xyz);
}

/* One substep from rest of a soft cloth (k = 1000 N/m, so the bound below is tight enough to
   fail): with tolerance ε the displacement u differs from the converged one u* by at most
   C ε |u* − y|, y the first iterate (the prediction, ½ h² g from rest). Derivation: the
   measure is |d| / |d_0| with d = D⁻¹(b − A u) = D⁻¹A (u* − u); D^-1/2 A D^-1/2 has its
   eigenvalues in [min_p (m_p/h²)/D_p, 2], so in the D-norm |u − u*| ≤ |d| / λ_min and
   |d_0| ≤ 2 |u* − y|; back to the 2-norm costs √(D_max / D_min):
   C = 2 max_p (D_p h² / m_p) √(D_max / D_min). (The local step makes the system nonlinear;
   with these small motions it is nearly linear, and the bound has room.) */
static void check_bound(cvk_context* ctx)
{
    static const uint32_t pins[2][2] = {{0, 0}, {9, 0}};
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = c.grid[1] = 10;
    c.size[0] = c.size[1] = 0.3f;
    c.mass = 0.1f;
    c.stiffness.structural = 1000.0f;
    c.rest_scale = 0.99f;
    c.pins = pins;
    c.pin_count = 2;
    cvk_scene_desc d = cvk_default_scene_desc();
    d.cloths = &c;
    d.cloth_count = 1;
    d.substeps = 1;
    d.solver.max_iterations = 2000; /* converged: 500 outer iterations */
    run_result full = run(ctx, &d, 1, 0, 0);
    cvk_sim* probe;
    cvk_error err;
    REQUIRE_OK(harness_sim_create(ctx, &d, &probe, &err), err);
    float* x0 = harness_read_all(probe);
    cvk_sim_destroy(probe);
    double h = d.dt, m = c.mass / 100.0, k = c.stiffness.structural;
    double d_min = m / (h * h) + 2.0 * k, d_max = m / (h * h) + 4.0 * k;
    double bound_factor = 2.0 * (d_max * h * h / m) * sqrt(d_max / d_min);
    /* |u* − y|: y moves free particles by ½ h² g; pinned ones do not move in either. */
    double e0 = 0.0;
    for (uint64_t p = 0; p < full.count; p++)
        for (int a = 0; a < 3; a++) {
            double u = (double)full.xyz[3 * p + a] - x0[3 * p + a];
            double y = u == 0.0 ? 0.0 : 0.5 * h * h * d.gravity[a];
            e0 += (u - y) * (u - y);
        }
    e0 = sqrt(e0);
    static const float tolerances[] = {1e-2f, 1e-3f, 1e-4f};
    for (size_t i = 0; i < sizeof tolerances / sizeof tolerances[0]; i++) {
        cvk_scene_desc t = d;
        t.solver.tolerance = tolerances[i];
        run_result r = run(ctx, &t, 1, 0, 0);
        double e = 0.0;
        for (uint64_t j = 0; j < 3 * r.count; j++)
            e += ((double)r.xyz[j] - full.xyz[j]) * ((double)r.xyz[j] - full.xyz[j]);
        e = sqrt(e);
        double bound = bound_factor * tolerances[i] * e0;
        printf("tolerance %g: %u sweeps, |u - u*| = %.3g m, bound %.3g m (|u* - y| = %.3g m)\n",
               tolerances[i], r.sweeps_last_frame, e, bound, e0);
        CHECK(e <= bound, "tolerance %g: |u - u*| = %.3g m, over the bound %.3g m",
              tolerances[i], e, bound);
        CHECK(r.sweeps_last_frame < 2000, "tolerance %g: all %u sweeps ran", tolerances[i],
              r.sweeps_last_frame);
        free(r.xyz);
    }
    free(x0);
    free(full.xyz);
}

/* Contact stays resolved when the solve stops early: the iterate it stops at has had its outer
   iteration's contact pass, and that iterate (not the half-swept one after it) is what moves the
   cloth. A cloth dropped on a sphere ends every frame outside its thickness: the contact pass
   puts particles on it, so no deeper than the rounding of float positions (1e-6 m). (Moving
   the half-swept iterate instead leaves them up to 0.05 mm inside.) */
static void check_contact(cvk_context* ctx)
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = c.grid[1] = 16;
    c.size[0] = c.size[1] = 0.6f;
    c.origin[0] = c.origin[2] = -0.3f;
    c.origin[1] = 0.25f;
    c.stiffness.structural = 1e4f;
    cvk_collider_desc ball = cvk_default_collider_desc();
    ball.type = CVK_COLLIDER_SPHERE;
    ball.radius = 0.15f;
    cvk_scene_desc d = cvk_default_scene_desc();
    d.cloths = &c;
    d.cloth_count = 1;
    d.colliders = &ball;
    d.collider_count = 1;
    d.solver.tolerance = 0.3f;
    d.solver.max_iterations = 64;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &d, &sim, &err), err);
    double worst = 0.0, thickness = 0.5 * c.size[0] / (c.grid[0] - 1); /* the default */
    uint64_t sweeps = 0, frames = 40;
    for (uint32_t f = 0; f < frames; f++) {
        cvk_sim_stats st;
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
        float* x = harness_read_all(sim);
        for (uint64_t p = 0; p < st.particles; p++) {
            double r = sqrt((double)x[3 * p] * x[3 * p] + (double)x[3 * p + 1] * x[3 * p + 1] +
                            (double)x[3 * p + 2] * x[3 * p + 2]);
            worst = fmax(worst, ball.radius + thickness - r);
        }
        free(x);
        sweeps = st.solver_iterations_total;
    }
    cvk_sim_destroy(sim);
    printf("cloth on a sphere, tolerance 0.3: deepest %.3g m inside its thickness, %.1f sweeps "
           "a substep\n",
           worst, (double)sweeps / (frames * d.substeps));
    CHECK(worst <= 1e-6, "a particle ends a frame %.3g m inside the sphere's thickness", worst);
    CHECK(sweeps < 64u * d.substeps * frames, "the tolerance stopped nothing on the sphere");
}

int main(void)
{
    check_messages();
    cvk_context* ctx = harness_context();
    check_plain_plan(ctx);
    check_unreached_tolerance(ctx);
    check_shapes(ctx);
    check_sweeps_follow_motion(ctx, 0);
    check_sweeps_follow_motion(ctx, 1);
    check_tethered_stops(ctx);
    check_bound(ctx);
    check_contact(ctx);
    return harness_finish(ctx);
}
