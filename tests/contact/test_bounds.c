/* Detection's bounds against a host brute force: three cloths stacked closer than the contact
   radius, 200 m from the origin, dropped over a box, and eight stacked 3 mm apart, whose edges
   have more near them than the edges' distance pass measures. After a detection each particle's bound on
   the device (where detection saw it and its bound, lib/contact/collide.h) must be
   0.45 (d - f): d the nearest distance, computed here in double over every pair — the particle
   against every triangle not around it, every triangle around it against every vertex not on it,
   its edges against every edge sharing no end — at most the radius; f the gap floor, the larger
   of 0.001 thicknesses and 2^-19 of its largest coordinate (shared/layout.h), which 200 m from
   the origin is 3.8e-4 m, far above what float distances there can be off by. And the floor
   under a squeeze: a small cloth whose every particle is attached, driven down through a
   pinned one, stops at the floor — each detection lets it close 0.45 of the gap left, which
   without a floor reached the float rounding of the positions and touched. And the count of
   particles held back by their bounds (cvk_sim_stats.contact_held: ended a substep past 0.9
   of their bound): none in a free fall, whose common motion the shift takes; a 20 x 20 cloth
   draped over a sphere is held in under 0.1 % of its particle-substeps in substeps of 1/480 s,
   and in over 5 % in one substep of 1/60 s, where it cannot fall faster than about a bound a
   substep past the part the sphere stops (docs/limits.md). */
#include "contact/collide.h"
#include "harness.h"
#include "shared/layout.h"
#include "sim/sim.h"

#define OFFSET 200.0f /* m along x: the gap floor is the coordinate's there */

static double dot3(const double* a, const double* b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void sub3(const double* a, const double* b, double* out)
{
    for (int k = 0; k < 3; k++)
        out[k] = a[k] - b[k];
}

static double dist3(const double* a, const double* b)
{
    double d[3];
    sub3(a, b, d);
    return sqrt(dot3(d, d));
}

static double clamp01(double x)
{
    return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x);
}

/* The distance between segments p1q1 and p2q2 (Ericson 5.1.9): the minimum over the interior
   solution and the four end-to-segment distances, so a near-parallel pair is exact too. */
static double point_segment(const double* p, const double* a, const double* b)
{
    double ab[3], ap[3], q[3];
    sub3(b, a, ab);
    sub3(p, a, ap);
    double len2 = dot3(ab, ab), t = len2 > 0.0 ? clamp01(dot3(ap, ab) / len2) : 0.0;
    for (int k = 0; k < 3; k++)
        q[k] = a[k] + t * ab[k];
    return dist3(p, q);
}

static void cross3(const double* a, const double* b, double* out)
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* The distance from p to triangle abc, worked out here rather than by the library's routine
   (lib/contact/intersect.c): the distance to the plane where p projects inside the triangle
   (on the inner side of each edge), else the nearest of the three edges. */
static double point_triangle(const double* p, const double* a, const double* b, const double* c)
{
    const double* v[3] = {a, b, c};
    double ab[3], ac[3], n[3];
    sub3(b, a, ab);
    sub3(c, a, ac);
    cross3(ab, ac, n);
    double len2 = dot3(n, n);
    bool inside = len2 > 0.0;
    for (int k = 0; k < 3 && inside; k++) {
        double edge[3], to_p[3], side[3];
        sub3(v[(k + 1) % 3], v[k], edge);
        sub3(p, v[k], to_p);
        cross3(edge, to_p, side);
        inside = dot3(side, n) >= 0.0;
    }
    if (inside) {
        double ap[3];
        sub3(p, a, ap);
        return fabs(dot3(ap, n)) / sqrt(len2);
    }
    return fmin(point_segment(p, a, b), fmin(point_segment(p, b, c), point_segment(p, c, a)));
}

