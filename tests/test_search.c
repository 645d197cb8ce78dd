/* The adaptive search for cloth-contact candidates (lib/collide.h): a cloth at rest stops
   searching, so does one moving fast as one, cloths approaching fast search at every substep, positions written from the host make the
   next substep search, and a snapshot carries the contact state so that stepping on from it
   gives the same bits as never having stopped; on folded cloths, the candidates a search keeps
   against a brute force over every particle–triangle pair. */
#include <math.h>
#include <string.h>

#include "collide.h"
#include "harness.h"
#include "intersect.h"
#include "shared/layout.h"
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
       thickness (0.83 cm), but all of it alike: no pair comes nearer, and only the first
       substep searches. */
    cvk_sim* fast = ground_scene(ctx, 1.0f, 10.0f);
    uint32_t substeps = fast->params.substeps;
    REQUIRE_OK(cvk_sim_step(fast, 3, &err), err);
    CHECK(searches(fast) == 1, "a cloth rising as one at 10 m/s searched %llu times in 3 frames "
          "(expected once)", (unsigned long long)searches(fast));
    cvk_sim_destroy(fast);

    /* Two such cloths, one rising and one falling at 10 m/s: they approach by 4 cm a substep,
       and every substep searches. */
    cvk_cloth_desc cloths[2] = {flat_cloth(16, 0.5f, 1.0f), flat_cloth(16, 0.5f, 3.0f)};
    cloths[0].velocity[1] = 10.0f;
    cloths[1].velocity[1] = -10.0f;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = 2;
    scene.collision.self = true;
    cvk_sim* pair = NULL;
    REQUIRE_OK(cvk_sim_create(ctx, &(cvk_sim_desc){.scene = &scene}, &pair, &err), err);
    REQUIRE_OK(cvk_sim_step(pair, 3, &err), err);
    CHECK(searches(pair) == 3ull * substeps, "two cloths approaching at 20 m/s searched %llu "
          "times in 3 frames of %u substeps (expected every substep)",
          (unsigned long long)searches(pair), substeps);
    cvk_sim_destroy(pair);
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

/* ---- the candidates against a brute force ---------------------------------------------- */

static double point_triangle_distance(const float* p, const float* a, const float* b,
                                      const float* c)
{
    double pd[3], ad[3], bd[3], cd[3];
    for (int k = 0; k < 3; k++) {
        pd[k] = p[k];
        ad[k] = a[k];
        bd[k] = b[k];
        cd[k] = c[k];
    }
    return sqrt(cvk_point_triangle_distance2(pd, ad, bd, cd));
}

