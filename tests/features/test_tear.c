/* Tearing on the device (lib/features/tear.h): the same springs tear in every run, dispatch shape and
   device solver; each substep's decisions are those of a host check on the positions the pass
   saw; a torn spring pulls no more (its free end falls exactly as a free body); the mesh and
   the export lose exactly the triangles along torn springs (a cell whose split diagonal is torn
   while its other diagonal holds split along that one), the same triangles; a cloth below its threshold tears
   nothing and a scene without tearing records no pass; gs-cpu tears on the host what rbgs
   tears on the device, and a switch between them carries the torn state; under the implicit
   and explicit families a torn rope's end moves as a lone particle and the same springs tear
   for every dispatch shape; a snapshot resumes the torn state bit for bit; writing the state
   or switching solver keeps torn springs torn. */
#include <stdint.h>

#include "core/gpu.h"
#include "harness.h"
#include "recorded.h"
#include "render/mesh.h"
#include "regenerate.h"
#include "sim/sim.h"

#define W 12
#define H 10
#define MAX_STRETCH 0.2f

static const cvk_keyframe drag[2] = {
    {.time = 0.0f, .rotation = {1, 0, 0, 0}},
    {.time = 0.5f, .translation = {0.0f, -0.35f, 0.25f}, .rotation = {1, 0, 0, 0}},
};
static const uint32_t drag_pins[2][2] = {{5, H - 1}, {6, H - 1}};

typedef struct setup {
    cvk_scene_desc scene;
    cvk_cloth_desc cloth;
    cvk_attachment_desc attachment;
    uint32_t pins[W][2];
} setup;

/* A W × H sheet hanging from its whole top row; two particles of its bottom row are dragged
   down and out until it tears. */
static void make_scene(setup* s, bool dragged, float max_stretch)
{
    for (uint32_t i = 0; i < W; i++) {
        s->pins[i][0] = i;
        s->pins[i][1] = 0;
    }
    s->cloth = cvk_default_cloth_desc();
    s->cloth.grid[0] = W;
    s->cloth.grid[1] = H;
    s->cloth.size[0] = 0.44f;
    s->cloth.size[1] = 0.36f;
    memcpy(s->cloth.origin, (float[3]){-0.22f, 1.0f, 0.0f}, sizeof s->cloth.origin);
    memcpy(s->cloth.v_axis, (float[3]){0.0f, -1.0f, 0.0f}, sizeof s->cloth.v_axis);
    s->cloth.stiffness.structural = 1e4f;
    s->cloth.stiffness.shear = 1e3f;
    s->cloth.stiffness.bend = 10.0f;
    s->cloth.pins = (const uint32_t(*)[2])s->pins;
    s->cloth.pin_count = W;
    s->cloth.tearing.max_stretch = max_stretch;
    s->attachment = cvk_default_attachment_desc();
    s->attachment.pins = drag_pins;
    s->attachment.pin_count = 2;
    s->attachment.motion = (cvk_motion){.keyframes = drag, .keyframe_count = 2};
    s->scene = cvk_default_scene_desc();
    s->scene.substeps = 4;
    s->scene.cloths = &s->cloth;
    s->scene.cloth_count = 1;
    if (dragged) {
        s->scene.attachments = &s->attachment;
        s->scene.attachment_count = 1;
    }
}

/* The same sheet, softer and thrown down at 15 m/s from its top row: it tears there within
   the first frame, with no attachment (which gs-cpu refuses). */
static void make_thrown(setup* s)
{
    make_scene(s, false, MAX_STRETCH);
    s->cloth.velocity[1] = -15.0f;
    s->cloth.stiffness.structural = 1e3f;
    s->cloth.stiffness.shear = 1e2f;
}

static cvk_sim* make_sim(cvk_context* ctx, const cvk_scene_desc* scene, uint32_t workgroup_size,
                         uint32_t max_workgroups)
{
    cvk_error err;
    cvk_sim* sim = NULL;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = scene;
    desc.workgroup_size = workgroup_size;
    desc.max_workgroups = max_workgroups;
    desc.timing = -1;
    REQUIRE_OK(cvk_sim_create(ctx, &desc, &sim, &err), err);
    return sim;
}

/* The spring flags (uint per spring of the build). */
static uint32_t* read_flags(cvk_sim* sim)
{
    cvk_error err;
    uint32_t* alive = malloc((size_t)sim->build.spring_count * sizeof *alive + 4);
    if (!alive)
        exit(1);
    REQUIRE_OK(cvk_tear_read_flags(sim, alive, &err), err);
    return alive;
}

static uint32_t count_torn(const cvk_sim* sim, const uint32_t* alive)
{
    uint32_t torn = 0;
    for (uint32_t s = 0; s < sim->build.spring_count; s++)
        torn += alive[s] == 0;
    return torn;
}

#define FRAMES 20

/* ---- the same springs everywhere -------------------------------------------------------- */

typedef struct shape {
    uint32_t workgroup_size, max_workgroups; /* 0: the library's choice */
} shape;

static const shape shapes[] = {{0, 0}, {8, 1}, {8, 3}, {32, 0}, {256, 3}, {0, 0}};
#define SHAPE_COUNT (sizeof shapes / sizeof shapes[0])

