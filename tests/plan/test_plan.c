/* The step plan's operation kinds, recorded on the device with validation on:
   - a plan of a fill (the group counts of an indirect dispatch), a fill and a copy (a
     displacement of 1 m in every component into u0, copied to u1) and an indirect dispatch
     of the finalize pipeline (x += u, reading u1) moves every free particle by exactly 1 m per component
     and leaves the pinned ones where they were: each kind did its part, in order;
   - the operation list grows past any initial capacity, and pass names are registered once,
     in order, with their operation counts;
   - the dispatch shape: on a CPU device the passes that stream over particles run in
     workgroups of the device's subgroup size and the others in the workgroup size (64), on
     other devices all in the workgroup size, and a workgroup size asked for is used for all;
     every dispatch's group count follows from its pipeline's size;
   - rbgs over-relaxes every sweep of an outer iteration but the last (cvk_gs_sweep_omega): at
     omega 1.7 with 4 x 4 sweeps, one sweep in four of every colour runs at omega 1, the last of
     each outer iteration; with one sweep per outer iteration (4 x 1), or one outer iteration
     a substep (1 x 5), every sweep keeps omega. */
#include <string.h>

#include "harness.h"

#include "solvers/solve_pd.h"

/* The test's scene: one 9 x 7 cloth at the defaults, pinned at two corners (cloth is the
   scene's). */
static const uint32_t corners[2][2] = {{0, 0}, {8, 0}};

static cvk_scene_desc nine_by_seven(cvk_cloth_desc* cloth)
{
    *cloth = cvk_default_cloth_desc();
    cloth->grid[0] = 9;
    cloth->grid[1] = 7;
    cloth->pins = corners;
    cloth->pin_count = 2;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloth;
    scene.cloth_count = 1;
    return scene;
}

static cvk_sim* make_sim_sized(cvk_context* ctx, uint32_t workgroup_size)
{
    cvk_cloth_desc cloth;
    cvk_scene_desc scene = nine_by_seven(&cloth);
    cvk_error err;
    cvk_sim* sim;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = &scene;
    desc.workgroup_size = workgroup_size;
    REQUIRE_OK(cvk_sim_create(ctx, &desc, &sim, &err), err);
    return sim;
}

static cvk_sim* make_sim(cvk_context* ctx)
{
    return make_sim_sized(ctx, 0);
}

/* Fill, fill, copy, indirect dispatch: one substep, recorded and run once. */
static void run_transfer_plan(cvk_context* ctx, cvk_sim* sim, cvk_buffer* indirect)
{
    cvk_error err;
    cvk_pd* pd = sim->family_state;
    uint32_t free_count = sim->build.free_count;
    VkDeviceSize n16 = (VkDeviceSize)sim->build.particle_count * 16u;
    float one = 1.0f;
    uint32_t one_bits;
    memcpy(&one_bits, &one, sizeof one_bits);

    cvk_plan plan;
    cvk_plan_init(&plan, 1, sim->plan.workgroup_size, sim->plan.max_groups);
    uint32_t pass = cvk_plan_pass(&plan, "test");
    cvk_plan_fill(&plan, pass, indirect->buffer, 0, 12, 1); /* one group in x, y, z */
    cvk_op* fill = cvk_plan_fill(&plan, pass, pd->u[0].buffer, 0, n16, one_bits);
    if (fill)
        fill->barrier = CVK_BARRIER_TRANSFER_TO_TRANSFER; /* the copy reads it next */
    cvk_plan_copy(&plan, pass, pd->u[0].buffer, 0, pd->u[1].buffer, 0, n16);
    cvk_pd_push push = {.first = 0, .count = free_count};
    cvk_plan_dispatch_indirect(&plan, pass, CVK_PIPE_FINALIZE, pd->descriptors.pipeline_layout,
                               pd->descriptors.sets[CVK_PD_SET_U1_TO_U0], CVK_DOMAIN_PARTICLES,
                               indirect->buffer, 0, &push, sizeof push);
    REQUIRE_OK(cvk_plan_check(&plan, &err), err);
    CHECK(plan.op_count == 4 && plan.has_transfer, "the plan holds %u ops (expected 4)",
          plan.op_count);
    cvk_spec_inputs inputs = {.workgroup_size = plan.workgroup_size, .max_degree = sim->build.max_degree};
    bool created;
    REQUIRE_OK(cvk_plan_require_pipelines(&plan, ctx, &sim->pipelines, &inputs, &created, &err),
               err);

    VkCommandBuffer cmd;
    REQUIRE_OK(cvk_command_buffer_allocate(ctx, &sim->device.submitter, &cmd, &err), err);
    REQUIRE_OK(cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, &err), err);
    cvk_plan_record_frame(&plan, &sim->pipelines, NULL, cmd);
    REQUIRE_OK(cvk_command_buffer_end(cmd, &err), err);
    REQUIRE_OK(cvk_submit_and_wait(ctx, &sim->device.submitter, &cmd, 1, &err), err);
    vkFreeCommandBuffers(ctx->device, sim->device.submitter.pool, 1, &cmd);
    cvk_plan_destroy(&plan);
}