static double segment_segment(const double* p1, const double* q1, const double* p2,
                              const double* q2)
{
    double best = fmin(fmin(point_segment(p1, p2, q2), point_segment(q1, p2, q2)),
                       fmin(point_segment(p2, p1, q1), point_segment(q2, p1, q1)));
    double d1[3], d2[3], r[3];
    sub3(q1, p1, d1);
    sub3(q2, p2, d2);
    sub3(p1, p2, r);
    double a = dot3(d1, d1), e = dot3(d2, d2), b = dot3(d1, d2), c = dot3(d1, r), f = dot3(d2, r);
    double denom = a * e - b * b;
    if (denom > 1e-12 * a * e) {
        double s = (b * f - c * e) / denom, t = (a * f - b * c) / denom;
        if (s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0) {
            double x1[3], x2[3];
            for (int k = 0; k < 3; k++) {
                x1[k] = p1[k] + s * d1[k];
                x2[k] = p2[k] + t * d2[k];
            }
            best = fmin(best, dist3(x1, x2));
        }
    }
    return best;
}

typedef struct mesh {
    uint32_t n, triangle_count, edge_count;
    uint32_t* tri;   /* 3 internal indices per triangle */
    uint32_t* edges; /* 2 internal indices per edge, each edge once */
} mesh;

/* The triangles in internal order and their edges, each once. */
static mesh make_mesh(const cvk_build* b)
{
    mesh m = {b->particle_count, b->triangle_count, 0, malloc(12u * b->triangle_count),
              malloc(24u * b->triangle_count)};
    for (uint32_t t = 0; t < m.triangle_count; t++) {
        for (int k = 0; k < 3; k++)
            m.tri[3 * t + k] = b->internal_of[b->triangles[3 * (size_t)t + k]];
        for (int k = 0; k < 3; k++) {
            uint32_t u = m.tri[3 * t + k], v = m.tri[3 * t + (k + 1) % 3];
            uint32_t lo = u < v ? u : v, hi = u < v ? v : u;
            bool seen = false;
            for (uint32_t e = 0; e < m.edge_count && !seen; e++)
                seen = m.edges[2 * e] == lo && m.edges[2 * e + 1] == hi;
            if (!seen) {
                m.edges[2 * m.edge_count] = lo;
                m.edges[2 * m.edge_count + 1] = hi;
                m.edge_count++;
            }
        }
    }
    return m;
}

/* Each particle's nearest distance as detection defines it, at most `radius` (d, n entries). */
static void nearest_distances(const mesh* m, const double* x, double radius, double* d)
{
    double* edge = malloc(sizeof *edge * m->edge_count);
    for (uint32_t p = 0; p < m->n; p++)
        d[p] = radius;
    for (uint32_t e = 0; e < m->edge_count; e++)
        edge[e] = radius;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t* c = &m->tri[3 * t];
        for (uint32_t p = 0; p < m->n; p++) {
            if (p == c[0] || p == c[1] || p == c[2])
                continue;
            double dist = point_triangle(&x[3 * p], &x[3 * c[0]], &x[3 * c[1]], &x[3 * c[2]]);
            d[p] = fmin(d[p], dist);
            for (int k = 0; k < 3; k++)
                d[c[k]] = fmin(d[c[k]], dist);
        }
    }
    for (uint32_t e = 0; e < m->edge_count; e++) {
        const uint32_t* a = &m->edges[2 * e];
        for (uint32_t f = e + 1; f < m->edge_count; f++) {
            const uint32_t* b = &m->edges[2 * f];
            if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1])
                continue;
            double dist = segment_segment(&x[3 * a[0]], &x[3 * a[1]], &x[3 * b[0]], &x[3 * b[1]]);
            edge[e] = fmin(edge[e], dist);
            edge[f] = fmin(edge[f], dist);
        }
    }
    for (uint32_t e = 0; e < m->edge_count; e++)
        for (int k = 0; k < 2; k++)
            d[m->edges[2 * e + k]] = fmin(d[m->edges[2 * e + k]], edge[e]);
    free(edge);
}

/* How many edges the last detection's distance pass sent to the walking pass (shared/
   layout.h: CVK_CELLS_WALK). */
static uint32_t edges_walked(cvk_context* ctx, cvk_sim* sim)
{
    uint32_t header[CVK_CELLS_HEADER];
    cvk_error err;
    REQUIRE_OK(cvk_buffer_download(ctx, &sim->device.submitter, sim->device.transfer_cmd,
                                   &sim->collide->cells, header, sizeof header, &err), err);
    return header[CVK_CELLS_WALK + 3];
}

/* `layers` cloths `apart` m above one another (the radius is 2.5 cm); crowded: so many within
   the radius that edges have more to measure than the distance pass keeps, and the walking
   pass (contact_edges.comp phase 5) measures the rest. */