static void same_springs_everywhere(cvk_context* ctx)
{
    setup s;
    make_scene(&s, true, MAX_STRETCH);
    const cvk_linear_solver solvers[] = {CVK_LINEAR_RBGS, CVK_LINEAR_JACOBI, CVK_LINEAR_CHEBYSHEV};
    for (size_t k = 0; k < sizeof solvers / sizeof solvers[0]; k++) {
        s.scene.solver.linear = solvers[k];
        const char* name = cvk_linear_solver_name(solvers[k]);
        uint32_t* first = NULL;
        float* first_x = NULL;
        uint32_t torn = 0, springs = 0, same = 0;
        for (size_t i = 0; i < SHAPE_COUNT; i++) {
            cvk_error err;
            cvk_sim* sim = make_sim(ctx, &s.scene, shapes[i].workgroup_size, shapes[i].max_workgroups);
            REQUIRE_OK(cvk_sim_step(sim, FRAMES, &err), err);
            uint32_t* alive = read_flags(sim);
            float* x = harness_read_all(sim);
            uint64_t n = cvk_sim_particle_count(sim);
            springs = sim->build.spring_count;
            if (!first) {
                first = alive;
                first_x = x;
                torn = count_torn(sim, alive);
            } else {
                bool flags = memcmp(alive, first, springs * sizeof *alive) == 0;
                bool positions = memcmp(x, first_x, 3 * n * sizeof *x) == 0;
                CHECK(flags, "%s, workgroup size %u, max workgroups %u: %u springs torn, the first "
                      "shape tore %u (or others)", name, shapes[i].workgroup_size,
                      shapes[i].max_workgroups, count_torn(sim, alive), torn);
                CHECK(positions, "%s, workgroup size %u, max workgroups %u: positions differ by up "
                      "to %g m", name, shapes[i].workgroup_size, shapes[i].max_workgroups,
                      harness_max_diff(x, first_x, 3 * n));
                same += flags && positions;
                free(alive);
                free(x);
            }
            cvk_sim_destroy(sim);
        }
        /* A test of nothing torn, or of everything, would prove little. */
        CHECK(torn > 0 && torn < springs / 2, "%s: %u of %u springs torn in %d frames", name, torn,
              springs, FRAMES);
        printf("%s: %u of %u springs torn after %d frames, the same springs and positions for %u "
               "of %zu other shapes and runs\n", name, torn, springs, FRAMES, same, SHAPE_COUNT - 1);
        free(first);
        free(first_x);
    }
}

/* ---- each substep's decisions, checked on the host ---------------------------------------- */

/* With one substep per frame, the positions read after a frame are those the tear pass saw:
   a spring must be dead exactly when it was dead before or is now longer than its breaking
   length. Springs within 1e-5 of the threshold may round either way and are not judged. */
static void decisions_match_the_host(cvk_context* ctx)
{
    setup s;
    make_scene(&s, true, MAX_STRETCH);
    s.scene.substeps = 1;
    cvk_sim* sim = make_sim(ctx, &s.scene, 0, 0);
    const cvk_build* b = &sim->build;
    uint32_t* before = read_flags(sim);
    uint32_t judged = 0, wrong = 0, newly = 0, ambiguous = 0;
    for (uint32_t f = 0; f < 4 * FRAMES; f++) {
        cvk_error err;
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        uint32_t* after = read_flags(sim);
        REQUIRE_OK(cvk_sim_read_internal(sim, &err), err);
        for (uint32_t i = 0; i < b->spring_count; i++) {
            const cvk_spring* sp = &b->springs[i];
            const float* xa = &sim->scratch[3 * (size_t)sp->a];
            const float* xb = &sim->scratch[3 * (size_t)sp->b];
            double d = sqrt(pow((double)xa[0] - xb[0], 2) + pow((double)xa[1] - xb[1], 2) +
                            pow((double)xa[2] - xb[2], 2));
            double stretch = d / sp->rest - 1.0;
            if (before[i] && fabs(stretch - MAX_STRETCH) < 1e-5) {
                ambiguous++;
                continue;
            }
            bool dead = !before[i] || stretch > MAX_STRETCH;
            wrong += dead != (after[i] == 0);
            newly += before[i] && !after[i];
            judged++;
        }
        free(before);
        before = after;
    }
    CHECK(wrong == 0, "%u of %u tearing decisions differ from the host's", wrong, judged);
    CHECK(newly > 0, "no spring tore in %d frames", 4 * FRAMES);
    printf("one substep a frame: %u decisions as the host makes them (%u springs torn on the way, "
           "%u too close to the threshold to judge)\n", judged - wrong, newly, ambiguous);
    free(before);
    cvk_sim_destroy(sim);
}

/* ---- a torn spring pulls no more ---------------------------------------------------------- */

/* A two-particle rope, the top pinned, the bottom thrown down at 10 m/s: its spring (which
   would hold a 3 m/s throw to 9.5 % of stretch) passes 10 % within a few substeps and tears. From then on the free particle is a body in free
   fall, which Verlet integrates exactly: x(t) = x1 + v1 t + g t² / 2. Without tearing the
   spring would hold it within centimetres of the pin. */