static uint32_t next_random(uint32_t* state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

static float uniform(uint32_t* state, float lo, float hi)
{
    return lo + (hi - lo) * (float)next_random(state) / (float)(1u << 24);
}

/* A cloth folded twice into three layers (an S seen from the side) with random fold lines,
   gaps between 0.3 and 2.2 thicknesses and every particle jittered by up to a quarter
   thickness: the middle layer has candidates on both sides, more than a particle keeps. */
static void fold(float* xyz, uint32_t n, float size, float thickness, uint32_t* state)
{
    float h = size / (float)(n - 1);
    float s1 = uniform(state, 0.45f, 0.55f) * size, s2 = s1 + uniform(state, 0.25f, 0.35f) * size;
    float g1 = uniform(state, 0.3f, 2.2f) * thickness, g2 = uniform(state, 0.3f, 2.2f) * thickness;
    for (uint32_t j = 0; j < n; j++)
        for (uint32_t i = 0; i < n; i++) {
            float s = (float)i * h, x, y;
            if (s < s1) {
                x = s;
                y = 0.0f;
            } else if (s < s2) {
                x = s1 - (s - s1);
                y = g1;
            } else {
                x = s1 - (s2 - s1) + (s - s2);
                y = g1 + g2;
            }
            float* p = &xyz[3 * ((size_t)j * n + i)];
            p[0] = x + uniform(state, -0.25f, 0.25f) * thickness;
            p[1] = 0.5f + y + uniform(state, -0.25f, 0.25f) * thickness;
            p[2] = (float)j * h + uniform(state, -0.25f, 0.25f) * thickness;
        }
}

/* Cloths with self-contact, one substep a frame (every frame searches once). */
static cvk_sim* self_contact_sim(cvk_context* ctx, const cvk_cloth_desc* cloths, uint32_t count)
{
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = count;
    scene.substeps = 1;
    scene.collision.self = true;
    cvk_error err;
    cvk_sim* sim = NULL;
    REQUIRE_OK(cvk_sim_create(ctx, &(cvk_sim_desc){.scene = &scene}, &sim, &err), err);
    return sim;
}

/* After a search on a folded cloth: every particle–triangle pair within the detection radius
   that is not near at rest is among the particle's kept candidates, or the particle keeps as
   many as it can, all at most that far; every kept one is such a pair, once, with the side the
   particle is on. Distances on the host in double from the positions the search saw. */
static void test_candidates(cvk_context* ctx)
{
    const uint32_t n = 24, K = CVK_CONTACTS_PER_PARTICLE;
    const float size = 0.5f;
    uint64_t pairs = 0, kept_total = 0, full = 0, missing = 0, wrong = 0, unordered = 0;
    uint64_t ties = 0, tie_order = 0;
    uint64_t listed_particles = 0, culled_particles = 0;
    for (uint32_t seed = 1; seed <= 4; seed++) {
        /* seeds 3 and 4: a second folded cloth among the first one's layers */
        cvk_cloth_desc cloths[2] = {flat_cloth(n, size, 0.5f), flat_cloth(n, size, 0.7f)};
        uint32_t cloth_count = seed > 2 ? 2 : 1;
        cvk_error err;
        cvk_sim* sim = self_contact_sim(ctx, cloths, cloth_count);
        const cvk_collide* c = &sim->collide;
        const cvk_build* b = &sim->build;
        float* xyz = malloc(3 * (size_t)n * n * cloth_count * sizeof(float));
        uint32_t state = seed * 7919u;
        fold(xyz, n, size, c->thickness, &state);
        if (cloth_count == 2) {
            float* second = &xyz[3 * (size_t)n * n];
            fold(second, n, size, c->thickness, &state);
            float dx = uniform(&state, -0.2f, 0.2f) * size;
            float dy = uniform(&state, -1.0f, 3.0f) * c->thickness;
            for (size_t i = 0; i < (size_t)n * n; i++) {
                second[3 * i] += dx;
                second[3 * i + 1] += dy;
            }
        }
        REQUIRE_OK(cvk_sim_write_positions(sim, xyz, (uint64_t)n * n * cloth_count, &err), err);
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err); /* one substep: it searches */
        uint64_t bytes = cvk_collide_snapshot_size(sim);
        unsigned char* snap = malloc(bytes);
        REQUIRE_OK(cvk_collide_save_snapshot(sim, snap, &err), err);
        const float* seen = (const float*)(snap + sizeof(cvk_gpu_frame)); /* vec4 per particle */
        const uint32_t* kept = (const uint32_t*)(snap + sizeof(cvk_gpu_frame) +
                                                 16u * (size_t)b->particle_count);
        double radius = (double)CVK_DETECT_RADIUS_THICKNESSES(c->detect_every) * c->thickness;
        double slack = 1e-5 * radius; /* float rounding of the device's distances */
        /* The patches: the host's activity bracketed a little either way (the device's float
           rounding near the thresholds may go either way). */
        uint8_t* surely = malloc(c->patch_count ? c->patch_count : 1);
        uint8_t* maybe = malloc(c->patch_count ? c->patch_count : 1);
        cvk_collide_patch_activity(c, b, seen, -0.01, surely);
        cvk_collide_patch_activity(c, b, seen, 0.01, maybe);
        const uint32_t* table = c->patch_table;
        for (uint32_t p = 0; p < b->free_count; p++) {
            const float* xp = &seen[4 * (size_t)p];
            const uint32_t* mine = &kept[(size_t)K * p];
            uint32_t own = table[p];
            bool must = own == CVK_NO_PATCH || surely[own];
            bool may = own == CVK_NO_PATCH || maybe[own];
            listed_particles += must;
            if (!may) { /* a flat, lone patch: not searched (what it leaves out: test_flat_patches) */
                culled_particles++;
                wrong += mine[0] != CVK_NO_CONTACT;
                continue;
            }
            if (!must)
                continue; /* on a threshold: either is right */
            uint32_t count = 0;
            double farthest = 0.0, previous = 0.0;
            while (count < K && mine[count] != CVK_NO_CONTACT)
                count++;
            for (uint32_t k = count; k < K; k++)
                wrong += mine[k] != CVK_NO_CONTACT; /* the list ends at the first empty slot */
            for (uint32_t k = 0; k < count; k++) {
                uint32_t t = mine[k] >> 1, side = mine[k] & 1u;
                if (t >= b->triangle_count) {
                    wrong++;
                    continue;
                }
                uint32_t v[3];
                for (int m = 0; m < 3; m++)
                    v[m] = b->internal_of[b->triangles[3 * (size_t)t + m]];
                const float *a = &seen[4 * (size_t)v[0]], *bb = &seen[4 * (size_t)v[1]],
                            *cc = &seen[4 * (size_t)v[2]];
                double d = point_triangle_distance(xp, a, bb, cc);
                farthest = fmax(farthest, d);
                /* nearest first; at equal distances (the nearest point a corner that several
                   triangles share: the same distance to the bit here, and on the device too
                   unless its float arithmetic lands on an edge next to the corner), the lower
                   triangle first */
                if (k > 0 && d < previous - slack)
                    unordered++;
                if (k > 0 && d == previous && (mine[k - 1] >> 1) > t)
                    tie_order++;
                ties += k > 0 && d == previous;
                previous = d;
                bool twice = false;
                for (uint32_t m = 0; m < k; m++)
                    twice |= (mine[m] >> 1) == t;
                /* the side: the sign of (p − a) · n, well away from the plane only */
                double e1[3], e2[3], ap[3];
                for (int m = 0; m < 3; m++) {
                    e1[m] = (double)bb[m] - a[m];
                    e2[m] = (double)cc[m] - a[m];
                    ap[m] = (double)xp[m] - a[m];
                }
                double nrm[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                 e1[0] * e2[1] - e1[1] * e2[0]};
                double height = (ap[0] * nrm[0] + ap[1] * nrm[1] + ap[2] * nrm[2]) /
                                sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
                bool bad_side = fabs(height) > slack && (height < 0.0) != (side == 1u);
                if (d >= radius + slack || cvk_collide_rest_near(c, p, v) || twice || bad_side)
                    wrong++;
            }
            kept_total += count;
            full += count == K;
            for (uint32_t t = 0; t < b->triangle_count; t++) {
                uint32_t v[3];
                for (int m = 0; m < 3; m++)
                    v[m] = b->internal_of[b->triangles[3 * (size_t)t + m]];
                if (cvk_collide_rest_near(c, p, v))
                    continue;
                double d = point_triangle_distance(xp, &seen[4 * (size_t)v[0]],
                                                   &seen[4 * (size_t)v[1]],
                                                   &seen[4 * (size_t)v[2]]);
                if (d >= radius - slack)
                    continue;
                pairs++;
                bool found = false;
                for (uint32_t k = 0; k < count; k++)
                    found |= (mine[k] >> 1) == t;
                if (!found && !(count == K && farthest <= d + slack))
                    missing++;
            }
        }
        free(surely);
        free(maybe);
        free(snap);
        free(xyz);
        cvk_sim_destroy(sim);
    }
    CHECK(listed_particles > 1000, "%llu particles searched on the folded cloths",
          (unsigned long long)listed_particles);
    printf("patches: %llu particles searched, %llu left out\n",
           (unsigned long long)listed_particles, (unsigned long long)culled_particles);
    CHECK(missing == 0, "%llu of %llu pairs within the detection radius are neither kept nor "
          "beyond a full list of nearer ones", (unsigned long long)missing,
          (unsigned long long)pairs);
    CHECK(wrong == 0, "%llu kept candidates are too far, near at rest, kept twice, on the wrong "
          "side or out of place", (unsigned long long)wrong);
    CHECK(unordered == 0, "%llu kept candidates after a farther one", (unsigned long long)unordered);
    /* ties broken by the order of the walk put about one in six the other way */
    CHECK(ties > 1000 && tie_order * 100 < ties, "%llu of %llu ties not in triangle order",
          (unsigned long long)tie_order, (unsigned long long)ties);
    /* The folds bring layers within the radius, and the middle layer's particles have more
       such triangles than they keep: both branches above are exercised. */
    CHECK(pairs > 1000 && kept_total > 1000 && full > 10,
          "%llu pairs within the radius, %llu kept, %llu full lists: the folds did not fold",
          (unsigned long long)pairs, (unsigned long long)kept_total, (unsigned long long)full);
    printf("candidates: %llu pairs within the radius, %llu kept, %llu full lists, %llu ties\n",
           (unsigned long long)pairs, (unsigned long long)kept_total, (unsigned long long)full,
           (unsigned long long)ties);
}

