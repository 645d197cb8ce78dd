/* Picking and dragging (lib/features/pick.h, lib/features/grab.h): the device's pick equals a double-precision
   host search on random rays over two cloths (hits, misses, rays from behind, ties broken by
   the first particle, radius 0), bad rays are refused with their message, picking leaves the
   frames alone; a grabbed particle is at its target at the end of every frame, moved evenly
   over the substeps, with the cloth following, under every device linear solver and with
   tethers; released, it is free with the drag's velocity; a frame recorded once and submitted
   again with the target changed between submissions gives the bits of cvk_sim_step; the grab
   holds a particle inside a collider (contact does not push it out); a hand (grab within a
   radius) holds every free particle near the grabbed one at its offset; pinned
   particles, missing ones, bad targets and solvers that cannot hold a grab are refused. */
#include <stdint.h>

#include "harness.h"
#include "recorded.h"

#define AW 12
#define AH 10
#define BW 7
#define BH 6

typedef struct setup {
    cvk_scene_desc scene;
    cvk_cloth_desc cloths[2];
    uint32_t pins[AW][2];
} setup;

/* Cloth 0: AW × AH hanging in the x-y plane (z = 0), its top row pinned. Cloth 1 (with `two`):
   BW × BH parallel to it at z = -0.3, behind part of it. */
static void make_scene(setup* s, bool two)
{
    cvk_cloth_desc* a = &s->cloths[0];
    *a = cvk_default_cloth_desc();
    a->name = "hanging";
    a->grid[0] = AW;
    a->grid[1] = AH;
    a->size[0] = 0.55f;
    a->size[1] = 0.45f;
    memcpy(a->origin, (float[3]){-0.25f, 1.0f, 0.0f}, sizeof a->origin);
    memcpy(a->v_axis, (float[3]){0.0f, -1.0f, 0.0f}, sizeof a->v_axis);
    a->stiffness.structural = 1e4f;
    a->stiffness.shear = 1e3f;
    for (uint32_t i = 0; i < AW; i++) {
        s->pins[i][0] = i;
        s->pins[i][1] = 0;
    }
    a->pins = (const uint32_t(*)[2])s->pins;
    a->pin_count = AW;
    cvk_cloth_desc* b = &s->cloths[1];
    *b = cvk_default_cloth_desc();
    b->name = "flat";
    b->grid[0] = BW;
    b->grid[1] = BH;
    b->size[0] = 0.3f;
    b->size[1] = 0.25f;
    memcpy(b->origin, (float[3]){-0.2f, 0.62f, -0.3f}, sizeof b->origin);
    memcpy(b->u_axis, (float[3]){1.0f, 0.0f, 0.0f}, sizeof b->u_axis);
    memcpy(b->v_axis, (float[3]){0.0f, 1.0f, 0.0f}, sizeof b->v_axis);
    b->stiffness.structural = 1e4f;
    s->scene = cvk_default_scene_desc();
    s->scene.substeps = 8;
    s->scene.cloths = s->cloths;
    s->scene.cloth_count = two ? 2 : 1;
}

/* ---- picking ---------------------------------------------------------------------------- */

typedef struct host_pick {
    bool hit;
    uint32_t user;     /* over all cloths */
    double distance;
    bool ambiguous;    /* a particle on the radius, or another hit as near, within rounding */
} host_pick;

/* The nearest particle within `radius` of the ray, in front of the origin, ties to the lower
   user index, in double precision. */
static host_pick host_search(const float* xyz, uint64_t n, const double o[3], const double d[3],
                             double radius)
{
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double u[3] = {d[0] / len, d[1] / len, d[2] / len};
    host_pick best = {.distance = INFINITY};
    double second = INFINITY;
    for (uint64_t p = 0; p < n; p++) {
        double v[3], w2 = 0.0, t = 0.0;
        for (int k = 0; k < 3; k++) {
            v[k] = xyz[3 * p + k] - o[k];
            t += v[k] * u[k];
        }
        for (int k = 0; k < 3; k++)
            w2 += (v[k] - t * u[k]) * (v[k] - t * u[k]);
        double r2 = radius * radius;
        if (fabs(w2 - r2) < 1e-5 * (r2 + 1e-6) || fabs(t) < 1e-6)
            best.ambiguous = true;
        if (t < 0.0 || w2 > r2)
            continue;
        if (t < best.distance) {
            second = best.distance;
            best = (host_pick){true, (uint32_t)p, t, best.ambiguous};
        } else {
            second = fmin(second, t);
        }
    }
    if (best.hit && second - best.distance < 1e-5)
        best.ambiguous = true;
    return best;
}