static void test_bounds_against_host(cvk_context* ctx, int layers, float apart, bool crowded)
{
    cvk_cloth_desc cloths[8];
    for (int i = 0; i < layers; i++) {
        cloths[i] = cvk_default_cloth_desc();
        cloths[i].grid[0] = cloths[i].grid[1] = 12;
        cloths[i].size[0] = cloths[i].size[1] = 0.4f;
        cloths[i].origin[0] = OFFSET - 0.2f + 0.011f * (float)i;
        cloths[i].origin[1] = 0.43f + apart * (float)i;
        cloths[i].origin[2] = -0.2f - 0.007f * (float)i;
    }
    cvk_collider_desc box = cvk_default_collider_desc();
    box.type = CVK_COLLIDER_BOX;
    box.center[0] = OFFSET;
    box.center[1] = 0.2f;
    box.half_extents[0] = box.half_extents[2] = 0.12f;
    box.half_extents[1] = 0.2f;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = (uint32_t)layers;
    scene.colliders = &box;
    scene.collider_count = 1;
    scene.dt = 1.0f / 120.0f;
    scene.substeps = 1;
    scene.collision.self = true;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    mesh m = make_mesh(&sim->build);
    float* seen = malloc(16u * m.n);
    double* x = malloc(sizeof *x * 3 * m.n);
    double* d = malloc(sizeof *d * m.n);
    double radius = sim->collide->radius, thickness = sim->collide->thickness;
    const uint32_t checked[3] = {1, 20, 40};
    for (uint32_t f = 1, next = 0; f <= (crowded ? 1u : 40u); f++) {
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        if (f != checked[next])
            continue;
        next++;
        if (crowded) { /* the first substep detects */
            uint32_t walked = edges_walked(ctx, sim);
            printf("%d layers %.0f mm apart: %u edges walked\n", layers, 1000.0 * apart, walked);
            CHECK(walked > 0, "%d layers %g m apart: no edge walked: the case tests little",
                  layers, (double)apart);
        }
        REQUIRE_OK(cvk_buffer_download(ctx, &sim->device.submitter, sim->device.transfer_cmd,
                                       &sim->collide->searched, seen, 16u * m.n, &err), err);
        for (uint32_t p = 0; p < m.n; p++)
            for (int k = 0; k < 3; k++)
                x[3 * p + k] = seen[4 * p + k];
        nearest_distances(&m, x, radius, d);
        uint32_t wrong = 0, near = 0, worst_at = 0;
        double worst = 0.0, least_floor = INFINITY;
        for (uint32_t p = 0; p < m.n; p++) {
            double largest = fmax(fabs(x[3 * p]), fmax(fabs(x[3 * p + 1]), fabs(x[3 * p + 2])));
            double floor_gap = fmax(CVK_GAP_FLOOR_THICKNESSES * thickness,
                                    CVK_GAP_FLOOR_RELATIVE * largest);
            least_floor = fmin(least_floor, floor_gap);
            double expected = CVK_BOUND_GAMMA * fmax(d[p] - floor_gap, 0.0);
            double off = fabs(seen[4 * p + 3] - expected);
            near += d[p] < radius ? 1u : 0u;
            wrong += off > 1e-5 + 1e-4 * d[p] ? 1u : 0u;
            if (off > worst) {
                worst = off;
                worst_at = p;
            }
        }
        printf("frame %u: %u of %u particles nearer than the radius to something, bounds off "
               "the host's by at most %.3g m (particle %u)\n", f, near, m.n, worst, worst_at);
        CHECK(wrong == 0, "frame %u: %u bounds differ from 0.45 (d - f), the most by %g m "
              "(particle %u: %g on the device, d %g)", f, wrong, worst, worst_at,
              (double)seen[4 * worst_at + 3], d[worst_at]);
        CHECK(near > m.n / 4, "frame %u: only %u particles near another cloth: the case tests "
              "little", f, near);
        /* The tolerance must be far below what the floor takes off, or the check could not
           tell a bound without it. */
        CHECK(CVK_BOUND_GAMMA * least_floor > 10.0 * (1e-5 + 1e-4 * radius),
              "the floor (%g m) is within the tolerance", least_floor);
    }
    free(seen);
    free(x);
    free(d);
    free(m.tri);
    free(m.edges);
    cvk_sim_destroy(sim);
}