static void test_transfer_kinds(cvk_context* ctx)
{
    cvk_error err;
    cvk_sim* sim = make_sim(ctx);
    uint64_t n = cvk_sim_particle_count(sim);
    float* before = harness_read_all(sim);
    cvk_buffer indirect;
    REQUIRE_OK(cvk_buffer_create(ctx, 12,
                                 VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 CVK_MEMORY_DEVICE, "indirect groups", &indirect, &err), err);
    run_transfer_plan(ctx, sim, &indirect);
    float* after = harness_read_all(sim);
    double worst_free = 0.0, worst_pinned = 0.0;
    uint32_t pinned_count = 0;
    for (uint32_t p = 0; p < n; p++) {
        bool pinned = sim->build.internal_of[p] >= sim->build.free_count;
        pinned_count += pinned;
        for (int c = 0; c < 3; c++) {
            double moved = (double)after[3 * p + c] - before[3 * p + c];
            double off = pinned ? fabs(moved) : fabs(moved - 1.0);
            if (pinned && (off > worst_pinned || isnan(off)))
                worst_pinned = off;
            if (!pinned && (off > worst_free || isnan(off)))
                worst_free = off;
        }
    }
    CHECK(worst_free < 1e-6, "free particles moved by 1 m per component up to %g m", worst_free);
    CHECK(worst_pinned == 0.0 && pinned_count == 2, "%u pinned particles (2 expected) moved by "
          "%g m", pinned_count, worst_pinned);
    cvk_buffer_destroy(ctx, &indirect);
    free(before);
    free(after);
    cvk_sim_destroy(sim);
}

static void test_growth(void)
{
    cvk_plan plan;
    cvk_plan_init(&plan, 2, 64, 4);
    const char* names[] = {"predict", "collide", "solve"};
    for (uint32_t i = 0; i < 1000; i++) {
        uint32_t pass = cvk_plan_pass(&plan, names[i % 3]);
        cvk_plan_dispatch(&plan, pass, CVK_PIPE_JACOBI, VK_NULL_HANDLE, VK_NULL_HANDLE,
                          CVK_DOMAIN_SPRINGS, 0, 1 + i, NULL, 0);
    }
    cvk_plan_dispatch(&plan, 0, CVK_PIPE_JACOBI, VK_NULL_HANDLE, VK_NULL_HANDLE,
                      CVK_DOMAIN_SPRINGS, 0, 0, NULL, 0); /* nothing to do: no op */
    cvk_error err;
    CHECK(cvk_plan_check(&plan, &err) == CVK_SUCCESS, "growing the plan failed: %s", err.message);
    CHECK(plan.op_count == 1000, "the plan holds %u ops (expected 1000)", plan.op_count);
    CHECK(plan.pass_count == 3 && strcmp(plan.pass_names[1], "collide") == 0,
          "%u passes, the second named %s (expected 3, collide)", plan.pass_count,
          plan.pass_count > 1 ? plan.pass_names[1] : "-");
    CHECK(plan.pass_count == 3 && plan.pass_dispatches[0] == 334 && plan.pass_dispatches[2] == 333,
          "pass op counts %u, %u (expected 334, 333)", plan.pass_dispatches[0],
          plan.pass_count == 3 ? plan.pass_dispatches[2] : 0);
    CHECK(plan.ops[999].groups == 4 && plan.ops[0].groups == 1,
          "groups of the first and last op: %u and %u (expected 1 and 4, the cap)",
          plan.ops[0].groups, plan.ops[999].groups);
    CHECK(cvk_plan_query_count(&plan, NULL) == 1 + 2 * 1000,
          "%u queries for 2 substeps of 1000 ops in alternating passes (expected 2001)",
          cvk_plan_query_count(&plan, NULL));
    cvk_plan_destroy(&plan);
}

/* A plan with more kinds of pass than the statistics list (CVK_MAX_PASSES) is refused, not
   listed in part; at the limit it is not. */