static uint32_t user_index(cvk_sim* sim, cvk_particle p)
{
    return cvk_sim_get_cloth(sim, p.cloth).first_particle + p.index;
}

/* Random rays through random positions: aimed near a random particle (hits), or anywhere
   (mostly misses), from either side. */
static void pick_matches_host(cvk_context* ctx)
{
    setup s;
    make_scene(&s, true);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &sim, &err), err);
    uint64_t n = cvk_sim_particle_count(sim);
    float* xyz = harness_read_all(sim);
    harness_rng rng = {2024u};
    for (uint64_t i = 0; i < 3 * n; i++)
        xyz[i] += (float)harness_uniform(&rng, -0.02, 0.02);
    REQUIRE_OK(cvk_sim_write_positions(sim, xyz, n, &err), err);
    uint32_t hits = 0, misses = 0, cloth1 = 0, skipped = 0, wrong = 0;
    double worst_distance = 0.0;
    for (int ray = 0; ray < 300; ray++) {
        double o[3], d[3], radius = harness_uniform(&rng, 0.0, 0.05);
        uint64_t aim = harness_next(&rng) % n;
        for (int k = 0; k < 3; k++)
            o[k] = harness_uniform(&rng, -1.5, 1.5);
        for (int k = 0; k < 3; k++) {
            double to = ray % 3 == 2 ? harness_uniform(&rng, -1.0, 1.0) : xyz[3 * aim + k];
            d[k] = to + harness_uniform(&rng, -0.01, 0.01) - o[k];
        }
        host_pick want = host_search(xyz, n, o, d, radius);
        if (want.ambiguous) {
            skipped++;
            continue;
        }
        float of[3] = {(float)o[0], (float)o[1], (float)o[2]};
        float df[3] = {(float)d[0], (float)d[1], (float)d[2]};
        cvk_pick_result got;
        REQUIRE_OK(cvk_sim_pick(sim, of, df, (float)radius, &got, &err), err);
        bool same = got.hit == want.hit &&
                    (!want.hit || user_index(sim, got.particle) == want.user);
        if (!same) {
            wrong++;
            CHECK(same, "ray %d: device %s particle %u, host %s particle %u", ray,
                  got.hit ? "hit" : "missed", got.hit ? user_index(sim, got.particle) : 0,
                  want.hit ? "hit" : "missed", want.user);
            continue;
        }
        if (!want.hit) {
            misses++;
            continue;
        }
        hits++;
        cloth1 += got.particle.cloth == 1;
        worst_distance = fmax(worst_distance, fabs(got.distance - want.distance));
        const float* x = &xyz[3 * (size_t)want.user];
        CHECK(memcmp(got.position, x, sizeof got.position) == 0,
              "ray %d: position [%g %g %g], the particle is at [%g %g %g]", ray,
              (double)got.position[0], (double)got.position[1], (double)got.position[2],
              (double)x[0], (double)x[1], (double)x[2]);
    }
    CHECK(worst_distance < 1e-5, "distance along the ray off by up to %.3g m", worst_distance);
    CHECK(hits >= 100 && misses >= 50 && cloth1 >= 10 && skipped < 30,
          "too few cases to mean anything: %u hits (%u on cloth 1), %u misses, %u skipped", hits,
          cloth1, misses, skipped);
    printf("pick vs host: %u hits (%u on cloth 1), %u misses, %u ambiguous rays skipped, %u wrong, "
           "distance within %.3g m\n", hits, cloth1, misses, skipped, wrong, worst_distance);
    free(xyz);
    cvk_sim_destroy(sim);
}

/* Rays whose answer is known: the front particle from the front, the back one from behind, a
   miss when the cloth is behind the origin or beside the ray, exact ties, radius 0. */