static double rope_deviation(cvk_context* ctx, float max_stretch, cvk_linear_solver linear,
                             uint64_t* torn)
{
    static const uint32_t pin[1][2] = {{0, 0}};
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = 1;
    c.grid[1] = 2;
    c.size[1] = 0.1f;
    memcpy(c.origin, (float[3]){0.0f, 1.0f, 0.0f}, sizeof c.origin);
    memcpy(c.v_axis, (float[3]){0.0f, -1.0f, 0.0f}, sizeof c.v_axis);
    c.mass = 0.02f;
    c.stiffness.structural = 1e3f;
    c.pins = pin;
    c.pin_count = 1;
    c.velocity[1] = -10.0f;
    c.tearing.max_stretch = max_stretch;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &c;
    scene.cloth_count = 1;
    scene.solver.linear = linear;
    cvk_sim* sim = make_sim(ctx, &scene, 0, 0);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, 2, &err), err);
    float x1[6], v1[6], x[6];
    REQUIRE_OK(cvk_sim_read_state(sim, x1, v1, 2, &err), err);
    const uint32_t frames = 20;
    REQUIRE_OK(cvk_sim_step(sim, frames, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(sim, x, 2, &err), err);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    *torn = st.torn_springs;
    double t = (double)frames * scene.substeps * scene.dt, worst = 0.0;
    for (int k = 0; k < 3; k++) {
        double expect = x1[3 + k] + v1[3 + k] * t + 0.5 * scene.gravity[k] * t * t;
        worst = fmax(worst, fabs(x[3 + k] - expect));
    }
    cvk_sim_destroy(sim);
    return worst;
}

static void torn_spring_pulls_no_more(cvk_context* ctx)
{
    const cvk_linear_solver solvers[] = {CVK_LINEAR_RBGS, CVK_LINEAR_JACOBI, CVK_LINEAR_CHEBYSHEV,
                                         CVK_LINEAR_GS_CPU};
    for (size_t k = 0; k < sizeof solvers / sizeof solvers[0]; k++) {
        const char* name = cvk_linear_solver_name(solvers[k]);
        uint64_t torn = 0, kept = 0;
        double free_fall = rope_deviation(ctx, 0.1f, solvers[k], &torn);
        double held = rope_deviation(ctx, 0.0f, solvers[k], &kept);
        CHECK(torn == 1, "%s: the rope's one spring: %llu torn", name, (unsigned long long)torn);
        CHECK(kept == 0, "%s: without tearing %llu springs tore", name, (unsigned long long)kept);
        /* Float positions near 1 m and 0.32 s of float displacements: micrometres. */
        CHECK(free_fall < 1e-4, "%s: the torn rope's end is %g m from free fall", name, free_fall);
        CHECK(held > 1e-2, "%s: the intact rope's end is only %g m from free fall: the check "
              "cannot tell", name, held);
        printf("%s, torn rope: the free end %.3g m from exact free fall after 0.32 s (%.3g m with "
               "the spring intact)\n", name, free_fall, held);
    }
}

/* ---- the implicit and explicit families ---------------------------------------------------------- */

/* The rope again, solved by `solver` for two frames (its spring tears in the first), then by
   `after` (a switch when they differ): from then on its free end moves exactly as a lone
   particle (a 1 x 1 cloth, no springs) solved by `after` from the same state. Returns the
   largest distance between the two after 20 more frames. */
static double rope_against_lone(cvk_context* ctx, cvk_solver_desc solver, cvk_solver_desc after,
                                float max_stretch, uint64_t* torn)
{
    static const uint32_t pin[1][2] = {{0, 0}};
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = 1;
    c.grid[1] = 2;
    c.size[1] = 0.1f;
    memcpy(c.origin, (float[3]){0.0f, 1.0f, 0.0f}, sizeof c.origin);
    memcpy(c.v_axis, (float[3]){0.0f, -1.0f, 0.0f}, sizeof c.v_axis);
    c.mass = 0.02f;
    c.stiffness.structural = 1e3f;
    c.pins = pin;
    c.pin_count = 1;
    c.velocity[1] = -10.0f;
    c.tearing.max_stretch = max_stretch;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &c;
    scene.cloth_count = 1;
    scene.solver = solver;
    cvk_sim* rope = make_sim(ctx, &scene, 0, 0);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(rope, 2, &err), err);
    REQUIRE_OK(cvk_sim_set_solver(rope, &after, &err), err);
    float x1[6], v1[6], x[6], lone_x[3];
    REQUIRE_OK(cvk_sim_read_state(rope, x1, v1, 2, &err), err);

    scene.solver = after;
    cvk_cloth_desc one = c;
    one.grid[1] = 1;
    one.mass = 0.01f; /* the rope's free particle's */
    one.pins = NULL;
    one.pin_count = 0;
    one.tearing.max_stretch = 0.0f;
    scene.cloths = &one;
    cvk_sim* lone = make_sim(ctx, &scene, 0, 0);
    REQUIRE_OK(cvk_sim_write_state(lone, &x1[3], &v1[3], 1, &err), err);

    const uint32_t frames = 20;
    REQUIRE_OK(cvk_sim_step(rope, frames, &err), err);
    REQUIRE_OK(cvk_sim_step(lone, frames, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(rope, x, 2, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(lone, lone_x, 1, &err), err);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(rope, &st, &err), err);
    *torn = st.torn_springs;
    double worst = 0.0;
    for (int k = 0; k < 3; k++)
        worst = fmax(worst, fabs((double)x[3 + k] - lone_x[k]));
    cvk_sim_destroy(rope);
    cvk_sim_destroy(lone);
    return worst;
}

