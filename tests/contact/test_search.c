/* The adaptive search for cloth-contact candidates (lib/contact/collide.h): a cloth at rest stops
   searching, so does one moving fast as one, cloths approaching fast search at every substep, positions written from the host make the
   next substep search, and a snapshot carries the contact state so that stepping on from it
   gives the same bits as never having stopped; on folded cloths, the candidates a search keeps
   against a brute force over every particle–triangle pair. */
#include <math.h>
#include <string.h>

#include "contact/collide.h"
#include "harness.h"
#include "contact/intersect.h"
#include "shared/layout.h"
#include "sim/sim.h"

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
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
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
    REQUIRE_OK(harness_sim_create(ctx, &scene, &pair, &err), err);
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
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
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
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
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
    uint64_t marked_total = 0;
    uint64_t ties = 0, tie_order = 0;
    uint64_t listed_particles = 0, culled_particles = 0;
    for (uint32_t seed = 1; seed <= 4; seed++) {
        /* seeds 3 and 4: a second folded cloth among the first one's layers */
        cvk_cloth_desc cloths[2] = {flat_cloth(n, size, 0.5f), flat_cloth(n, size, 0.7f)};
        uint32_t cloth_count = seed > 2 ? 2 : 1;
        cvk_error err;
        cvk_sim* sim = self_contact_sim(ctx, cloths, cloth_count);
        const cvk_collide* c = sim->collide;
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
                /* a pair the untangling step marked (test_collide) has the side the particle
                   is not on, or had when marked: its side is not judged here */
                bool marked = (mine[k] & CVK_UNTANGLE_PAIR) != 0u;
                uint32_t t = (mine[k] & ~CVK_UNTANGLE_PAIR) >> 1, side = mine[k] & 1u;
                marked_total += marked;
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
                if (k > 0 && d == previous && ((mine[k - 1] & ~CVK_UNTANGLE_PAIR) >> 1) > t)
                    tie_order++;
                ties += k > 0 && d == previous;
                previous = d;
                bool twice = false;
                for (uint32_t m = 0; m < k; m++)
                    twice |= ((mine[m] & ~CVK_UNTANGLE_PAIR) >> 1) == t;
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
                bool bad_side = !marked && fabs(height) > slack && (height < 0.0) != (side == 1u);
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
                    found |= ((mine[k] & ~CVK_UNTANGLE_PAIR) >> 1) == t;
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
    printf("candidates: %llu pairs within the radius, %llu kept (%llu marked by the untangling "
           "step), %llu full lists, %llu ties\n", (unsigned long long)pairs,
           (unsigned long long)kept_total, (unsigned long long)marked_total,
           (unsigned long long)full, (unsigned long long)ties);
}

/* ---- edge pairs (collision.edges) ---- */

/* Nearest points of segments p1q1 and p2q2 in double (Ericson 2005, §5.1.9): the distance, and
   where they are on each (s, t), the points in c1, c2. */
static double segment_distance(const double p1[3], const double q1[3], const double p2[3],
                               const double q2[3], double* s, double* t, double c1[3], double c2[3])
{
    double d1[3], d2[3], r[3];
    for (int k = 0; k < 3; k++) {
        d1[k] = q1[k] - p1[k];
        d2[k] = q2[k] - p2[k];
        r[k] = p1[k] - p2[k];
    }
    double a = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
    double e = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2];
    double f = d2[0] * r[0] + d2[1] * r[1] + d2[2] * r[2];
    double c = d1[0] * r[0] + d1[1] * r[1] + d1[2] * r[2];
    double b = d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2];
    double denom = a * e - b * b;
    *s = denom > 0.0 ? fmin(fmax((b * f - c * e) / denom, 0.0), 1.0) : 0.0;
    *t = (b * *s + f) / e;
    if (*t < 0.0) {
        *t = 0.0;
        *s = fmin(fmax(-c / a, 0.0), 1.0);
    } else if (*t > 1.0) {
        *t = 1.0;
        *s = fmin(fmax((b - c) / a, 0.0), 1.0);
    }
    double d2sum = 0.0;
    for (int k = 0; k < 3; k++) {
        c1[k] = p1[k] + *s * d1[k];
        c2[k] = p2[k] + *t * d2[k];
        d2sum += (c1[k] - c2[k]) * (c1[k] - c2[k]);
    }
    return sqrt(d2sum);
}