/* Patches (collide.h): a flat cloth moving fast in space lists no particle to search and has
   no candidates; with another cloth stacked on it, folded, or squeezed within its plane, it
   lists the particles of its active patches, as the host's reference of the activity says. */
static void test_flat_patches(cvk_context* ctx)
{
    /* Two cloths: the second far off, then stacked on the first (each flat, facing the same
       way: only being apart makes them inactive), then away again while the first folds. */
    cvk_cloth_desc cloths[2] = {flat_cloth(40, 1.0f, 1.0f), flat_cloth(20, 0.5f, 1.0f)};
    cloths[0].velocity[0] = cloths[1].velocity[0] = 3.0f;
    cloths[1].origin[0] += 5.0f;
    cvk_error err;
    cvk_sim* sim = self_contact_sim(ctx, cloths, 2);
    const cvk_collide* c = &sim->collide;
    const cvk_build* b = &sim->build;
    uint64_t bytes = cvk_collide_snapshot_size(sim);
    unsigned char* snap = malloc(bytes);
    uint8_t* active = malloc(c->patch_count);
    uint8_t* maybe = malloc(c->patch_count);
    uint64_t n = cvk_sim_particle_count(sim);
    float* xyz = malloc(3 * n * sizeof(float));
    float* flat_xyz = malloc(3 * n * sizeof(float));
    const uint64_t first_count = 40 * 40;
    static const char* const names[4] = {"flat", "stacked", "folded", "squeezed"};
    for (int phase = 0; phase < 4; phase++) {
        bool folded = phase == 2;
        const char* name = names[phase];
        if (phase > 0) { /* from the flat state each time */
            memcpy(xyz, flat_xyz, 3 * n * sizeof(float));
            float x_min = xyz[0], x_max = xyz[0];
            for (uint64_t i = 0; i < first_count; i++) {
                x_min = fminf(x_min, xyz[3 * i]);
                x_max = fmaxf(x_max, xyz[3 * i]);
            }
            /* stacked: the second cloth two thicknesses above the first's middle, or away */
            float second_min = xyz[3 * first_count];
            for (uint64_t i = first_count; i < n; i++)
                second_min = fminf(second_min, xyz[3 * i]);
            float shift = (phase == 1 ? 0.5f * (x_min + x_max) - 0.25f : x_max + 3.0f) - second_min;
            for (uint64_t i = first_count; i < n; i++) {
                xyz[3 * i] += shift;
                xyz[3 * i + 1] = xyz[1] + (phase == 1 ? 2.0f * c->thickness : 0.0f);
            }
            float fold_at = x_min + 2.0f / 3.0f * (x_max - x_min);
            for (uint64_t i = 0; phase == 3 && i < first_count; i++)
                if (xyz[3 * i] > fold_at) /* the far third squeezed to 0.4 of its width, flat */
                    xyz[3 * i] = fold_at + 0.4f * (xyz[3 * i] - fold_at);
            for (uint64_t i = 0; folded && i < first_count; i++)
                if (xyz[3 * i] > fold_at) {
                    /* the far third folded back over the middle, two thicknesses above */
                    xyz[3 * i] = 2.0f * fold_at - xyz[3 * i];
                    xyz[3 * i + 1] += 2.0f * c->thickness;
                }
            REQUIRE_OK(cvk_sim_write_positions(sim, xyz, n, &err), err);
        }
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        if (phase == 0)
            REQUIRE_OK(cvk_sim_read_positions(sim, flat_xyz, n, &err), err);
        REQUIRE_OK(cvk_collide_save_snapshot(sim, snap, &err), err);
        const float* seen = (const float*)(snap + sizeof(cvk_gpu_frame));
        const uint32_t* kept = (const uint32_t*)(snap + sizeof(cvk_gpu_frame) + 16u * (size_t)n);
        const uint32_t* lists = (const uint32_t*)(snap + bytes - 4u * (CVK_LIST_HEADER + 2u * (size_t)n));
        cvk_collide_patch_activity(c, b, seen, -0.01, active);
        cvk_collide_patch_activity(c, b, seen, 0.01, maybe);
        uint32_t on = 0, expected = 0, undecided = 0, disagree = 0, with = 0, culled_pairs = 0;
        double farthest = 0.0;
        for (uint32_t a = 0; a < c->patch_count; a++)
            on += active[a];
        uint32_t listed = lists[CVK_LIST_SEARCH_COUNT];
        for (uint32_t p = 0; p < b->free_count; p++) {
            bool in = false;
            for (uint32_t i = 0; i < listed; i++)
                in = in || lists[CVK_LIST_HEADER + i] == p;
            uint32_t own = c->patch_table[p];
            bool must = own == CVK_NO_PATCH || active[own], may = own == CVK_NO_PATCH || maybe[own];
            expected += must;
            undecided += must != may;
            disagree += must == may && in != must;
            with += kept[(size_t)CVK_CONTACTS_PER_PARTICLE * p] != CVK_NO_CONTACT;
            if (in || may)
                continue;
            /* Left out: what lies within the detection radius is the cloth's own surface
               around p (near at rest: a flat surface is a height field over its axis). */
            const float* xp = &seen[4 * (size_t)p];
            for (uint32_t t = 0; t < b->triangle_count; t++) {
                uint32_t v[3];
                for (int m = 0; m < 3; m++)
                    v[m] = b->internal_of[b->triangles[3 * (size_t)t + m]];
                if (point_triangle_distance(xp, &seen[4 * (size_t)v[0]], &seen[4 * (size_t)v[1]],
                                            &seen[4 * (size_t)v[2]]) >= c->detect_radius)
                    continue;
                double nearest = INFINITY;
                for (int m = 0; m < 3; m++) {
                    const float* r0 = &c->rest_xyz[4 * (size_t)p];
                    const float* r1 = &c->rest_xyz[4 * (size_t)v[m]];
                    double d[3] = {(double)r0[0] - r1[0], (double)r0[1] - r1[1], (double)r0[2] - r1[2]};
                    nearest = fmin(nearest, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
                }
                culled_pairs++;
                farthest = fmax(farthest, nearest);
            }
        }
        if (folded) {
            CHECK(culled_pairs > 0 && farthest <= 2.0 * c->detect_radius, "folded cloths: of %u "
                  "pairs within the detection radius left out by the patches, one is %.4g m apart "
                  "at rest (more than 2 radii, %.4g m)", culled_pairs, farthest,
                  2.0 * (double)c->detect_radius);
            printf("folded cloths: %u pairs within the radius left out, at most %.4g m apart at rest "
                   "(radius %.4g m)\n", culled_pairs, farthest, (double)c->detect_radius);
        }
        CHECK(disagree == 0, "%s cloths: %u particles listed to search or not against the host's "
              "patch activity", name, disagree);
        CHECK(lists[CVK_LIST_CONTACT_COUNT] == with, "%s cloths: %u particles listed with "
              "candidates, %u have them", name, lists[CVK_LIST_CONTACT_COUNT], with);
        if (phase == 0)
            CHECK(on == 0 && listed == 0 && with == 0, "a flat cloth: %u of %u patches active, "
                  "%u particles searched, %u with candidates", on, c->patch_count, listed, with);
        else
            CHECK(on > 0 && listed > 0 && with > 0 && listed < b->free_count, "%s cloths: "
                  "%u of %u patches active, %u of %u particles searched, %u with candidates",
                  name, on, c->patch_count, listed, b->free_count, with);
        printf("%s cloths: %u of %u patches active, %u particles searched (%u on a threshold), "
               "%u with candidates\n", name, on, c->patch_count, listed, undecided, with);
    }
    free(xyz);
    free(flat_xyz);
    free(active);
    free(maybe);
    free(snap);
    cvk_sim_destroy(sim);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    test_flat_patches(ctx);
    test_rest_and_motion(ctx);
    test_snapshot(ctx);
    test_candidates(ctx);
    return harness_finish(ctx);
}