/* The implicit (CG) or explicit (Verlet: stable with the rope's spring intact, too) solver, with
   spring damping, which a torn spring must lose with its stiffness. */
static cvk_solver_desc other_family(cvk_method method)
{
    cvk_solver_desc solver = cvk_default_scene_desc().solver;
    solver.method = method;
    if (method == CVK_METHOD_IMPLICIT)
        solver.linear = CVK_LINEAR_CG;
    else
        solver.integrator = CVK_INTEGRATOR_VERLET;
    solver.kd = 0.5f;
    return solver;
}

static void other_families_tear(cvk_context* ctx)
{
    cvk_solver_desc implicit = other_family(CVK_METHOD_IMPLICIT);
    cvk_solver_desc explicit = other_family(CVK_METHOD_EXPLICIT);
    const cvk_solver_desc solvers[] = {implicit, explicit};
    for (size_t k = 0; k < 2; k++) {
        const char* name = cvk_method_name(solvers[k].method);
        uint64_t torn = 0, kept = 0;
        double apart = rope_against_lone(ctx, solvers[k], solvers[k], 0.1f, &torn);
        double held = rope_against_lone(ctx, solvers[k], solvers[k], 0.0f, &kept);
        CHECK(torn == 1 && kept == 0, "%s: %llu springs torn with tearing, %llu without", name,
              (unsigned long long)torn, (unsigned long long)kept);
        CHECK(apart < 1e-5, "%s: the torn rope's end is %g m from a lone particle's path", name,
              apart);
        CHECK(held > 1e-2, "%s: the intact rope's end is only %g m from a lone particle's path: "
              "the check cannot tell", name, held);
        printf("%s, torn rope: the free end %.3g m from a lone particle's path after 0.32 s "
               "(%.3g m with the spring intact)\n", name, apart, held);
    }

    /* Torn under one family and switched to another, the rope's end is still free: the new
       family takes the torn state. */
    cvk_solver_desc rbgs = cvk_default_scene_desc().solver, gs_cpu = rbgs;
    gs_cpu.linear = CVK_LINEAR_GS_CPU;
    const cvk_solver_desc pairs[][2] = {{rbgs, implicit}, {implicit, explicit}, {explicit, rbgs},
                                        {implicit, gs_cpu}};
    for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++) {
        uint64_t torn = 0;
        double apart = rope_against_lone(ctx, pairs[k][0], pairs[k][1], 0.1f, &torn);
        const char* from = pairs[k][0].method == CVK_METHOD_PD
                               ? cvk_linear_solver_name(pairs[k][0].linear)
                               : cvk_method_name(pairs[k][0].method);
        const char* to = pairs[k][1].method == CVK_METHOD_PD
                             ? cvk_linear_solver_name(pairs[k][1].linear)
                             : cvk_method_name(pairs[k][1].method);
        CHECK(torn == 1, "%s -> %s: %llu springs torn", from, to, (unsigned long long)torn);
        /* A device PD state written back from velocities rounds: micrometres at most. */
        CHECK(apart < 1e-5, "%s -> %s: the torn rope's end is %g m from a lone particle's path",
              from, to, apart);
        printf("torn under %s, switched to %s: the free end %.3g m from a lone particle's path\n",
               from, to, apart);
    }

}

/* The thrown sheet of host_tears_as_the_device under the implicit and explicit families: the
   same springs tear for every dispatch shape. */
