/* Air on the device (lib/features/aero.h): the per-particle force the device computes equals the host
   reference's (double precision, same model) on a small cloth in a gusty wind at a time inside
   the gusts; known truths of the model — a flat cloth facing a steady wind is pushed along it
   with ½ ρ drag A v², a cloth parallel to it feels only the small skin friction ½ ρ friction A v²,
   the force grows with the square of the relative speed — and a free cloth in the wind is
   carried along it; a frame recorded once and resubmitted equals stepping while the gusts
   change; the same bits for two dispatch shapes; no wind, no wind pass. */
#include <stdint.h>

#include "harness.h"
#include "recorded.h"
#include "sim/sim.h"
#include "solvers/reference.h"

#define W 6
#define H 5

typedef struct setup {
    cvk_scene_desc scene;
    cvk_cloth_desc cloth;
} setup;

/* A W × H cloth, 0.5 × 0.4 m, level at y = 1 (normal ±y), free, without gravity. */
static void make_scene(setup* s, const float wind[3])
{
    s->cloth = cvk_default_cloth_desc();
    s->cloth.grid[0] = W;
    s->cloth.grid[1] = H;
    s->cloth.size[0] = 0.5f;
    s->cloth.size[1] = 0.4f;
    s->cloth.mass = 0.02f;
    s->cloth.stiffness.structural = 1e3f;
    s->cloth.stiffness.shear = 1e2f;
    s->scene = cvk_default_scene_desc();
    memset(s->scene.gravity, 0, sizeof s->scene.gravity);
    s->scene.substeps = 1;
    s->scene.cloths = &s->cloth;
    s->scene.cloth_count = 1;
    s->scene.wind.enabled = true;
    memcpy(s->scene.wind.velocity, wind, sizeof s->scene.wind.velocity);
}

static cvk_sim* create(cvk_context* ctx, const setup* s, uint32_t workgroup_size, uint32_t groups)
{
    cvk_error err;
    cvk_sim* sim = NULL;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = &s->scene;
    desc.workgroup_size = workgroup_size;
    desc.max_workgroups = groups;
    REQUIRE_OK(cvk_sim_create(ctx, &desc, &sim, &err), err);
    return sim;
}

/* The device's force on every particle after one substep from rest (the force at its start). */
static void total_force(cvk_context* ctx, const setup* s, double out[3])
{
    cvk_sim* sim = create(ctx, s, 0, 0);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
    uint64_t n = cvk_sim_particle_count(sim);
    float* f = malloc(3 * n * sizeof(float));
    REQUIRE_OK(cvk_aero_read_forces(sim, f, &err), err);
    out[0] = out[1] = out[2] = 0.0;
    for (uint64_t p = 0; p < n; p++)
        for (int k = 0; k < 3; k++)
            out[k] += f[3 * p + k];
    free(f);
    cvk_sim_destroy(sim);
}

static void known_truths(cvk_context* ctx)
{
    const double area = 0.5 * 0.4, half_rho = 0.5 * 1.2;
    setup s;
    double facing[3], faster[3], parallel[3];
    make_scene(&s, (const float[3]){0.0f, 5.0f, 0.0f});
    total_force(ctx, &s, facing);
    make_scene(&s, (const float[3]){0.0f, 10.0f, 0.0f});
    total_force(ctx, &s, faster);
    make_scene(&s, (const float[3]){5.0f, 0.0f, 0.0f});
    total_force(ctx, &s, parallel);
    double drag = half_rho * 1.0 * area * 25.0, friction = half_rho * 0.02 * area * 25.0;
    CHECK(fabs(facing[1] - drag) < 1e-4 * drag && fabs(facing[0]) < 1e-6 && fabs(facing[2]) < 1e-6,
          "facing a 5 m/s wind: force [%.6g, %.6g, %.6g] N, expected [0, %.6g, 0]", facing[0],
          facing[1], facing[2], drag);
    CHECK(fabs(faster[1] / facing[1] - 4.0) < 1e-4,
          "twice the speed gives %.6g times the force, not 4", faster[1] / facing[1]);
    CHECK(fabs(parallel[0] - friction) < 1e-4 * friction && fabs(parallel[1]) < 1e-6 &&
              fabs(parallel[2]) < 1e-6,
          "parallel to a 5 m/s wind: force [%.6g, %.6g, %.6g] N, expected [%.6g, 0, 0]", parallel[0],
          parallel[1], parallel[2], friction);
    CHECK(parallel[0] < 0.05 * facing[1], "the tangential drag %.4g N is not small against %.4g N",
          parallel[0], facing[1]);
    printf("facing: %.6g N (1/2 rho cd A v^2 = %.6g), x2 speed: x%.6f, parallel: %.6g N\n",
           facing[1], drag, faster[1] / facing[1], parallel[0]);
}