static void pick_known(cvk_context* ctx)
{
    setup s;
    make_scene(&s, true);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &sim, &err), err);
    float* x = harness_read_all(sim); /* the built grids: cloth 0 in z = 0, cloth 1 in z = -0.3 */
    uint32_t first1 = cvk_sim_get_cloth(sim, 1).first_particle;
    cvk_pick_result got;
    uint32_t front = 2 * AW + 3; /* cloth 0's [3, 2] */
    const float* f = &x[3 * front];
    /* Along -z through it from z = 2: it is hit first, at 2 m. */
    REQUIRE_OK(cvk_sim_pick(sim, (float[3]){f[0], f[1], 2.0f}, (float[3]){0, 0, -1}, 0.01f, &got,
                            &err), err);
    CHECK(got.hit && got.particle.cloth == 0 && got.particle.index == front &&
              fabsf(got.distance - 2.0f) < 1e-6f,
          "from the front: hit %d cloth %u index %u distance %g", got.hit, got.particle.cloth,
          got.particle.index, (double)got.distance);
    /* Through cloth 1's [1, 1], which has cloth 0 in front of it: from the front (z = 2,
       looking along -z) cloth 0 is hit first, at 2 m; from behind (z = -1, looking along +z, a
       direction of length 3) cloth 1, at 0.7 m. */
    const float* g = &x[3 * (first1 + BW + 1)];
    REQUIRE_OK(cvk_sim_pick(sim, (float[3]){g[0], g[1], 2.0f}, (float[3]){0, 0, -1}, 0.04f, &got,
                            &err), err);
    CHECK(got.hit && got.particle.cloth == 0 && fabsf(got.distance - 2.0f) < 1e-6f,
          "in front of cloth 1: hit %d cloth %u distance %g (want cloth 0 at 2 m)", got.hit,
          got.particle.cloth, (double)got.distance);
    REQUIRE_OK(cvk_sim_pick(sim, (float[3]){g[0], g[1], -1.0f}, (float[3]){0, 0, 3.0f}, 0.04f,
                            &got, &err), err);
    CHECK(got.hit && got.particle.cloth == 1 && fabsf(got.distance - 0.7f) < 1e-6f,
          "from behind: hit %d cloth %u distance %g (want cloth 1 at 0.7 m)", got.hit,
          got.particle.cloth, (double)got.distance);
    /* The same line, looking away from the cloths (they are behind the origin): a miss. */
    REQUIRE_OK(cvk_sim_pick(sim, (float[3]){f[0], f[1], 2.0f}, (float[3]){0, 0, 1}, 0.5f, &got,
                            &err), err);
    CHECK(!got.hit, "the cloth behind the origin was hit (cloth %u index %u)", got.particle.cloth,
          got.particle.index);
    /* Beside the cloth: a miss. */
    REQUIRE_OK(cvk_sim_pick(sim, (float[3]){3.0f, 1.0f, 2.0f}, (float[3]){0, 0, -1}, 0.5f, &got,
                            &err), err);
    CHECK(!got.hit, "a ray beside the cloths hit cloth %u index %u", got.particle.cloth,
          got.particle.index);
    /* Exact ties: down -z between four particles of cloth 0 with a radius reaching all four,
       every one at distance 2: the first in user order, [3, 2], wins. */
    const float* q = &x[3 * (front + AW + 1)];
    float mid[3] = {0.5f * (f[0] + q[0]), 0.5f * (f[1] + q[1]), 2.0f};
    REQUIRE_OK(cvk_sim_pick(sim, mid, (float[3]){0, 0, -1}, 0.04f, &got, &err), err);
    CHECK(got.hit && got.particle.cloth == 0 && got.particle.index == front,
          "tie of four: got cloth %u index %u, want the first, %u", got.particle.cloth,
          got.particle.index, front);
    /* Radius 0: only a particle exactly on the line; beside it by 1 mm, none. */
    REQUIRE_OK(cvk_sim_pick(sim, (float[3]){q[0], q[1], 5.0f}, (float[3]){0, 0, -1}, 0.0f, &got,
                            &err), err);
    CHECK(got.hit && got.particle.cloth == 0 && got.particle.index == front + AW + 1,
          "radius 0 on a particle: hit %d index %u, want %u", got.hit, got.particle.index,
          front + AW + 1);
    REQUIRE_OK(cvk_sim_pick(sim, (float[3]){q[0] + 1e-3f, q[1], 5.0f}, (float[3]){0, 0, -1}, 0.0f,
                            &got, &err), err);
    CHECK(!got.hit, "radius 0 beside every particle hit index %u", got.particle.index);
    free(x);
    cvk_sim_destroy(sim);
}