static void other_families_same_springs(cvk_context* ctx)
{
    const cvk_solver_desc solvers[] = {other_family(CVK_METHOD_IMPLICIT),
                                       other_family(CVK_METHOD_EXPLICIT)};
    const shape family_shapes[] = {{0, 0}, {8, 1}, {32, 3}, {64, 0}, {0, 0}};
    for (size_t k = 0; k < 2; k++) {
        setup s;
        make_thrown(&s);
        s.scene.solver = solvers[k];
        s.scene.solver.kd = 0.0f; /* the light sheet's particles: 0.5 N s/m would be stiff */
        if (solvers[k].method == CVK_METHOD_EXPLICIT) { /* inside Verlet's stable step */
            s.scene.dt = 0.0005f;
            s.scene.substeps = 16;
        }
        const char* name = cvk_method_name(solvers[k].method);
        /* The implicit family's CG sums partial dot products per workgroup: its positions
           depend on the dispatch shape by float rounding (tests/sim/test_determinism.c covers
           projective dynamics only); its tearing decisions must not. */
        double tolerance = solvers[k].method == CVK_METHOD_IMPLICIT ? 1e-6 : 0.0;
        uint32_t* first = NULL;
        float* first_x = NULL;
        uint32_t torn = 0, same = 0;
        size_t count = sizeof family_shapes / sizeof family_shapes[0];
        for (size_t i = 0; i < count; i++) {
            cvk_error err;
            cvk_sim* sim = make_sim(ctx, &s.scene, family_shapes[i].workgroup_size,
                                    family_shapes[i].max_workgroups);
            REQUIRE_OK(cvk_sim_step(sim, 6, &err), err);
            uint32_t* alive = read_flags(sim);
            float* x = harness_read_all(sim);
            uint64_t n = cvk_sim_particle_count(sim);
            size_t springs = sim->build.spring_count;
            if (!first) {
                first = alive;
                first_x = x;
                torn = count_torn(sim, alive);
                CHECK(torn > 0 && torn < springs / 2, "%s: %u of %zu springs torn", name, torn,
                      springs);
            } else {
                bool flags = memcmp(alive, first, springs * sizeof *alive) == 0;
                bool positions = tolerance > 0.0
                                     ? harness_max_diff(x, first_x, 3 * n) <= tolerance
                                     : memcmp(x, first_x, 3 * n * sizeof *x) == 0;
                CHECK(flags && positions, "%s, workgroup size %u, max workgroups %u: %u springs "
                      "torn (first shape %u), positions up to %g m apart", name,
                      family_shapes[i].workgroup_size, family_shapes[i].max_workgroups,
                      count_torn(sim, alive), torn, harness_max_diff(x, first_x, 3 * n));
                same += flags && positions;
                free(alive);
                free(x);
            }
            cvk_sim_destroy(sim);
        }
        printf("%s, thrown sheet: %u springs torn in 6 frames, the same springs and positions (%s) "
               "for %u of %zu other shapes and runs\n", name, torn,
               tolerance > 0.0 ? "within 1e-6 m" : "bit for bit", same, count - 1);
        free(first);
        free(first_x);
    }
}

/* ---- the host reference ----------------------------------------------------------------------- */

/* Switching between gs-cpu and rbgs carries the torn state both ways: a run switched from rbgs
   to gs-cpu after `frames` goes on as the gs-cpu run `host` does, and one switched back as the
   rbgs run `dev` does. */
static void host_switches(cvk_context* ctx, cvk_sim* dev, cvk_sim* host, uint32_t frames)
{
    setup s;
    make_thrown(&s);
    cvk_error err;
    uint64_t n = cvk_sim_particle_count(dev);
    s.scene.solver.linear = CVK_LINEAR_GS_CPU;
    cvk_sim* to_host = make_sim(ctx, &s.scene, 0, 0); /* gs-cpu */
    s.scene.solver.linear = CVK_LINEAR_RBGS;
    cvk_sim* to_dev = make_sim(ctx, &s.scene, 0, 0);
    REQUIRE_OK(cvk_sim_step(to_host, frames, &err), err);
    REQUIRE_OK(cvk_sim_step(to_dev, frames, &err), err);
    cvk_solver_desc rbgs = s.scene.solver, gs_cpu = rbgs;
    gs_cpu.linear = CVK_LINEAR_GS_CPU;
    REQUIRE_OK(cvk_sim_set_solver(to_host, &rbgs, &err), err);  /* gs-cpu -> rbgs */
    REQUIRE_OK(cvk_sim_set_solver(to_dev, &gs_cpu, &err), err); /* rbgs -> gs-cpu */
    cvk_sim* runs[2][2] = {{to_host, dev}, {to_dev, host}}; /* switched, and its peer */
    for (int k = 0; k < 2; k++) {
        cvk_sim* switched = runs[k][0];
        cvk_sim* peer = runs[k][1];
        REQUIRE_OK(cvk_sim_step(switched, 4, &err), err);
        REQUIRE_OK(cvk_sim_step(peer, 4, &err), err);
        uint32_t* a = read_flags(switched);
        uint32_t* b = read_flags(peer);
        float* xa = harness_read_all(switched);
        float* xb = harness_read_all(peer);
        uint32_t differ = 0;
        for (uint32_t i = 0; i < dev->build.spring_count; i++)
            differ += a[i] != b[i];
        double gap = harness_max_diff(xa, xb, 3 * n);
        const char* what = k == 0 ? "gs-cpu -> rbgs" : "rbgs -> gs-cpu";
        CHECK(differ == 0, "%s: %u springs torn on one side only", what, differ);
        CHECK(gap < 1e-4, "%s: positions differ by up to %g m from the run that did not switch",
              what, gap);
        printf("switched %s: the same %u springs torn as the run that did not switch, positions "
               "within %.2g m\n", what, count_torn(switched, a), gap);
        free(a);
        free(b);
        free(xa);
        free(xb);
    }
    cvk_sim_destroy(to_host);
    cvk_sim_destroy(to_dev);
}

