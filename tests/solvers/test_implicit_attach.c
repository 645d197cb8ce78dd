/* Attachments with implicit Euler (lib/features/attach.h, shaders/features/attach.comp -DIMPLICIT=1), with cg and
   with block Jacobi:
   - every frame the attached particles are where their keyframes put their start positions
     (with and without a collider pass counting time);
   - the cloth is dragged: a free particle below the slide moves along x, against the same
     scene whose attachment stands still, and the attached particles carry the motion's
     velocity;
   - one frame recorded and submitted N times gives the bits of cvk_sim_step(N), and so does a
     snapshot stepped on; pd -> implicit -> pd switches keep them on their keyframes;
   - substep by substep the device equals the host reference driven the same way (the attached
     particles' velocities prescribed before the substep, their positions placed after it);
   - a scene without attachments records no attach pass. */
#include <stdint.h>

#include "attach_scene.h"
#include "topology/build.h"
#include "recorded.h"
#include "solvers/solve_implicit.h"

/* As tests/solvers/test_implicit.c: one substep with a fixed number of iterations, float against
   double, relative to the substep's largest velocity change. */
#define SAME_TO_ROUNDING 1e-4

static const cvk_keyframe still[1] = {{.time = 0.0f, .rotation = {1, 0, 0, 0}}};

/* The attachment tests' scene, solved by implicit `linear`. */
static void make_scene(setup* s, cvk_linear_solver linear, bool collider)
{
    attach_make_scene(s, collider);
    s->scene.solver.method = CVK_METHOD_IMPLICIT;
    s->scene.solver.linear = linear;
}

static cvk_sim* create(cvk_context* ctx, const cvk_scene_desc* scene)
{
    cvk_error err;
    cvk_sim* sim = NULL;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    return sim;
}

/* Every frame, through the slide's loop and past the turn's last keyframe. */
static void follow_keyframes(cvk_context* ctx, cvk_linear_solver linear, bool collider)
{
    setup s;
    make_scene(&s, linear, collider);
    cvk_sim* sim = create(ctx, &s.scene);
    cvk_error err;
    float* start = harness_read_all(sim);
    double frame = s.scene.dt * s.scene.substeps, worst = 0.0;
    uint32_t worst_frame = 0, frames = 60; /* 0.48 s: the slide loops twice */
    for (uint32_t f = 1; f <= frames; f++) {
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        float* x = harness_read_all(sim);
        double e = attachment_error(&s.scene, start, x, f * frame);
        if (e > worst) {
            worst = e;
            worst_frame = f;
        }
        free(x);
    }
    const char* name = cvk_linear_solver_name(linear);
    CHECK(worst < 2e-6, "%s %s: an attached particle is %.3g m from its keyframed place (frame %u)",
          name, collider ? "with a collider pass" : "alone", worst, worst_frame);
    printf("%s: follow keyframes (%s): worst %.3g m over %u frames\n", name,
           collider ? "with a collider" : "alone", worst, frames);
    free(start);
    cvk_sim_destroy(sim);
}

/* The slide alone, 6 frames (0.048 s, 2 m/s along x): the attached particles report the
   motion's velocity, and the free particle below the slide's first pin and the bottom corner
   are ahead along x of where they are when the attachment stands still, the corner lagging
   behind the pins (0.096 m) and behind the particle next to them: dragged through the
   springs, not teleported. */
static void dragged(cvk_context* ctx, cvk_linear_solver linear)
{
    const char* name = cvk_linear_solver_name(linear);
    float* x[2];
    float* v = NULL;
    for (int moving = 0; moving < 2; moving++) {
        setup s;
        make_scene(&s, linear, false);
        s.scene.attachment_count = 1;
        if (!moving)
            s.attachments[0].motion = (cvk_motion){.keyframes = still, .keyframe_count = 1};
        cvk_sim* sim = create(ctx, &s.scene);
        cvk_error err;
        REQUIRE_OK(cvk_sim_step(sim, 6, &err), err);
        uint64_t n = cvk_sim_particle_count(sim);
        x[moving] = malloc(3 * n * sizeof(float));
        free(v);
        v = malloc(3 * n * sizeof(float));
        REQUIRE_OK(cvk_sim_read_state(sim, x[moving], v, n, &err), err);
        cvk_sim_destroy(sim);
    }
    CHECK(fabs(v[0] - 2.0) < 1e-3 && fabs(v[3] - 2.0) < 1e-3,
          "%s: attached particles move at %.5g and %.5g m/s along x, not the motion's 2", name,
          (double)v[0], (double)v[3]);
    const size_t below = 3 * (size_t)W, corner = 3 * ((size_t)(H - 1) * W);
    double near = x[1][below] - x[0][below], far = x[1][corner] - x[0][corner];
    CHECK(near > 1e-3 && far > 0.0 && far < 0.096 && far < near,
          "%s: the free particles below the slide are %.4g m (next row) and %.4g m (bottom) "
          "ahead of a standing attachment's: not dragged", name, near, far);
    printf("%s: dragged: next row %.4g m, bottom corner %.4g m ahead (pins 0.096 m)\n", name,
           near, far);
    free(x[0]);
    free(x[1]);
    free(v);
}