#define EXPECT_MESSAGE(call, result, want)                                                      \
    do {                                                                                        \
        cvk_result r_ = (call);                                                                 \
        CHECK(r_ == (result), "%s returned %s", #call, cvk_result_name(r_));                   \
        CHECK(strcmp(err.message, (want)) == 0, "got \"%s\", want \"%s\"", err.message, (want)); \
    } while (0)

static void pick_refuses(cvk_context* ctx)
{
    setup s;
    make_scene(&s, false);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &sim, &err), err);
    cvk_pick_result got;
    float o[3] = {0, 0, 1};
    EXPECT_MESSAGE(cvk_sim_pick(sim, o, (float[3]){0, 0, 0}, 0.1f, &got, &err),
                   CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_pick: the ray's direction must be finite and not zero, got [0, 0, 0]");
    EXPECT_MESSAGE(cvk_sim_pick(sim, o, (float[3]){NAN, 0, -1}, 0.1f, &got, &err),
                   CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_pick: the ray's direction must be finite and not zero, got "
                   "[nan, 0, -1]");
    EXPECT_MESSAGE(cvk_sim_pick(sim, (float[3]){0, INFINITY, 1}, (float[3]){0, 0, -1}, 0.1f, &got,
                                &err),
                   CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_pick: the ray's origin must be finite, got [0, inf, 1]");
    EXPECT_MESSAGE(cvk_sim_pick(sim, o, (float[3]){0, 0, -1}, -0.5f, &got, &err),
                   CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_pick: the radius must be finite and at least 0 m, got -0.5");
    EXPECT_MESSAGE(cvk_sim_pick(sim, o, (float[3]){0, 0, -1}, NAN, &got, &err),
                   CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_pick: the radius must be finite and at least 0 m, got nan");
    cvk_sim_destroy(sim);
}

/* Picks between frames change no bit of the frames. */
static void pick_leaves_frames(cvk_context* ctx)
{
    setup s;
    make_scene(&s, false);
    cvk_error err;
    cvk_sim *plain, *picked;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &plain, &err), err);
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &picked, &err), err);
    uint32_t hits = 0;
    for (int f = 0; f < 6; f++) {
        REQUIRE_OK(cvk_sim_step(plain, 1, &err), err);
        REQUIRE_OK(cvk_sim_step(picked, 1, &err), err);
        cvk_pick_result got;
        REQUIRE_OK(cvk_sim_pick(picked, (float[3]){0, 0.8f, 1}, (float[3]){0, 0, -1}, 0.05f, &got,
                                &err), err);
        hits += got.hit;
    }
    uint64_t n = cvk_sim_particle_count(plain);
    float* a = harness_read_all(plain);
    float* b = harness_read_all(picked);
    CHECK(hits == 6 && memcmp(a, b, 3 * n * sizeof(float)) == 0,
          "picking between frames changed them by up to %.3g m (%u of 6 picks hit)",
          harness_max_diff(a, b, 3 * n), hits);
    free(a);
    free(b);
    cvk_sim_destroy(plain);
    cvk_sim_destroy(picked);
}

/* ---- dragging ---------------------------------------------------------------------------- */

static double dist3(const float* a, const float* b)
{
    double d2 = 0.0;
    for (int k = 0; k < 3; k++)
        d2 += ((double)a[k] - b[k]) * ((double)a[k] - b[k]);
    return sqrt(d2);
}

/* The bottom middle particle of cloth 0, dragged out along +z and a little up (or `down` m a
   frame lower) at a steady 0.64 m/s for 16 frames, then let go: at the target at the end of
   every frame, its velocity that of the drag (the motion spread over the substeps; a jump in
   one substep would show S times more), the particle two rows above pulled along; released, it
   moves on as a free particle with that velocity. */