/* gs-cpu's snapshots carry its torn state too: resumed, the same bits. */
static void host_snapshot(cvk_context* ctx)
{
    setup s;
    make_thrown(&s);
    s.scene.solver.linear = CVK_LINEAR_GS_CPU;
    cvk_error err;
    cvk_sim* first = make_sim(ctx, &s.scene, 0, 0);
    cvk_sim* second = make_sim(ctx, &s.scene, 0, 0);
    uint64_t n = cvk_sim_particle_count(first);
    REQUIRE_OK(cvk_sim_step(first, 1, &err), err);
    uint32_t* a = read_flags(first);
    uint32_t torn_at_save = count_torn(first, a);
    free(a);
    uint64_t size = cvk_sim_snapshot_size(first);
    void* snap = malloc(size);
    if (!snap)
        exit(1);
    REQUIRE_OK(cvk_sim_save_snapshot(first, snap, size, &err), err);
    REQUIRE_OK(cvk_sim_load_snapshot(second, snap, size, &err), err);
    REQUIRE_OK(cvk_sim_step(first, 4, &err), err);
    REQUIRE_OK(cvk_sim_step(second, 4, &err), err);
    a = read_flags(first);
    uint32_t* b = read_flags(second);
    float* xa = harness_read_all(first);
    float* xb = harness_read_all(second);
    /* The throw tears them all in the first frame; a torn spring the load had mended would
       pull the resumed run's positions away. */
    CHECK(torn_at_save > 0, "gs-cpu: nothing torn at the snapshot");
    CHECK(memcmp(a, b, first->build.spring_count * sizeof *a) == 0 &&
          memcmp(xa, xb, 3 * n * sizeof *xa) == 0,
          "gs-cpu resumed from a snapshot: other torn springs or positions (up to %g m)",
          harness_max_diff(xa, xb, 3 * n));
    printf("gs-cpu snapshot with %u springs torn: resumed to the same %u torn springs and "
           "positions, bit for bit\n", torn_at_save, count_torn(first, a));
    free(a);
    free(b);
    free(xa);
    free(xb);
    free(snap);
    cvk_sim_destroy(first);
    cvk_sim_destroy(second);
}

/* gs-cpu tears on the host (cvk_tear_host) what rbgs tears on the device: a sheet hanging from
   its top row thrown down at 15 m/s tears the same springs, and its particles end where the
   host's do to float rounding. */
static void host_tears_as_the_device(cvk_context* ctx)
{
    setup s;
    make_thrown(&s);
    cvk_sim* dev = make_sim(ctx, &s.scene, 0, 0);
    s.scene.solver.linear = CVK_LINEAR_GS_CPU;
    cvk_sim* host = make_sim(ctx, &s.scene, 0, 0);
    cvk_error err;
    const uint32_t frames = 6;
    REQUIRE_OK(cvk_sim_step(dev, frames, &err), err);
    REQUIRE_OK(cvk_sim_step(host, frames, &err), err);
    uint32_t* a = read_flags(dev);
    uint32_t* b = read_flags(host);
    float* xa = harness_read_all(dev);
    float* xb = harness_read_all(host);
    uint64_t n = cvk_sim_particle_count(dev);
    uint32_t differ = 0;
    for (uint32_t i = 0; i < dev->build.spring_count; i++)
        differ += a[i] != b[i];
    double gap = harness_max_diff(xa, xb, 3 * n);
    CHECK(count_torn(dev, a) > 0, "nothing tore in %u frames", frames);
    CHECK(differ == 0, "%u springs torn on one side only (rbgs %u torn, gs-cpu %u)", differ,
          count_torn(dev, a), count_torn(host, b));
    CHECK(gap < 1e-4, "rbgs and gs-cpu positions differ by up to %g m", gap);
    printf("thrown sheet: rbgs and gs-cpu tear the same %u springs in %u frames, positions "
           "within %.2g m\n", count_torn(dev, a), frames, gap);

    host_switches(ctx, dev, host, frames);
    host_snapshot(ctx);
    free(a);
    free(b);
    free(xa);
    free(xb);
    cvk_sim_destroy(dev);
    cvk_sim_destroy(host);
}

/* ---- triangles ------------------------------------------------------------------------------ */

/* Triangles whose three indices are not all equal. */
static uint32_t live_triangles(const uint32_t* indices, uint64_t count)
{
    uint32_t live = 0;
    for (uint64_t t = 0; t < count; t++)
        live += !(indices[3 * t] == indices[3 * t + 1] && indices[3 * t] == indices[3 * t + 2]);
    return live;
}

/* A triangle as its corners in ascending order, for comparing sets of triangles. */
typedef struct corners {
    uint32_t v[3];
} corners;

static int corners_order(const void* a, const void* b)
{
    const corners *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x->v[k] != y->v[k])
            return x->v[k] < y->v[k] ? -1 : 1;
    return 0;
}

static corners sorted_corners(uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    if (c < lo)
        return (corners){{c, lo, hi}};
    if (c < hi)
        return (corners){{lo, c, hi}};
    return (corners){{lo, hi, c}};
}

/* The live (not collapsed) triangles of an index list into out, sorted; returns their count. */
static uint32_t live_set(const uint32_t* indices, uint64_t count, corners* out)
{
    uint32_t live = 0;
    for (uint64_t t = 0; t < count; t++) {
        const uint32_t* v = &indices[3 * t];
        if (!(v[0] == v[1] && v[0] == v[2]))
            out[live++] = sorted_corners(v[0], v[1], v[2]);
    }
    qsort(out, live, sizeof *out, corners_order);
    return live;
}

/* Whether the structural or shear spring between particles ua and ub (user order) holds;
   false where there is none. */
static bool holds(const cvk_build* b, const uint32_t* alive, uint32_t ua, uint32_t ub)
{
    for (uint32_t s = 0; s < b->spring_count; s++) {
        const cvk_spring* sp = &b->springs[s];
        uint32_t a = b->user_of[sp->a], c = b->user_of[sp->b];
        if (sp->type != CVK_SPRING_BEND && ((a == ua && c == ub) || (a == ub && c == ua)))
            return alive[s] != 0;
    }
    return false;
}

