/* The adaptive search for cloth-contact candidates (lib/collide.h): a cloth at rest stops
   searching, a fast one searches at every substep, positions written from the host make the
   next substep search, and a snapshot carries the contact state so that stepping on from it
   gives the same bits as never having stopped. */
#include <string.h>

#include "collide.h"
#include "harness.h"
#include "sim.h"

/* A cloth of n × n particles, `size` m, horizontal at height y, centred on x = z = 0. */
static cvk_cloth_desc flat_cloth(uint32_t n, float size, float y)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = n;
    cloth.size[0] = cloth.size[1] = size;
    cloth.origin[0] = -0.5f * size;
    cloth.origin[1] = y;
    cloth.origin[2] = -0.5f * size;
    cloth.stiffness.shear = 1e6f;
    return cloth;
}

static uint64_t searches(cvk_sim* sim)
{
    cvk_error err;
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    return st.contact_searches;
}

/* One cloth on the ground plane (y = 0) with self-contact, at height y, moving at vy. */
static cvk_sim* ground_scene(cvk_context* ctx, float y, float vy)
{
    static cvk_collider_desc ground;
    ground = cvk_default_collider_desc();
    ground.type = CVK_COLLIDER_PLANE;
    static cvk_cloth_desc cloth;
    cloth = flat_cloth(16, 0.5f, y);
    cloth.velocity[1] = vy;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.colliders = &ground;
    scene.collider_count = 1;
    scene.collision.self = true;
    cvk_error err;
    cvk_sim* sim = NULL;
    REQUIRE_OK(cvk_sim_create(ctx, &(cvk_sim_desc){.scene = &scene}, &sim, &err), err);
    return sim;
}

static void test_rest_and_motion(cvk_context* ctx)
{
    cvk_error err;
    /* Lying on the ground at its thickness (half the spacing), the cloth only settles by
       rounding: the first substep searches (nothing was searched yet), no other does. */
    cvk_sim* rest = ground_scene(ctx, 0.5f * 0.5f / 15.0f, 0.0f);
    REQUIRE_OK(cvk_sim_step(rest, 1, &err), err);
    uint64_t first = searches(rest);
    REQUIRE_OK(cvk_sim_step(rest, 6, &err), err);
    uint64_t later = searches(rest);
    CHECK(first == 1 && later == 1, "a cloth at rest searched %llu times in its first frame and "
          "%llu in all after 7 (expected 1 and 1)", (unsigned long long)first,
          (unsigned long long)later);
    /* Written positions (the same ones) make the next substep search once more. */
    uint64_t n = cvk_sim_particle_count(rest);
    float* xyz = malloc(3 * n * sizeof(float));
    REQUIRE_OK(cvk_sim_read_positions(rest, xyz, n, &err), err);
    REQUIRE_OK(cvk_sim_write_positions(rest, xyz, n, &err), err);
    REQUIRE_OK(cvk_sim_step(rest, 2, &err), err);
    CHECK(searches(rest) == 2, "after cvk_sim_write_positions and 2 frames: %llu searches in all "
          "(expected 2)", (unsigned long long)searches(rest));
    free(xyz);
    cvk_sim_destroy(rest);

    /* Rising at 10 m/s a cloth moves 2 cm in a substep of 1/480 s, more than half its
       thickness (0.83 cm): every substep searches. */
    cvk_sim* fast = ground_scene(ctx, 1.0f, 10.0f);
    uint32_t substeps = fast->params.substeps;
    REQUIRE_OK(cvk_sim_step(fast, 3, &err), err);
    CHECK(searches(fast) == 3ull * substeps, "a cloth at 10 m/s searched %llu times in 3 frames "
          "of %u substeps (expected every substep)", (unsigned long long)searches(fast),
          substeps);
    cvk_sim_destroy(fast);
}

/* Two cloths dropped on each other: save after some frames, step on, load, step on again: the
   same bits, the same searches. */
static void test_snapshot(cvk_context* ctx)
{
    cvk_cloth_desc cloths[2] = {flat_cloth(12, 0.4f, 0.03f), flat_cloth(12, 0.4f, 0.12f)};
    cloths[1].origin[0] += 0.05f;
    cvk_collider_desc ground = cvk_default_collider_desc();
    ground.type = CVK_COLLIDER_PLANE;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = 2;
    scene.colliders = &ground;
    scene.collider_count = 1;
    scene.collision.self = true;
    cvk_error err;
    cvk_sim* sim = NULL;
    REQUIRE_OK(cvk_sim_create(ctx, &(cvk_sim_desc){.scene = &scene}, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 8, &err), err);
    uint64_t size = cvk_sim_snapshot_size(sim);
    CHECK(size > cvk_collide_snapshot_size(sim) && cvk_collide_snapshot_size(sim) > 0,
          "a self-contact snapshot of %llu bytes holds %llu of contact state",
          (unsigned long long)size, (unsigned long long)cvk_collide_snapshot_size(sim));
    void* snap = malloc(size);
    REQUIRE_OK(cvk_sim_save_snapshot(sim, snap, size, &err), err);
    uint64_t n = cvk_sim_particle_count(sim);
    float* a = malloc(3 * n * sizeof(float));
    float* b = malloc(3 * n * sizeof(float));
    REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(sim, a, n, &err), err);
    uint64_t searched_a = searches(sim);
    REQUIRE_OK(cvk_sim_load_snapshot(sim, snap, size, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(sim, b, n, &err), err);
    uint32_t differ = 0;
    for (uint64_t i = 0; i < 3 * n; i++)
        differ += memcmp(&a[i], &b[i], sizeof(float)) != 0;
    CHECK(differ == 0, "stepping on from a loaded snapshot: %u of %llu coordinates differ from "
          "the run that never stopped", differ, (unsigned long long)(3 * n));
    CHECK(searches(sim) == searched_a && searched_a > 0,
          "searches: %llu after the reload, %llu without", (unsigned long long)searches(sim),
          (unsigned long long)searched_a);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    CHECK(st.self_contacts > 0, "the cloths should lie on each other (no contact between them)");
    free(a);
    free(b);
    free(snap);
    cvk_sim_destroy(sim);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    test_rest_and_motion(ctx);
    test_snapshot(ctx);
    return harness_finish(ctx);
}