/* One frame recorded into the caller's command buffer and submitted N times: the same bits as
   cvk_sim_step(N) of a second simulation, with the keyframes moving all along. */
static void record_equals_step(cvk_context* ctx, cvk_linear_solver linear)
{
    const uint32_t frames = 25 + 12; /* 0.296 s: the slide is 0.192 m along x */
    setup s;
    make_scene(&s, linear, false);
    cvk_error err;
    cvk_sim* stepped = create(ctx, &s.scene);
    cvk_sim* recorded = create(ctx, &s.scene);
    float* start = harness_read_all(stepped);
    REQUIRE_OK(cvk_sim_step(stepped, frames, &err), err);
    cvk_submitter sub;
    VkCommandBuffer cmd = harness_record(ctx, recorded, 1, &sub);
    harness_submit(ctx, &sub, cmd, frames);
    cvk_submitter_destroy(ctx, &sub);
    float* a = harness_read_all(stepped);
    float* b = harness_read_all(recorded);
    uint64_t n = cvk_sim_particle_count(stepped);
    const char* name = cvk_linear_solver_name(linear);
    CHECK(memcmp(a, b, 3 * n * sizeof(float)) == 0,
          "%s: recorded and resubmitted %u times differs from stepped %u frames by up to %.3g m",
          name, frames, frames, harness_max_diff(a, b, 3 * n));
    CHECK(fabs(b[0] - start[0] - 0.192) < 1e-5,
          "%s: the sliding corner moved %.4g m along x, not 0.192", name,
          (double)(b[0] - start[0]));
    free(a);
    free(b);
    free(start);
    cvk_sim_destroy(stepped);
    cvk_sim_destroy(recorded);
}

/* Frame by frame (one substep each, a fixed number of iterations), the device's step from its
   own state equals the host reference's from the same state, with the attached particles
   driven as the attach passes drive them: before the substep v = (pose(t + h) · start − x) / h,
   after it x = pose(t + h) · start. */
static void equals_reference(cvk_context* ctx, cvk_linear_solver linear)
{
    setup s;
    make_scene(&s, linear, false);
    s.scene.substeps = 1;
    s.scene.dt = 1.0f / 120.0f;
    s.scene.solver.tolerance = 1e-7f; /* runs every iteration it is given */
    s.scene.solver.max_iterations = 5;
    cvk_sim* sim = create(ctx, &s.scene);
    cvk_error err;
    cvk_build b;
    REQUIRE_OK(cvk_build_create(&s.scene, &b, &err), err);
    cvk_step_params step_params = cvk_step_params_of(&s.scene);
    cvk_implicit_params ip = cvk_implicit_params_of(&step_params, &s.scene.solver);
    size_t n = b.particle_count;
    float *x = malloc(3 * n * sizeof(float)), *v = malloc(3 * n * sizeof(float));
    float *x1 = malloc(3 * n * sizeof(float)), *v1 = malloc(3 * n * sizeof(float));
    double *hx = malloc(3 * n * sizeof(double)), *hv = malloc(3 * n * sizeof(double));
    double worst = 0.0, worst_x = 0.0;
    const uint32_t frames = 20; /* 0.167 s: through the slide's turn, into the turn's motion */
    for (uint32_t f = 0; f < frames; f++) {
        REQUIRE_OK(cvk_sim_read_state(sim, x, v, n, &err), err);
        for (size_t p = 0; p < n; p++)
            for (int c = 0; c < 3; c++) {
                hx[3 * p + c] = x[3 * b.user_of[p] + c];
                hv[3 * p + c] = v[3 * b.user_of[p] + c];
            }
        double t1 = (f + 1) * (double)s.scene.dt;
        float target[3 * 3];
        for (uint32_t i = 0; i < b.attached_count; i++) {
            cvk_pose pose = cvk_motion_pose(&s.attachments[b.attached_to[i]].motion, t1);
            size_t c = b.attached[i];
            cvk_pose_apply(&pose, &b.position[3 * c], &target[3 * i]);
            for (int k = 0; k < 3; k++)
                hv[3 * c + k] = (target[3 * i + k] - hx[3 * c + k]) / ip.h;
        }
        cvk_implicit_report rep;
        CHECK(cvk_ref_implicit_substep(&b, &ip, hx, hv, &rep), "out of memory");
        for (uint32_t i = 0; i < b.attached_count; i++)
            for (int k = 0; k < 3; k++)
                hx[3 * (size_t)b.attached[i] + k] = target[3 * i + k];
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_sim_read_state(sim, x1, v1, n, &err), err);
        double diff = 0.0, scale = 1e-30, diff_x = 0.0;
        for (size_t p = 0; p < n; p++)
            for (int c = 0; c < 3; c++) {
                size_t u = 3 * (size_t)b.user_of[p] + c;
                double d = fabs(v1[u] - hv[3 * p + c]);
                diff = isnan(d) || d > diff ? d : diff;
                if (p < b.free_count) /* the free particles' velocity change */
                    scale = fmax(scale, fabs(hv[3 * p + c] - v[u]));
                diff_x = fmax(diff_x, fabs(x1[u] - hx[3 * p + c]));
            }
        worst = fmax(worst, isnan(diff) ? INFINITY : diff / scale);
        worst_x = fmax(worst_x, diff_x);
    }
    const char* name = cvk_linear_solver_name(linear);
    CHECK(worst < SAME_TO_ROUNDING && worst_x < 1e-5,
          "%s: the device differs from the reference by %.3g of the velocity change, %.3g m",
          name, worst, worst_x);
    printf("%s: device against the reference over %u frames: velocity %.3g (relative), "
           "position %.3g m\n", name, frames, worst, worst_x);
    free(x);
    free(v);
    free(x1);
    free(v1);
    free(hx);
    free(hv);
    cvk_build_destroy(&b);
    cvk_sim_destroy(sim);
}