static void drag_follows(cvk_context* ctx, cvk_linear_solver linear, float tethers, float down)
{
    setup s;
    make_scene(&s, false);
    s.scene.solver.linear = linear;
    s.cloths[0].tethers = tethers;
    const char* name = cvk_linear_solver_name(linear);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 5, &err), err);
    uint64_t n = cvk_sim_particle_count(sim);
    cvk_particle grabbed = {0, (AH - 1) * AW + AW / 2};
    uint32_t above = grabbed.index - 2 * AW;
    float* x = harness_read_all(sim);
    float start[3], above_start[3];
    memcpy(start, &x[3 * grabbed.index], sizeof start);
    memcpy(above_start, &x[3 * above], sizeof above_start);
    free(x);
    double frame = s.scene.dt * s.scene.substeps;
    const float step[3] = {0.0f, 0.002f - down, 0.01f}; /* per frame: 0.64 m/s at 16 ms frames */
    float target[3];
    double worst = 0.0, worst_v = 0.0;
    float* v = malloc(3 * n * sizeof(float));
    x = malloc(3 * n * sizeof(float));
    for (int f = 1; f <= 16; f++) {
        for (int k = 0; k < 3; k++)
            target[k] = start[k] + f * step[k];
        REQUIRE_OK(cvk_sim_grab(sim, grabbed, target, &err), err);
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_sim_read_state(sim, x, v, n, &err), err);
        worst = fmax(worst, dist3(&x[3 * grabbed.index], target));
        for (int k = 0; k < 3; k++)
            worst_v = fmax(worst_v, fabs(v[3 * grabbed.index + k] - step[k] / frame));
    }
    CHECK(worst < 2e-6,
          "%s%s: the grabbed particle is up to %.3g m from its target at a frame's end",
          name, tethers > 0 ? " with tethers" : "", worst);
    /* Verlet's velocity adds h g / 2 (clothvk.h); the drag's is 0.64 m/s. */
    CHECK(worst_v < 0.05, "%s: the grabbed particle's velocity is off the drag's by %.3g m/s",
          name, worst_v);
    double pulled = x[3 * above + 2] - above_start[2];
    CHECK(pulled > 0.05, "%s: the particle two rows above moved only %.3g m along z (the drag: "
          "0.16 m)", name, pulled);
    /* Let go: from then on it moves as a particle of a simulation that never grabbed one, from
       the same state (velocities through floats: to their rounding). */
    cvk_sim_release(sim);
    cvk_sim* free_sim;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &free_sim, &err), err);
    REQUIRE_OK(cvk_sim_write_state(free_sim, x, v, n, &err), err);
    float held[3];
    memcpy(held, &x[3 * grabbed.index], sizeof held);
    REQUIRE_OK(cvk_sim_step(sim, 10, &err), err);
    REQUIRE_OK(cvk_sim_step(free_sim, 10, &err), err);
    float* free_x = harness_read_all(free_sim);
    REQUIRE_OK(cvk_sim_read_positions(sim, x, n, &err), err);
    double apart = harness_max_diff(x, free_x, 3 * n);
    double away = dist3(&free_x[3 * grabbed.index], held);
    CHECK(apart < 1e-5, "%s: released, the cloth differs from one never grabbed by %.3g m", name,
          apart);
    CHECK(away > 0.01, "%s: released, it moved only %.3g m in 10 frames: the check is void", name,
          away);
    free(free_x);
    cvk_sim_destroy(free_sim);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    CHECK(st.nan_count == 0 && !st.diverged, "%s: %llu NaN, diverged %d", name,
          (unsigned long long)st.nan_count, st.diverged);
    printf("drag (%s%s): at the target to %.3g m, velocity to %.3g m/s, the row above pulled "
           "%.3f m; released: %.3f m in 10 frames, %.3g m from a cloth never grabbed\n",
           name, tethers > 0 ? ", tethers" : "", worst, worst_v, pulled, away, apart);
    free(x);
    free(v);
    cvk_sim_destroy(sim);
}

/* A hand (cvk_sim_grab_within): the free particles of the grabbed one's cloth within the
   radius when the grab starts (found on the host here, in double precision) are at the target
   plus their offsets at the end of every frame, the rest are not held (the pinned row is
   never taken), a repeated call with the same radius only moves the target (the offsets stay
   those of the start), radius 0 holds the one particle, and a released hand lets them all go. */