static void test_pass_limit(void)
{
    char names[CVK_MAX_PASSES + 1][16]; /* the plan keeps the pointers until destroyed */
    cvk_plan plan;
    cvk_plan_init(&plan, 1, 64, 4);
    cvk_error err;
    char expected[192];
    snprintf(expected, sizeof expected,
             "the step plan has %u kinds of pass and the statistics list at most %u "
             "(CVK_MAX_PASSES): a defect of clothvk, please report it", CVK_MAX_PASSES + 1,
             CVK_MAX_PASSES);
    for (uint32_t i = 0; i <= CVK_MAX_PASSES; i++) {
        snprintf(names[i], sizeof names[i], "pass %u", i);
        cvk_plan_pass(&plan, names[i]);
        cvk_result r = cvk_plan_check(&plan, &err);
        if (i < CVK_MAX_PASSES)
            CHECK(r == CVK_SUCCESS, "%u kinds of pass refused: %s", i + 1, err.message);
        else
            CHECK(r == CVK_ERROR_UNSUPPORTED && strcmp(err.message, expected) == 0,
                  "%u kinds of pass: result %d, \"%s\"", i + 1, (int)r,
                  r == CVK_SUCCESS ? "" : err.message);
    }
    cvk_plan_destroy(&plan);
}

/* The group count every direct dispatch of `plan` should have: one invocation per item in
   workgroups of its pipeline's size, at most max_groups, and over particles at most one per
   particle_group_items. */
static void check_groups(const cvk_plan* plan, const char* what)
{
    uint32_t wrong = 0, streaming = 0, other = 0;
    for (uint32_t i = 0; i < plan->op_count; i++) {
        const cvk_op* op = &plan->ops[i];
        if (op->kind != CVK_OP_DISPATCH)
            continue;
        bool particles = cvk_pipeline_streams_particles(op->pipeline);
        uint32_t size = particles ? plan->particle_workgroup_size : plan->workgroup_size;
        uint32_t groups = (op->count + size - 1) / size;
        if (groups > plan->max_groups)
            groups = plan->max_groups;
        uint32_t items = plan->particle_group_items;
        if (particles && items > 1 && groups > (op->count + items - 1) / items)
            groups = (op->count + items - 1) / items;
        wrong += op->groups != groups;
        streaming += particles;
        other += !particles;
    }
    CHECK(wrong == 0 && streaming > 0, "%s: %u of the dispatches have the wrong group count "
          "(%u over particles, %u others)", what, wrong, streaming, other);
}

/* The floor on the items a workgroup over particles takes: 10,000 particles with a floor of
   16,384 in one workgroup, 40,000 in three, 200,000 in the cap's four; other pipelines and
   plans without the floor keep one workgroup per size items up to the cap. */
static void test_group_floor(void)
{
    cvk_plan plan;
    cvk_plan_init(&plan, 1, 64, 4);
    plan.particle_workgroup_size = 8;
    plan.particle_group_items = 16384;
    uint32_t got[4] = {cvk_plan_groups_of(&plan, CVK_PIPE_GS, 10000),
                       cvk_plan_groups_of(&plan, CVK_PIPE_GS, 40000),
                       cvk_plan_groups_of(&plan, CVK_PIPE_FINALIZE, 200000),
                       cvk_plan_groups_of(&plan, CVK_PIPE_PD_CONTACT, 10000)};
    CHECK(got[0] == 1 && got[1] == 3 && got[2] == 4 && got[3] == 4,
          "groups with a floor of 16384 items over particles: %u, %u, %u, contact %u (expected "
          "1, 3, 4, 4)", got[0], got[1], got[2], got[3]);
    plan.particle_group_items = 0;
    CHECK(cvk_plan_groups_of(&plan, CVK_PIPE_GS, 10000) == 4,
          "without the floor 10,000 particles take %u workgroups (expected the cap, 4)",
          cvk_plan_groups_of(&plan, CVK_PIPE_GS, 10000));
    cvk_plan_destroy(&plan);
}