static void triangles_follow(cvk_context* ctx)
{
    setup s;
    make_scene(&s, true, MAX_STRETCH);
    cvk_sim* sim = make_sim(ctx, &s.scene, 0, 0);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, FRAMES, &err), err);
    const cvk_build* b = &sim->build;
    uint32_t* alive = read_flags(sim);
    /* Per cell [i, j] (corners a, b = a + 1, c = a + W, d = c + 1): split along b − c into
       (a, b, c) and (b, d, c), or, while the spring along b − c is torn and the one along
       a − d holds, along a − d into (a, b, d) and (a, d, c); a triangle lives while the
       springs along its edges do. */
    uint32_t predicted = 0;
    corners* want = malloc(2 * W * H * sizeof *want);
    if (!want)
        exit(1);
    for (uint32_t j = 0; j + 1 < H; j++)
        for (uint32_t i = 0; i + 1 < W; i++) {
            uint32_t a = j * W + i, bb = a + 1, c = a + W, d = c + 1;
            bool other = !holds(b, alive, bb, c) && holds(b, alive, a, d);
            uint32_t tri[2][3] = {{a, bb, c}, {bb, d, c}};
            uint32_t flip[2][3] = {{a, bb, d}, {a, d, c}};
            for (int k = 0; k < 2; k++) {
                const uint32_t* v = other ? flip[k] : tri[k];
                if (holds(b, alive, v[0], v[1]) && holds(b, alive, v[1], v[2]) &&
                    holds(b, alive, v[2], v[0]))
                    want[predicted++] = sorted_corners(v[0], v[1], v[2]);
            }
        }
    qsort(want, predicted, sizeof *want, corners_order);
    uint64_t n = cvk_sim_particle_count(sim), count = cvk_sim_triangle_count(sim);
    uint32_t* triangles = malloc(3 * count * sizeof *triangles);
    corners* got = malloc(count * sizeof *got);
    if (!triangles || !got)
        exit(1);
    REQUIRE_OK(cvk_sim_read_mesh(sim, NULL, NULL, triangles, n, count, &err), err);
    uint32_t exported = live_set(triangles, count, got);

    cvk_mesh* mesh;
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    harness_regenerate(ctx, mesh);
    cvk_mesh_buffers info = cvk_mesh_get_buffers(mesh);
    uint32_t* indices = harness_read_buffer(ctx, info.index_buffer, (VkDeviceSize)info.index_count * 4u);
    uint32_t drawn = live_triangles(indices, info.index_count / 3);

    CHECK(predicted < count, "nothing torn: %u of %llu triangles live", predicted,
          (unsigned long long)count);
    CHECK(exported == predicted && memcmp(got, want, predicted * sizeof *got) == 0,
          "cvk_sim_read_mesh keeps %u triangles; the spring flags leave %u%s", exported, predicted,
          exported == predicted ? ", not the same ones" : "");
    CHECK(drawn == predicted, "the device mesh draws %u triangles; the spring flags leave %u", drawn,
          predicted);
    CHECK(memcmp(indices, triangles, (size_t)info.index_count * 4u) == 0,
          "the device mesh and cvk_sim_read_mesh draw different triangles");
    printf("%u springs torn: %u of %llu triangles left, in the export and the device mesh alike\n",
           count_torn(sim, alive), predicted, (unsigned long long)count);
    free(indices);
    free(triangles);
    free(want);
    free(got);
    free(alive);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
}

/* ---- below the threshold, and no tearing at all ------------------------------------------------ */

static void below_threshold(cvk_context* ctx)
{
    setup s;
    make_scene(&s, false, MAX_STRETCH); /* hanging alone: stretched by a few percent */
    cvk_sim* sim = make_sim(ctx, &s.scene, 0, 0);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, 3 * FRAMES, &err), err);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    CHECK(st.torn_springs == 0, "%llu springs torn below the threshold",
          (unsigned long long)st.torn_springs);
    CHECK(st.max_stretch > 1e-4 && st.max_stretch < MAX_STRETCH,
          "the hanging sheet's largest stretch is %g, not between 1e-4 and %g", st.max_stretch,
          MAX_STRETCH);
    uint32_t with_pass = cvk_plan_find_pass(&sim->plan, "tear");
    CHECK(with_pass != UINT32_MAX, "a tearing scene records no \"tear\" pass");
    uint32_t dispatches = st.dispatches_per_substep;
    uint64_t n = cvk_sim_particle_count(sim);
    float* with = harness_read_all(sim);
    cvk_sim_destroy(sim);

    make_scene(&s, false, 0.0f);
    sim = make_sim(ctx, &s.scene, 0, 0);
    REQUIRE_OK(cvk_sim_step(sim, 3 * FRAMES, &err), err);
    float* without = harness_read_all(sim);
    cvk_sim_stats off;
    REQUIRE_OK(cvk_sim_get_stats(sim, &off, &err), err);
    CHECK(cvk_plan_find_pass(&sim->plan, "tear") == UINT32_MAX,
          "a scene without tearing records a \"tear\" pass");
    CHECK(off.dispatches_per_substep + 1 == dispatches,
          "%u dispatches a substep without tearing, %u with it", off.dispatches_per_substep,
          dispatches);
    CHECK(off.torn_springs == 0, "%llu springs torn without tearing",
          (unsigned long long)off.torn_springs);
    /* Below the threshold nothing tears, so the pass changes nothing: the same positions,
       bit for bit. */
    CHECK(cvk_sim_particle_count(sim) == n && memcmp(with, without, 3 * n * sizeof(float)) == 0,
          "positions differ by up to %g m with the tear pass below its threshold",
          cvk_sim_particle_count(sim) == n ? harness_max_diff(with, without, 3 * n) : -1.0);
    free(with);
    free(without);
    printf("below the threshold: nothing torn, largest stretch %.3g; the same state as without "
           "tearing, one dispatch less a substep without it\n", st.max_stretch);
    cvk_sim_destroy(sim);
}