static void hand_follows(cvk_context* ctx)
{
    setup s;
    make_scene(&s, true);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 5, &err), err);
    uint64_t n = cvk_sim_particle_count(sim);
    /* the second row's middle: the radius reaches the pinned top row and past it */
    cvk_particle grabbed = {0, AW + AW / 2};
    const float radius = 0.11f; /* about two spacings */
    float* x0 = harness_read_all(sim);
    const float* p0 = &x0[3 * grabbed.index];
    bool member[AW * AH] = {false};
    uint32_t members = 0, pinned_near = 0;
    for (uint32_t q = 0; q < AW * AH; q++) {
        if (dist3(&x0[3 * q], p0) > radius)
            continue;
        if (q < AW) /* the pinned top row: never held */
            pinned_near++;
        else
            member[q] = true, members++;
    }
    CHECK(members > 4 && members < AW * AH / 2 && pinned_near > 0,
          "hand: %u members and %u pinned particles within the radius: the test is void", members,
          pinned_near);
    float* x = malloc(3 * n * sizeof(float));
    double worst = 0.0, nearest_other = 1e30;
    float target[3];
    for (int f = 1; f <= 12; f++) {
        for (int k = 0; k < 3; k++)
            target[k] = p0[k] + (k == 2 ? 0.012f * f : 0.0f);
        REQUIRE_OK(cvk_sim_grab_within(sim, grabbed, radius, target, &err), err);
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_sim_read_positions(sim, x, n, &err), err);
        for (uint32_t q = 0; q < AW * AH; q++) {
            float want[3];
            for (int k = 0; k < 3; k++)
                want[k] = target[k] + (x0[3 * q + k] - p0[k]);
            double off = dist3(&x[3 * q], want);
            if (member[q])
                worst = fmax(worst, off);
            else if (q >= AW) /* a free particle outside the hand lags behind it */
                nearest_other = fmin(nearest_other, off);
        }
    }
    CHECK(worst < 2e-6, "hand: a held particle is up to %.3g m from the target plus its offset",
          worst);
    CHECK(nearest_other > 1e-4, "hand: a particle outside the radius followed the hand to %.3g m",
          nearest_other);
    /* Radius 0: the one particle; its former members are let go. */
    REQUIRE_OK(cvk_sim_grab_within(sim, grabbed, 0.0f, target, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 3, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(sim, x, n, &err), err);
    double one = dist3(&x[3 * grabbed.index], target), left = 0.0;
    for (uint32_t q = 0; q < AW * AH; q++)
        if (member[q] && q != grabbed.index) {
            float want[3];
            for (int k = 0; k < 3; k++)
                want[k] = target[k] + (x0[3 * q + k] - p0[k]);
            left = fmax(left, dist3(&x[3 * q], want));
        }
    CHECK(one < 2e-6 && left > 1e-4, "hand of radius 0: the particle %.3g m from the target, the "
          "former members up to %.3g m from their offsets", one, left);
    cvk_sim_release(sim);
    REQUIRE_OK(cvk_sim_step(sim, 3, &err), err);
    REQUIRE_OK(cvk_sim_read_positions(sim, x, n, &err), err);
    double fell = dist3(&x[3 * grabbed.index], target);
    CHECK(fell > 1e-3, "hand released: the particle stayed within %.3g m of the target", fell);
    EXPECT_MESSAGE(cvk_sim_grab_within(sim, grabbed, -0.1f, target, &err),
                   CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_grab_within: the radius must be a finite number of metres, at least "
                   "0; got -0.1");
    EXPECT_MESSAGE(cvk_sim_grab_within(sim, grabbed, NAN, target, &err),
                   CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_grab_within: the radius must be a finite number of metres, at least "
                   "0; got nan");
    EXPECT_MESSAGE(cvk_sim_grab_within(sim, (cvk_particle){0, 1}, 0.1f, target, &err),
                   CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_grab_within: particle 1 of cloth 0 (\"hanging\") is pinned; only free "
                   "particles can be grabbed");
    printf("hand of %u particles: held to %.3g m; the nearest free particle outside %.3g m off; "
           "radius 0 then: %.3g m, former members up to %.3g m off\n", members, worst,
           nearest_other, one, left);
    free(x);
    free(x0);
    cvk_sim_destroy(sim);
}

/* A frame recorded once (before the first grab, the pass planned from creation) and submitted
   again and again while the host moves the target between submissions, then releases: the bits
   of cvk_sim_step on a simulation that grabbed without cvk_sim_desc.grab. */
static void record_equals_step(cvk_context* ctx)
{
    setup s;
    make_scene(&s, false);
    cvk_error err;
    cvk_sim *stepped, *recorded;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &stepped, &err), err);
    cvk_sim_desc grab_desc = cvk_default_sim_desc();
    grab_desc.scene = &s.scene;
    grab_desc.grab = true;
    REQUIRE_OK(cvk_sim_create(ctx, &grab_desc, &recorded, &err), err);
    cvk_submitter sub;
    VkCommandBuffer cmd = harness_record(ctx, recorded, 1, &sub);
    cvk_particle grabbed = {0, (AH - 1) * AW + 2};
    float* x = harness_read_all(stepped);
    float target[3];
    const int frames = 20;
    for (int f = 0; f < frames; f++) {
        if (f >= 3 && f < 15) {
            for (int k = 0; k < 3; k++)
                target[k] = x[3 * grabbed.index + k] + (k == 0 ? 0.02f : 0.015f) * (f - 2);
            REQUIRE_OK(cvk_sim_grab(stepped, grabbed, target, &err), err);
            REQUIRE_OK(cvk_sim_grab(recorded, grabbed, target, &err), err);
        } else if (f == 15) {
            cvk_sim_release(stepped);
            cvk_sim_release(recorded);
        }
        REQUIRE_OK(cvk_sim_step(stepped, 1, &err), err);
        REQUIRE_OK(cvk_submit_and_wait(ctx, &sub, &cmd, 1, &err), err);
    }
    cvk_submitter_destroy(ctx, &sub);
    uint64_t n = cvk_sim_particle_count(stepped);
    float* a = harness_read_all(stepped);
    float* b = harness_read_all(recorded);
    CHECK(memcmp(a, b, 3 * n * sizeof(float)) == 0,
          "recorded and resubmitted %d times differs from stepped by up to %.3g m", frames,
          harness_max_diff(a, b, 3 * n));
    double moved = dist3(&a[3 * grabbed.index], &x[3 * grabbed.index]);
    CHECK(moved > 0.1, "the grabbed particle moved only %.3g m: the check is void", moved);
    printf("recorded = stepped with a drag: %s (the particle moved %.3f m)\n",
           memcmp(a, b, 3 * n * sizeof(float)) == 0 ? "same bits" : "DIFFERENT", moved);
    free(x);
    free(a);
    free(b);
    cvk_sim_destroy(stepped);
    cvk_sim_destroy(recorded);
}