/* Edge pairs' exclusion (collide.h: wider than the triangles'). */
static bool rest_near(const cvk_collide* c, uint32_t p, uint32_t q)
{
    const float* rp = &c->rest_xyz[4 * (size_t)p];
    const float* rq = &c->rest_xyz[4 * (size_t)q];
    float d[3] = {rp[0] - rq[0], rp[1] - rq[1], rp[2] - rq[2]};
    return rp[3] == rq[3] &&
           d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < c->edge_exclusion * c->edge_exclusion;
}

static double distance3(const float* a, const float* b)
{
    double d[3] = {(double)a[0] - b[0], (double)a[1] - b[1], (double)a[2] - b[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

/* Whether some triangle runs the edge from u to v (internal indices). */
static bool runs(const uint32_t* tri, uint32_t tc, uint32_t u, uint32_t v)
{
    for (uint32_t t = 0; t < tc; t++)
        for (int k = 0; k < 3; k++)
            if (tri[3 * t + k] == u && tri[3 * t + (k + 1) % 3] == v)
                return true;
    return false;
}

/* Two cloths, the second turned 35° about the vertical, lying within the detection radius of
   each other with every particle jittered: their edges cross at many angles. After a search,
   every edge pair within the radius that the search promises (one of the two a border, an end
   of the other edge within the hash's reach of the particle, lib/contact/collide_passes.c; neither near
   the other at rest) is
   among the particle's kept candidates, or it keeps as many edge pairs as it can
   (CVK_EDGE_CONTACTS_PER_PARTICLE), all at most that far; every kept edge pair
   is such a pair, once, with the side its own edge is on. Distances on the host in double. */
static void test_edge_candidates(cvk_context* ctx)
{
    const uint32_t n = 16, K = CVK_CONTACTS_PER_PARTICLE;
    const float size = 0.4f;
    uint64_t pairs = 0, kept_edges = 0, missing = 0, wrong = 0, found_pairs = 0;
    for (uint32_t seed = 1; seed <= 2; seed++) {
        cvk_cloth_desc cloths[2] = {flat_cloth(n, size, 0.5f), flat_cloth(n, size, 0.5f)};
        cvk_scene_desc scene = cvk_default_scene_desc();
        scene.cloths = cloths;
        scene.cloth_count = 2;
        scene.substeps = 1;
        scene.collision.self = true;
        scene.collision.edges = true;
        /* Made on top of each other; the positions below replace the start. */
        scene.collision.allow_intersecting_start = true;
        cvk_error err;
        cvk_sim* sim = NULL;
        REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
        const cvk_collide* c = sim->collide;
        const cvk_build* b = &sim->build;
        uint32_t state = seed * 104729u;
        float* xyz = malloc(3 * 2 * (size_t)n * n * sizeof(float));
        double turn = 35.0 * 3.14159265358979 / 180.0;
        for (uint32_t cl = 0; cl < 2; cl++)
            for (uint32_t i = 0; i < n * n; i++) {
                float u = size * (float)(i % n) / (float)(n - 1) - 0.5f * size;
                float v = size * (float)(i / n) / (float)(n - 1) - 0.5f * size;
                float* x = &xyz[3 * ((size_t)cl * n * n + i)];
                x[0] = cl ? (float)(cos(turn) * u - sin(turn) * v) : u;
                x[2] = cl ? (float)(sin(turn) * u + cos(turn) * v) : v;
                x[1] = 0.5f + (cl ? uniform(&state, 1.4f, 2.2f) * c->thickness : 0.0f) +
                       uniform(&state, -0.3f, 0.3f) * c->thickness;
                x[0] += uniform(&state, -0.25f, 0.25f) * c->thickness;
                x[2] += uniform(&state, -0.25f, 0.25f) * c->thickness;
            }
        REQUIRE_OK(cvk_sim_write_positions(sim, xyz, 2 * (uint64_t)n * n, &err), err);
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        uint64_t bytes = cvk_collide_snapshot_size(sim);
        unsigned char* snap = malloc(bytes);
        REQUIRE_OK(cvk_collide_save_snapshot(sim, snap, &err), err);
        const float* seen = (const float*)(snap + sizeof(cvk_gpu_frame));
        const uint32_t* kept = (const uint32_t*)(snap + sizeof(cvk_gpu_frame) +
                                                 16u * (size_t)b->particle_count);
        double radius = (double)CVK_DETECT_RADIUS_THICKNESSES(c->detect_every) * c->thickness;
        double reach = (double)c->hash.cell_size, slack = 1e-5 * radius;
        uint32_t tc = b->triangle_count;
        uint32_t* tri = malloc(3 * (size_t)tc * sizeof(uint32_t));
        for (size_t i = 0; i < 3 * (size_t)tc; i++)
            tri[i] = b->internal_of[b->triangles[i]];
        for (uint32_t p = 0; p < b->free_count; p++) {
            const uint32_t* mine = &kept[(size_t)K * p];
            uint32_t count = 0;
            while (count < K && mine[count] != CVK_NO_CONTACT)
                count++;
            double farthest_edge = 0.0;
            uint32_t edge_count = 0;
            /* p's own edge slots: its triangles in index order (the device's table) */
            uint32_t own_end[64], own_count = 0;
            bool own_border[64];
            for (uint32_t t = 0; t < tc; t++)
                for (int k = 0; k < 3; k++)
                    if (tri[3 * t + k] == p) {
                        uint32_t next = tri[3 * t + (k + 1) % 3], prev = tri[3 * t + (k + 2) % 3];
                        own_border[own_count] = !runs(tri, tc, next, p);
                        own_end[own_count++] = next;
                        own_border[own_count] = true;
                        own_end[own_count++] = runs(tri, tc, p, prev) ? UINT32_MAX : prev;
                    }
            double xp[3] = {seen[4 * (size_t)p], seen[4 * (size_t)p + 1], seen[4 * (size_t)p + 2]};
            for (uint32_t k = 0; k < count; k++) {
                uint32_t e = mine[k];
                if ((e & CVK_EDGE_PAIR) == 0u) { /* a triangle: test_candidates */
                    wrong += edge_count > 0; /* triangles first, then edge pairs */
                    continue;
                }
                kept_edges++;
                uint32_t slot = (e & ~CVK_EDGE_PAIR) >> CVK_EDGE_OWN_SHIFT;
                uint32_t f = (e >> 1) & ((1u << (CVK_EDGE_OWN_SHIFT - 1)) - 1u), t = f / 3, j = f % 3;
                if (slot >= own_count || own_end[slot] == UINT32_MAX || t >= tc) {
                    wrong++;
                    continue;
                }
                uint32_t r = own_end[slot], fa = tri[3 * t + j], fb = tri[3 * t + (j + 1) % 3];
                double xr[3], xa[3], xb[3], s, u, c1[3], c2[3];
                for (int m = 0; m < 3; m++) {
                    xr[m] = seen[4 * (size_t)r + m];
                    xa[m] = seen[4 * (size_t)fa + m];
                    xb[m] = seen[4 * (size_t)fb + m];
                }
                double d = segment_distance(xp, xr, xa, xb, &s, &u, c1, c2);
                farthest_edge = fmax(farthest_edge, d);
                edge_count++;
                bool f_border = !runs(tri, tc, fb, fa);
                bool canonical = (fa < fb || f_border) && (f_border || own_border[slot]);
                bool excluded = fa == p || fa == r || fb == p || fb == r || rest_near(c, p, fa) ||
                                rest_near(c, p, fb) || rest_near(c, r, fa) || rest_near(c, r, fb);
                bool twice = false;
                for (uint32_t m = 0; m < k; m++)
                    twice |= (mine[m] >> 1) == (e >> 1);
                double m_[3] = {(xr[1] - xp[1]) * (xb[2] - xa[2]) - (xr[2] - xp[2]) * (xb[1] - xa[1]),
                                (xr[2] - xp[2]) * (xb[0] - xa[0]) - (xr[0] - xp[0]) * (xb[2] - xa[2]),
                                (xr[0] - xp[0]) * (xb[1] - xa[1]) - (xr[1] - xp[1]) * (xb[0] - xa[0])};
                double along = (c1[0] - c2[0]) * m_[0] + (c1[1] - c2[1]) * m_[1] + (c1[2] - c2[2]) * m_[2];
                double scale = sqrt(m_[0] * m_[0] + m_[1] * m_[1] + m_[2] * m_[2]);
                bool bad_side = fabs(along) > slack * scale && (along < 0.0) != ((e & 1u) == 1u);
                if (d >= radius + slack || !canonical || excluded || twice || bad_side)
                    wrong++;
            }
            for (uint32_t slot = 0; slot < own_count; slot++) {
                uint32_t r = own_end[slot];
                if (r == UINT32_MAX)
                    continue;
                double xr[3] = {seen[4 * (size_t)r], seen[4 * (size_t)r + 1], seen[4 * (size_t)r + 2]};
                for (uint32_t t = 0; t < tc; t++)
                    for (uint32_t j = 0; j < 3; j++) {
                        uint32_t fa = tri[3 * t + j], fb = tri[3 * t + (j + 1) % 3];
                        bool f_border = !runs(tri, tc, fb, fa);
                        if (!(fa < fb || f_border) || !(f_border || own_border[slot]))
                            continue; /* each edge once; one of the two a border */
                        if (fa == p || fa == r || fb == p || fb == r || rest_near(c, p, fa) ||
                            rest_near(c, p, fb) || rest_near(c, r, fa) || rest_near(c, r, fb))
                            continue;
                        /* the promise: an end of the other edge within reach of p */
                        if (distance3(&seen[4 * (size_t)p], &seen[4 * (size_t)fa]) >= reach * (1.0 - 1e-5) &&
                            distance3(&seen[4 * (size_t)p], &seen[4 * (size_t)fb]) >= reach * (1.0 - 1e-5))
                            continue;
                        double xa[3], xb[3], s, u, c1[3], c2[3];
                        for (int m = 0; m < 3; m++) {
                            xa[m] = seen[4 * (size_t)fa + m];
                            xb[m] = seen[4 * (size_t)fb + m];
                        }
                        double d = segment_distance(xp, xr, xa, xb, &s, &u, c1, c2);
                        if (d >= radius - slack)
                            continue;
                        pairs++;
                        uint32_t want = CVK_EDGE_PAIR | (slot << CVK_EDGE_OWN_SHIFT) | ((3u * t + j) << 1);
                        bool found = false;
                        for (uint32_t k = 0; k < count; k++)
                            found |= (mine[k] >> 1) == (want >> 1);
                        found_pairs += found;
                        if (!found && !(edge_count == CVK_EDGE_CONTACTS_PER_PARTICLE &&
                                        farthest_edge <= d + slack))
                            missing++;
                    }
            }
        }
        free(tri);
        free(snap);
        free(xyz);
        cvk_sim_destroy(sim);
    }
    printf("edge candidates: %llu pairs within the radius, %llu of them kept (%llu kept in all), "
           "the others behind full lists\n", (unsigned long long)pairs,
           (unsigned long long)found_pairs, (unsigned long long)kept_edges);
    CHECK(pairs > 1000 && found_pairs > 1000, "%llu edge pairs within the radius, %llu found: "
          "the cloths did not meet", (unsigned long long)pairs, (unsigned long long)found_pairs);
    CHECK(missing == 0, "%llu of %llu edge pairs within the detection radius are neither kept "
          "nor beyond a full list of nearer ones", (unsigned long long)missing,
          (unsigned long long)pairs);
    CHECK(wrong == 0, "%llu kept edge pairs are too far, not the edge's own entry, of two "
          "interior edges, near at rest, kept twice, on the wrong side or before a triangle",
          (unsigned long long)wrong);
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
    const cvk_collide* c = sim->collide;
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
    test_edge_candidates(ctx);
    return harness_finish(ctx);
}