/* A wavy state with velocities, in a gusty wind 7 substeps in: device and host forces agree. */
static void host_reference(cvk_context* ctx)
{
    setup s;
    make_scene(&s, (const float[3]){3.0f, 0.5f, -1.0f});
    s.scene.wind.gusts = (cvk_gusts_desc){.amplitude = 0.4f, .period = 0.7f, .jitter = 20.0f};
    s.cloth.aero = (cvk_aero_desc){.drag = 1.3f, .lift = 0.6f, .friction = 0.05f};
    memcpy(s.scene.gravity, (float[3]){0.0f, -9.81f, 0.0f}, sizeof s.scene.gravity);
    cvk_sim* sim = create(ctx, &s, 0, 0);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(sim, 7, &err), err);
    uint64_t n = cvk_sim_particle_count(sim);
    float* x = harness_read_all(sim);
    float* v = calloc(3 * n, sizeof(float));
    harness_rng rng = {777};
    for (uint64_t i = 0; i < 3 * n; i++) {
        x[i] += (float)harness_uniform(&rng, -0.02, 0.02);
        v[i] = (float)harness_uniform(&rng, -1.0, 1.0);
    }
    REQUIRE_OK(cvk_sim_write_state(sim, x, v, n, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
    /* The device's inputs in internal order: the positions written and u = v h − ½ h² g
       (the projective-dynamics family's conversion, in the same arithmetic). */
    const cvk_build* b = &sim->build;
    float* xi = malloc(3 * n * sizeof(float));
    float* ui = malloc(3 * n * sizeof(float));
    for (uint32_t user = 0; user < n; user++) {
        uint32_t p = b->internal_of[user];
        for (int c = 0; c < 3; c++) {
            xi[3 * p + c] = x[3 * user + c];
            ui[3 * p + c] = p < b->free_count
                                ? (float)((double)v[3 * user + c] * s.scene.dt -
                                          0.5 * cvk_ref_params_of(&sim->params).gravity_h2[c])
                                : 0.0f;
        }
    }
    double* host = malloc(3 * n * sizeof(double));
    float* device = malloc(3 * n * sizeof(float));
    cvk_aero_forces_host(sim, xi, ui, 7 * (double)s.scene.dt, host);
    REQUIRE_OK(cvk_aero_read_forces(sim, device, &err), err);
    double largest = 0.0, worst = 0.0;
    for (uint64_t i = 0; i < 3 * n; i++)
        largest = fmax(largest, fabs(host[i]));
    for (uint64_t i = 0; i < 3 * n; i++)
        worst = fmax(worst, fabs(device[i] - host[i]));
    CHECK(largest > 1e-4 && worst < 1e-4 * largest,
          "device and host forces differ by %.3g N (largest force %.3g N)", worst, largest);
    printf("host reference: largest force %.4g N, worst difference %.3g N\n", largest, worst);
    free(x);
    free(v);
    free(xi);
    free(ui);
    free(host);
    free(device);
    cvk_sim_destroy(sim);
}

/* A free cloth in the wind is carried along it; the same bits for another dispatch shape and
   for one recorded frame resubmitted, while the gusts change. */
static void carried_and_repeatable(cvk_context* ctx)
{
    const uint32_t frames = 12;
    setup s;
    make_scene(&s, (const float[3]){1.0f, 4.0f, 0.0f});
    s.scene.substeps = 4;
    s.scene.wind.gusts = (cvk_gusts_desc){.amplitude = 0.5f, .period = 0.05f, .jitter = 30.0f};
    cvk_sim* a = create(ctx, &s, 0, 0);
    cvk_sim* b = create(ctx, &s, 8, 1);
    cvk_sim* c = create(ctx, &s, 0, 0);
    float* start = harness_read_all(a);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(a, frames, &err), err);
    REQUIRE_OK(cvk_sim_step(b, frames, &err), err);
    cvk_submitter sub;
    VkCommandBuffer cmd = harness_record(ctx, c, 1, &sub);
    harness_submit(ctx, &sub, cmd, frames);
    cvk_submitter_destroy(ctx, &sub);
    float* xa = harness_read_all(a);
    float* xb = harness_read_all(b);
    float* xc = harness_read_all(c);
    uint64_t n = cvk_sim_particle_count(a);
    CHECK(memcmp(xa, xb, 3 * n * sizeof(float)) == 0,
          "another dispatch shape differs by up to %.3g m", harness_max_diff(xa, xb, 3 * n));
    CHECK(memcmp(xa, xc, 3 * n * sizeof(float)) == 0,
          "recorded and resubmitted differs from stepped by up to %.3g m",
          harness_max_diff(xa, xc, 3 * n));
    double rise = 0.0;
    for (uint64_t p = 0; p < n; p++)
        rise += (xa[3 * p + 1] - start[3 * p + 1]) / (double)n;
    CHECK(rise > 1e-3, "the cloth rose %.3g m in an upward wind", rise);
    printf("carried: the cloth rose %.4g m in %u frames\n", rise, frames);
    free(start);
    free(xa);
    free(xb);
    free(xc);
    cvk_sim_destroy(a);
    cvk_sim_destroy(b);
    cvk_sim_destroy(c);
}

/* A scene without wind records no wind pass; with it, the pass is there. */
static void plan_without_wind(cvk_context* ctx)
{
    setup s;
    make_scene(&s, (const float[3]){1.0f, 0.0f, 0.0f});
    cvk_sim* windy = create(ctx, &s, 0, 0);
    s.scene.wind.enabled = false;
    cvk_sim* calm = create(ctx, &s, 0, 0);
    CHECK(cvk_plan_find_pass(&windy->plan, "wind") != UINT32_MAX, "a windy scene has no wind pass");
    CHECK(cvk_plan_find_pass(&calm->plan, "wind") == UINT32_MAX, "a calm scene has a wind pass");
    cvk_sim_destroy(windy);
    cvk_sim_destroy(calm);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    known_truths(ctx);
    host_reference(ctx);
    carried_and_repeatable(ctx);
    plan_without_wind(ctx);
    return harness_finish(ctx);
}