/* ---- snapshots, written states, solver switches ---------------------------------------------- */

static void torn_state_carried(cvk_context* ctx)
{
    setup s;
    make_scene(&s, true, MAX_STRETCH);
    cvk_sim* a = make_sim(ctx, &s.scene, 0, 0);
    cvk_error err;
    uint32_t* at_save = NULL;
    for (int f = 0; f < FRAMES && (!at_save || count_torn(a, at_save) == 0); f++) {
        REQUIRE_OK(cvk_sim_step(a, 1, &err), err); /* on to the frame the first springs break */
        free(at_save);
        at_save = read_flags(a);
    }
    uint32_t torn_at_save = count_torn(a, at_save);
    uint64_t size = cvk_sim_snapshot_size(a);
    void* snap = malloc(size);
    if (!snap)
        exit(1);
    REQUIRE_OK(cvk_sim_save_snapshot(a, snap, size, &err), err);
    REQUIRE_OK(cvk_sim_step(a, FRAMES, &err), err);
    uint32_t* flags_a = read_flags(a);
    float* xa = harness_read_all(a);

    cvk_sim* b = make_sim(ctx, &s.scene, 0, 0);
    REQUIRE_OK(cvk_sim_load_snapshot(b, snap, size, &err), err);
    uint32_t* loaded = read_flags(b);
    REQUIRE_OK(cvk_sim_step(b, FRAMES, &err), err);
    uint32_t* flags_b = read_flags(b);
    float* xb = harness_read_all(b);
    uint64_t n = cvk_sim_particle_count(a);
    size_t springs = a->build.spring_count;
    CHECK(torn_at_save > 0, "nothing torn when the snapshot was taken");
    CHECK(count_torn(a, flags_a) > torn_at_save, "nothing tore after the snapshot (%u torn)",
          torn_at_save);
    CHECK(memcmp(loaded, at_save, springs * 4) == 0, "the loaded flags differ from the saved");
    CHECK(memcmp(flags_a, flags_b, springs * 4) == 0, "resumed: %u springs torn, %u in the run "
          "that went on", count_torn(b, flags_b), count_torn(a, flags_a));
    CHECK(memcmp(xa, xb, 3 * n * sizeof *xa) == 0, "resumed: positions differ by up to %g m",
          harness_max_diff(xa, xb, 3 * n));
    printf("snapshot with %u springs torn: resumed to the same %u torn springs and the same "
           "positions, bit for bit\n", torn_at_save, count_torn(a, flags_a));

    /* A written state keeps the torn springs torn; so does a switch of device solver. */
    float* start = malloc(3 * n * sizeof *start);
    if (!start)
        exit(1);
    for (uint32_t p = 0; p < b->build.particle_count; p++)
        memcpy(&start[3 * (size_t)b->build.user_of[p]], &b->build.position[3 * (size_t)p],
               3 * sizeof(float));
    REQUIRE_OK(cvk_sim_write_state(b, start, NULL, n, &err), err);
    uint32_t* written = read_flags(b);
    CHECK(memcmp(written, flags_b, springs * 4) == 0, "writing the state mended springs");
    cvk_solver_desc jacobi = s.scene.solver;
    jacobi.linear = CVK_LINEAR_JACOBI;
    REQUIRE_OK(cvk_sim_set_solver(b, &jacobi, &err), err);
    REQUIRE_OK(cvk_sim_step(b, 1, &err), err);
    uint32_t* switched = read_flags(b);
    uint32_t mended = 0;
    for (size_t i = 0; i < springs; i++)
        mended += !written[i] && switched[i];
    CHECK(mended == 0, "%u springs mended by a switch to jacobi", mended);

    free(written);
    free(switched);
    free(start);
    free(at_save);
    free(flags_a);
    free(flags_b);
    free(loaded);
    free(xa);
    free(xb);
    free(snap);
    cvk_sim_destroy(a);
    cvk_sim_destroy(b);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    same_springs_everywhere(ctx);
    decisions_match_the_host(ctx);
    torn_spring_pulls_no_more(ctx);
    host_tears_as_the_device(ctx);
    other_families_tear(ctx);
    other_families_same_springs(ctx);
    triangles_follow(ctx);
    below_threshold(ctx);
    torn_state_carried(ctx);
    return harness_finish(ctx);
}