/* The nearest distance between cloth `a`'s and cloth `b`'s primitives (vertex against
   triangle both ways, edge against edge), x in internal order. */
static double cloths_apart(const cvk_build* build, const mesh* m, const double* x, uint32_t a,
                           uint32_t b)
{
    double best = INFINITY;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t* c = &m->tri[3 * t];
        uint32_t of = cvk_build_cloth_of(build, c[0]);
        if (of != a && of != b)
            continue;
        for (uint32_t p = 0; p < m->n; p++)
            if (cvk_build_cloth_of(build, p) == (of == a ? b : a))
                best = fmin(best, point_triangle(&x[3 * p], &x[3 * c[0]], &x[3 * c[1]],
                                                 &x[3 * c[2]]));
    }
    for (uint32_t e = 0; e < m->edge_count; e++) {
        const uint32_t* u = &m->edges[2 * e];
        if (cvk_build_cloth_of(build, u[0]) != a)
            continue;
        for (uint32_t f = 0; f < m->edge_count; f++) {
            const uint32_t* v = &m->edges[2 * f];
            if (cvk_build_cloth_of(build, v[0]) == b)
                best = fmin(best, segment_segment(&x[3 * u[0]], &x[3 * u[1]], &x[3 * v[0]],
                                                  &x[3 * v[1]]));
        }
    }
    return best;
}

static void test_squeezed_to_the_floor(cvk_context* ctx, cvk_method method)
{
    uint32_t pins[25][2]; /* every particle of the 5 x 5 cloth */
    for (uint32_t k = 0; k < 25; k++) {
        pins[k][0] = k % 5;
        pins[k][1] = k / 5;
    }
    cvk_cloth_desc cloths[2] = {cvk_default_cloth_desc(), cvk_default_cloth_desc()};
    cloths[0].grid[0] = cloths[0].grid[1] = 5; /* 5 cm apart: the thickness 2 cm */
    cloths[0].size[0] = cloths[0].size[1] = 0.2f;
    memcpy(cloths[0].origin, (float[3]){-0.1f, 0.5f, -0.1f}, sizeof cloths[0].origin);
    cloths[0].pins = (const uint32_t(*)[2])pins;
    cloths[0].pin_count = 25;
    cloths[1].grid[0] = cloths[1].grid[1] = 3;
    cloths[1].size[0] = cloths[1].size[1] = 0.08f;
    memcpy(cloths[1].origin, (float[3]){-0.027f, 0.512f, -0.033f}, sizeof cloths[1].origin);
    static const cvk_keyframe down[2] = {
        {.time = 0.0f, .rotation = {1, 0, 0, 0}},
        {.time = 0.5f, .translation = {0.0f, -0.05f, 0.0f}, .rotation = {1, 0, 0, 0}},
    };
    cvk_attachment_desc held = cvk_default_attachment_desc();
    held.cloth = 1;
    held.use_pin_box = true;
    held.pin_box = (cvk_box3){{-1.0f, 0.0f, -1.0f}, {1.0f, 1.0f, 1.0f}};
    held.motion = (cvk_motion){.keyframes = down, .keyframe_count = 2};
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = 2;
    scene.attachments = &held;
    scene.attachment_count = 1;
    scene.collision.self = true;
    scene.solver.method = method;
    if (method == CVK_METHOD_IMPLICIT)
        scene.solver.linear = CVK_LINEAR_CG;
    const char* name = method == CVK_METHOD_IMPLICIT ? "implicit cg" : "pd rbgs";
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    mesh m = make_mesh(&sim->build);
    float* xf = malloc(16u * m.n);
    double* x = malloc(sizeof *x * 3 * m.n);
    double floor_gap = fmax(CVK_GAP_FLOOR_THICKNESSES * sim->collide->thickness,
                            CVK_GAP_FLOOR_RELATIVE * 0.5);
    double least = INFINITY;
    uint64_t pairs = 0, most = 0;
    for (uint32_t f = 1; f <= 60; f++) {
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        REQUIRE_OK(cvk_buffer_download(ctx, &sim->device.submitter, sim->device.transfer_cmd,
                                       &sim->positions, xf, 16u * m.n, &err), err);
        for (uint32_t p = 0; p < m.n; p++)
            for (int k = 0; k < 3; k++)
                x[3 * p + k] = xf[4 * p + k];
        least = fmin(least, cloths_apart(&sim->build, &m, x, 0, 1));
        REQUIRE_OK(cvk_sim_count_intersections(sim, &pairs, &err), err);
        most = pairs > most ? pairs : most;
    }
    printf("%s, a held cloth driven through a pinned one: at least %.3g m apart (the floor %.3g "
           "m), at most %llu intersecting pairs\n", name, least, floor_gap,
           (unsigned long long)most);
    CHECK(most == 0, "%s: %llu intersecting pairs", name, (unsigned long long)most);
    CHECK(least >= 0.5 * floor_gap, "%s: the cloths came %g m apart, under half the floor %g m",
          name, least, floor_gap);
    CHECK(least < 2.0 * floor_gap, "%s: the cloths stayed %g m apart, not squeezed to the floor "
          "(%g m): the case tests nothing", name, least, floor_gap);
    free(xf);
    free(x);
    free(m.tri);
    free(m.edges);
    cvk_sim_destroy(sim);
}