/* A plane collider 5 cm below the cloth's bottom edge, and the bottom middle particle dragged
   15 cm down, through it: the grab wins over contact (the hand holds the particle where it
   is), while the particles beside it stay on the free side. */
static void drag_beats_contact(cvk_context* ctx)
{
    setup s;
    make_scene(&s, false);
    cvk_collider_desc floor = cvk_default_collider_desc();
    floor.point[1] = 0.5f;
    s.scene.colliders = &floor;
    s.scene.collider_count = 1;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &sim, &err), err);
    uint64_t n = cvk_sim_particle_count(sim);
    cvk_particle grabbed = {0, (AH - 1) * AW + AW / 2};
    float* x = harness_read_all(sim);
    float start[3], target[3];
    memcpy(start, &x[3 * grabbed.index], sizeof start);
    double worst = 0.0;
    for (int f = 1; f <= 10; f++) {
        memcpy(target, start, sizeof target);
        target[1] -= 0.015f * f;
        REQUIRE_OK(cvk_sim_grab(sim, grabbed, target, &err), err);
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_sim_read_positions(sim, x, n, &err), err);
        worst = fmax(worst, dist3(&x[3 * grabbed.index], target));
    }
    double lowest_other = INFINITY;
    for (uint64_t p = 0; p < n; p++)
        if (p != grabbed.index)
            lowest_other = fmin(lowest_other, x[3 * p + 1]);
    CHECK(worst < 2e-6, "through a collider: the grabbed particle is up to %.3g m from its target",
          worst);
    CHECK(x[3 * grabbed.index + 1] < 0.45f && lowest_other > 0.49,
          "the grabbed particle is at y = %.3f (want 0.4), the lowest other at %.3f (want above "
          "the plane at 0.5, less its thickness)", (double)x[3 * grabbed.index + 1], lowest_other);
    printf("drag through a collider: at the target to %.3g m, the lowest other particle at "
           "y = %.4f\n", worst, lowest_other);
    free(x);
    cvk_sim_destroy(sim);
}