static void test_shapes(cvk_context* ctx)
{
    cvk_sim* sim = make_sim(ctx);
    bool cpu = ctx->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    uint32_t lanes = ctx->subgroup_size;
    uint32_t expected = cpu && lanes >= 4 && lanes <= 64 ? lanes : 64;
    CHECK(sim->plan.workgroup_size == 64 && sim->plan.particle_workgroup_size == expected,
          "default shape: workgroups of %u, %u over particles (expected 64 and %u on a%s device "
          "with subgroups of %u)",
          sim->plan.workgroup_size, sim->plan.particle_workgroup_size, expected,
          cpu ? " CPU" : "nother", lanes);
    CHECK(cvk_pipeline_streams_particles(CVK_PIPE_GS) &&
              cvk_pipeline_streams_particles(CVK_PIPE_FINALIZE) &&
              !cvk_pipeline_streams_particles(CVK_PIPE_PD_CONTACT) &&
              !cvk_pipeline_streams_particles(CVK_PIPE_HASH_COUNT),
          "the sweeps and finalize stream over particles, the contact and hash passes do not");
    CHECK(sim->plan.particle_group_items == (cpu ? 16384u : 0u),
          "default shape: a floor of %u particles a workgroup (expected %u on a%s device)",
          sim->plan.particle_group_items, cpu ? 16384u : 0u, cpu ? " CPU" : "nother");
    CHECK(sim->plan.walk_items == (cpu ? 8u : 1u) &&
              cvk_plan_walk_groups(&sim->plan, 10000) == (cpu ? 20u : 157u),
          "default shape: %u items an invocation of detection and contact, %u workgroups for "
          "10,000 (expected %u and %u on a%s device)", sim->plan.walk_items,
          cvk_plan_walk_groups(&sim->plan, 10000), cpu ? 8u : 1u, cpu ? 20u : 157u,
          cpu ? " CPU" : "nother");
    check_groups(&sim->plan, "default shape");
    cvk_sim_destroy(sim);
    sim = make_sim_sized(ctx, 32);
    CHECK(sim->plan.workgroup_size == 32 && sim->plan.particle_workgroup_size == 32,
          "workgroup size 32 asked for: %u, %u over particles", sim->plan.workgroup_size,
          sim->plan.particle_workgroup_size);
    check_groups(&sim->plan, "workgroup size 32");
    cvk_sim_destroy(sim);
}

/* The omega of each rbgs sweep dispatch of a 4-outer plan, in order, at `inner` sweeps. */
static void check_last_sweep(cvk_context* ctx, uint32_t outer, uint32_t inner)
{
    cvk_cloth_desc cloth;
    cvk_scene_desc scene = nine_by_seven(&cloth);
    scene.solver.omega = 1.7f;
    scene.solver.outer_iterations = outer;
    scene.solver.inner_iterations = inner;
    cvk_error err;
    cvk_sim* sim;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = &scene;
    REQUIRE_OK(cvk_sim_create(ctx, &desc, &sim, &err), err);
    uint32_t colours = sim->build.colour_count, sweep_ops = 0, wrong = 0;
    /* Without damping, air, contact or a check the first sweep predicts (pd_passes.c,
       first_sweep_predicts), the last substep's displacements in its src when the outer
       iterations are even, in its dst when odd: those dispatches and no prediction's own. */
    cvk_pipeline_id folded = outer % 2 ? CVK_PIPE_GS_FIRST_PREDICT_DST : CVK_PIPE_GS_FIRST_PREDICT_SRC;
    uint32_t predicting = 0, predicts = 0;
    for (uint32_t i = 0; i < sim->plan.op_count; i++) {
        predicting += sim->plan.ops[i].pipeline == folded;
        predicts += sim->plan.ops[i].pipeline == CVK_PIPE_PREDICT;
    }
    CHECK(predicting == colours && predicts == 0, "rbgs %u x %u: %u first sweeps that predict "
          "(%s; expected %u) and %u predict dispatches (expected 0)", outer, inner, predicting,
          outer % 2 ? "last in dst" : "last in src", colours, predicts);
    for (uint32_t i = 0; i < sim->plan.op_count; i++) {
        const cvk_op* op = &sim->plan.ops[i];
        if (op->pipeline != CVK_PIPE_GS_FIRST && op->pipeline != CVK_PIPE_GS &&
            op->pipeline != CVK_PIPE_GS_LAST && op->pipeline != CVK_PIPE_GS_FIRST_PREDICT_SRC &&
            op->pipeline != CVK_PIPE_GS_FIRST_PREDICT_DST)
            continue;
        cvk_pd_push push;
        memcpy(&push, op->push, sizeof push);
        uint32_t sweep = (sweep_ops / colours) % inner;
        float expected = outer >= 2 && inner >= 2 && sweep + 1 == inner ? 1.0f : 1.7f;
        wrong += push.omega != expected;
        sweep_ops++;
    }
    CHECK(sweep_ops == outer * inner * colours && wrong == 0,
          "rbgs %u x %u at omega 1.7: %u sweep dispatches (expected %u), %u with the wrong omega "
          "(the last sweep of an outer iteration of two or more at 1 when there are two or more "
          "outer iterations, the others at 1.7)", outer, inner, sweep_ops, outer * inner * colours,
          wrong);
    cvk_sim_destroy(sim);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    test_growth();
    test_pass_limit();
    test_group_floor();
    test_transfer_kinds(ctx);
    test_shapes(ctx);
    check_last_sweep(ctx, 4, 4);
    check_last_sweep(ctx, 4, 1);
    check_last_sweep(ctx, 1, 5);
    return harness_finish(ctx);
}