/* The fraction of a run's free particle-substeps held back by their bounds, and its
   intersecting pairs at the end. */
static double held_fraction(cvk_context* ctx, const cvk_scene_desc* scene, uint32_t frames,
                            uint64_t* pairs)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, frames, &err), err);
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    *pairs = st.intersecting_pairs;
    /* every substep but the first (it follows the state's upload) is counted */
    double total = (double)sim->build.free_count * (frames * scene->substeps - 1);
    CHECK(fabs(st.contact_held_fraction - (double)st.contact_held / total) <= 1e-12,
          "held fraction %.17g, %llu held of %.0f particle-substeps", st.contact_held_fraction,
          (unsigned long long)st.contact_held, total);
    cvk_sim_destroy(sim);
    return st.contact_held_fraction;
}

static void test_held(cvk_context* ctx)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = 20;
    cloth.size[0] = cloth.size[1] = 1.2f;
    memcpy(cloth.origin, (float[3]){-0.6f, 0.8f, -0.6f}, sizeof cloth.origin);
    cloth.pin_count = 0;
    cloth.mass = 0.144f;
    cloth.stiffness.shear = 1e6f;
    cloth.stiffness.bend = 2e4f;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.collision.self = true;
    scene.dt = 1.0f / 60.0f;
    scene.substeps = 1;
    uint64_t pairs;
    double falling = held_fraction(ctx, &scene, 30, &pairs);
    printf("a cloth falling freely, 30 frames of one substep: %.3g %% of its particle-substeps "
           "held at their bounds\n", 100.0 * falling);
    CHECK(falling == 0.0, "a free fall held %.3g %% of its particle-substeps at their bounds",
          100.0 * falling);
    cvk_collider_desc ball = cvk_default_collider_desc();
    ball.type = CVK_COLLIDER_SPHERE;
    ball.radius = 0.3f;
    ball.center[1] = 0.3f;
    scene.colliders = &ball;
    scene.collider_count = 1;
    scene.dt = 1.0f / 480.0f;
    scene.substeps = 8;
    double fine = held_fraction(ctx, &scene, 60, &pairs);
    CHECK(pairs == 0, "%llu intersecting pairs in 8 substeps", (unsigned long long)pairs);
    scene.dt = 1.0f / 60.0f;
    scene.substeps = 1;
    double coarse = held_fraction(ctx, &scene, 60, &pairs);
    CHECK(pairs == 0, "%llu intersecting pairs in one substep", (unsigned long long)pairs);
    printf("a 20 x 20 cloth draped over a sphere, 60 frames: %.3g %% of its particle-substeps "
           "held at their bounds in 8 substeps, %.3g %% in one\n", 100.0 * fine, 100.0 * coarse);
    CHECK(fine < 1e-3, "in 8 substeps %.3g %% held, not under 0.1 %%", 100.0 * fine);
    CHECK(coarse > 0.05, "in one substep %.3g %% held, not over 5 %%", 100.0 * coarse);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    test_bounds_against_host(ctx, 3, 0.02f, false);
    test_bounds_against_host(ctx, 8, 0.003f, true);
    test_squeezed_to_the_floor(ctx, CVK_METHOD_PD);
    test_squeezed_to_the_floor(ctx, CVK_METHOD_IMPLICIT);
    test_held(ctx);
    return harness_finish(ctx);
}