/* A snapshot taken while the attachments move, loaded into a fresh simulation, steps on to the
   bits the first one reaches: the clock comes back with it. */
static void snapshot(cvk_context* ctx, cvk_linear_solver linear)
{
    setup s;
    make_scene(&s, linear, false);
    cvk_error err;
    cvk_sim* a = create(ctx, &s.scene);
    cvk_sim* b = create(ctx, &s.scene);
    REQUIRE_OK(cvk_sim_step(a, 9, &err), err);
    uint64_t size = cvk_sim_snapshot_size(a);
    void* data = malloc(size);
    REQUIRE_OK(cvk_sim_save_snapshot(a, data, size, &err), err);
    REQUIRE_OK(cvk_sim_load_snapshot(b, data, size, &err), err);
    REQUIRE_OK(cvk_sim_step(a, 11, &err), err);
    REQUIRE_OK(cvk_sim_step(b, 11, &err), err);
    float* xa = harness_read_all(a);
    float* xb = harness_read_all(b);
    uint64_t n = cvk_sim_particle_count(a);
    CHECK(memcmp(xa, xb, 3 * n * sizeof(float)) == 0,
          "%s: stepped on from a snapshot, the positions differ by up to %.3g m",
          cvk_linear_solver_name(linear), harness_max_diff(xa, xb, 3 * n));
    free(data);
    free(xa);
    free(xb);
    cvk_sim_destroy(a);
    cvk_sim_destroy(b);
}

/* pd, then implicit cg, then pd again, 10 frames each: each family moves the attached particles
   on from where the last left them (each has its own descriptor set of the attach pass). */
static void switch_families(cvk_context* ctx)
{
    setup s;
    make_scene(&s, CVK_LINEAR_CG, false);
    s.scene.solver = cvk_default_scene_desc().solver; /* pd rbgs */
    cvk_sim* sim = create(ctx, &s.scene);
    cvk_error err;
    float* start = harness_read_all(sim);
    cvk_solver_desc implicit = s.scene.solver;
    implicit.method = CVK_METHOD_IMPLICIT;
    implicit.linear = CVK_LINEAR_CG;
    const cvk_solver_desc order[3] = {s.scene.solver, implicit, s.scene.solver};
    for (int i = 0; i < 3; i++) {
        REQUIRE_OK(cvk_sim_set_solver(sim, &order[i], &err), err);
        REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
        float* x = harness_read_all(sim);
        double t = 10 * (i + 1) * s.scene.dt * s.scene.substeps;
        double e = attachment_error(&s.scene, start, x, t);
        CHECK(e < 2e-6, "after %s: an attached particle is %.3g m from its keyframed place",
              cvk_method_name(order[i].method), e);
        free(x);
    }
    free(start);
    cvk_sim_destroy(sim);
}

/* The same scene without attachments plans no attach pass; with them, two per substep. */
static void no_attachments_no_pass(cvk_context* ctx)
{
    for (int attached = 0; attached < 2; attached++) {
        setup s;
        make_scene(&s, CVK_LINEAR_CG, false);
        if (!attached)
            s.scene.attachment_count = 0;
        cvk_sim* sim = create(ctx, &s.scene);
        const cvk_plan* plan = &sim->plan;
        uint32_t pass = cvk_plan_find_pass(plan, "attach");
        uint32_t ops = pass == UINT32_MAX ? 0 : cvk_plan_frame_ops(plan, pass);
        uint32_t want = attached ? 2 * s.scene.substeps : 0;
        CHECK(ops == want, "%s attachments: %u attach dispatches per frame, not %u",
              attached ? "with" : "without", ops, want);
        cvk_sim_destroy(sim);
    }
}

int main(void)
{
    cvk_context* ctx = harness_context();
    const cvk_linear_solver solvers[2] = {CVK_LINEAR_CG, CVK_LINEAR_JACOBI};
    for (int i = 0; i < 2; i++) {
        follow_keyframes(ctx, solvers[i], false);
        follow_keyframes(ctx, solvers[i], true);
        dragged(ctx, solvers[i]);
        record_equals_step(ctx, solvers[i]);
        equals_reference(ctx, solvers[i]);
        snapshot(ctx, solvers[i]);
    }
    switch_families(ctx);
    no_attachments_no_pass(ctx);
    return harness_finish(ctx);
}