static void grab_refuses(cvk_context* ctx)
{
    setup s;
    make_scene(&s, true);
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &sim, &err), err);
    float t[3] = {0, 0.5f, 0.2f};
    EXPECT_MESSAGE(cvk_sim_grab(sim, (cvk_particle){0, 3}, t, &err), CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_grab: particle 3 of cloth 0 (\"hanging\") is pinned; only free "
                   "particles can be grabbed");
    EXPECT_MESSAGE(cvk_sim_grab(sim, (cvk_particle){2, 0}, t, &err), CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_grab: cloth 2 does not exist (the scene has 2 cloths)");
    EXPECT_MESSAGE(cvk_sim_grab(sim, (cvk_particle){1, BW * BH}, t, &err),
                   CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_grab: particle 42 of cloth 1 (\"flat\") does not exist (it has 42)");
    EXPECT_MESSAGE(cvk_sim_grab(sim, (cvk_particle){1, 0}, (float[3]){0, NAN, 0}, &err),
                   CVK_ERROR_INVALID_ARGUMENT,
                   "cvk_sim_grab: the target must be finite, got [0, nan, 0]");
    /* A grab holds; the host solver cannot take over while it does. */
    REQUIRE_OK(cvk_sim_grab(sim, (cvk_particle){1, 0}, t, &err), err);
    cvk_solver_desc host = s.scene.solver;
    host.linear = CVK_LINEAR_GS_CPU;
    EXPECT_MESSAGE(cvk_sim_set_solver(sim, &host, &err), CVK_ERROR_UNSUPPORTED,
                   "cvk_sim_set_solver: a particle is grabbed and gs-cpu (the host reference) "
                   "cannot hold it; release it first (cvk_sim_release)");
    cvk_sim_release(sim);
    REQUIRE_OK(cvk_sim_set_solver(sim, &host, &err), err);
    EXPECT_MESSAGE(cvk_sim_grab(sim, (cvk_particle){1, 0}, t, &err), CVK_ERROR_UNSUPPORTED,
                   "cvk_sim_grab: gs-cpu (the host reference) cannot hold a grabbed particle; use "
                   "the pd method with rbgs, jacobi or chebyshev");
    cvk_sim_destroy(sim);
    /* The implicit method, at creation and on a grab. */
    make_scene(&s, false);
    s.scene.solver.method = CVK_METHOD_IMPLICIT;
    s.scene.solver.linear = CVK_LINEAR_CG;
    s.scene.substeps = 1;
    s.scene.dt = 1.0f / 60.0f;
    cvk_sim* bad = NULL;
    cvk_sim_desc grab_desc = cvk_default_sim_desc();
    grab_desc.scene = &s.scene;
    grab_desc.grab = true;
    EXPECT_MESSAGE(cvk_sim_create(ctx, &grab_desc, &bad, &err),
                   CVK_ERROR_UNSUPPORTED,
                   "cvk_sim_desc.grab: the implicit method cannot hold a grabbed particle; use "
                   "the pd method with rbgs, jacobi or chebyshev");
    CHECK(bad == NULL, "a failed creation returned a simulation");
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &sim, &err), err);
    EXPECT_MESSAGE(cvk_sim_grab(sim, (cvk_particle){0, AW}, t, &err), CVK_ERROR_UNSUPPORTED,
                   "cvk_sim_grab: the implicit method cannot hold a grabbed particle; use the pd "
                   "method with rbgs, jacobi or chebyshev");
    cvk_sim_destroy(sim);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    pick_matches_host(ctx);
    pick_known(ctx);
    pick_refuses(ctx);
    pick_leaves_frames(ctx);
    drag_follows(ctx, CVK_LINEAR_RBGS, 0.0f, 0.0f);
    drag_follows(ctx, CVK_LINEAR_JACOBI, 0.0f, 0.0f);
    drag_follows(ctx, CVK_LINEAR_CHEBYSHEV, 0.0f, 0.0f);
    /* Pulled down as well, past the length its tethers allow: the grab wins over them. */
    drag_follows(ctx, CVK_LINEAR_RBGS, 1.0f, 0.005f);
    drag_beats_contact(ctx);
    hand_follows(ctx);
    record_equals_step(ctx);
    grab_refuses(ctx);
    return harness_finish(ctx);
}
