/* The exact intersection check and the host contact figures:
   - the triangle–triangle predicate on hand-made cases (crossing, touching at a vertex, an
     edge through an edge, coplanar overlap and disjoint, parallel and near-parallel, collapsed
     triangles), each in all 72 vertex orders, orientations and argument orders;
   - the predicate against an independent test (an edge of one triangle through the other) on
     random pairs in general position;
   - the grid count against the O(n²) count on random triangle soups with shared vertices and
     torn triangles, several seeds; a flat cloth (level and tilted) has no pair, a cloth folded
     through itself has some; the first pair (cvk_first_intersecting_pair) is the O(n²) loop's
     first, and a 160 x 160 cloth is checked in well under a second;
   - through the library: a flat cloth has cvk_sim_count_intersections == 0, and the contact
     figures of cloths over a plane and over each other against direct counts. */
#include "harness.h"
#include "contact/intersect.h"
#include "sim/sim.h"

/* ---- the predicate on hand-made cases ---------------------------------------------------- */

typedef struct tri_case {
    const char* name;
    float a[9], b[9];
    bool expected;
    bool exact_only; /* touching away from shared coordinates: after the rotation below,
                        rounding to float moves the contact off by an ulp either way */
} tri_case;

#define BASE {0, 0, 0, 2, 0, 0, 0, 2, 0} /* in z = 0, legs along x and y, hypotenuse x + y = 2 */

static const tri_case cases[] = {
    {"crossing (an edge of b through a's interior)", BASE, {0.5f, 0.5f, -1, 0.5f, 0.5f, 1, 0.5f, 3, 0}, true, false},
    {"crossing, b moved clear along x", BASE, {2.5f, 0.5f, -1, 2.5f, 0.5f, 1, 2.5f, 3, 0}, false, false},
    {"a vertex of b touching a's face", BASE, {0.5f, 0.5f, 0, 1, 1, 1, 0, 1, 1}, true, true},
    {"a vertex of b 1e-4 above a's face", BASE, {0.5f, 0.5f, 1e-4f, 1, 1, 1, 0, 1, 1}, false, false},
    {"a vertex of b on a's vertex", BASE, {0, 0, 0, -1, 0, 1, 0, -1, 1}, true, false},
    {"an edge of b through an edge of a", BASE, {1, -1, 1, 1, 1, -1, 1, -2, -2}, true, true},
    {"an edge of b passing 0.01 beside an edge of a", BASE,
     {1, -1.01f, 1, 1, 0.99f, -1, 1, -2.01f, -2}, false, false},
    {"an edge of b lying in a's face", BASE, {0.5f, 0.5f, 0, 1, 0.5f, 0, 0.7f, 0.6f, 1}, true, true},
    {"coplanar, overlapping", BASE, {0.5f, 0.5f, 0, 3, 0.5f, 0, 0.5f, 3, 0}, true, false},
    {"coplanar, b inside a", BASE, {0.2f, 0.2f, 0, 0.6f, 0.2f, 0, 0.2f, 0.6f, 0}, true, false},
    {"coplanar, disjoint", BASE, {2, 2, 0, 4, 2, 0, 2, 4, 0}, false, false},
    {"coplanar, touching at a vertex", BASE, {2, 0, 0, 3, 0, 0, 3, 1, 0}, true, false},
    {"coplanar, touching along an edge", BASE, {2, 0, 0, 0, 2, 0, 2, 2, 0}, true, false},
    {"coplanar, 1e-3 apart across the hypotenuse", BASE, {2, 0.001f, 0, 0.001f, 2, 0, 2, 2, 0}, false, false},
    {"parallel, 1e-3 apart", BASE, {0, 0, 1e-3f, 2, 0, 1e-3f, 0, 2, 1e-3f}, false, false},
    {"near-parallel, crossing", BASE, {0, 0, 1e-3f, 2, 0, 1e-3f, 0, 2, -1e-3f}, true, false},
    {"near-parallel, 1e-6 clear", BASE, {0, 0, 1e-3f, 2, 0, 1e-3f, 0, 2, 1e-6f}, false, false},
    {"b collapsed to a segment through a", BASE, {0.5f, 0.5f, -1, 0.5f, 0.5f, 1, 0.5f, 0.5f, 0.5f}, true, false},
    {"b collapsed to a segment beside a", BASE, {3, 3, -1, 3, 3, 1, 3, 3, 0.5f}, false, false},
    {"b collapsed to a point on a", BASE, {0.5f, 0.5f, 0, 0.5f, 0.5f, 0, 0.5f, 0.5f, 0}, true, true},
};

/* Triangle t with its vertices turned by `turn` and, when `flip`, in the opposite order. */
static void arrange(const float t[9], int turn, bool flip, float out[9])
{
    static const int order[2][3] = {{0, 1, 2}, {0, 2, 1}};
    for (int k = 0; k < 3; k++) {
        int src = order[flip][(k + turn) % 3];
        memcpy(&out[3 * k], &t[3 * src], 3 * sizeof(float));
    }
}

static void check_case(const tri_case* c, const char* suffix, const float a[9], const float b[9])
{
    int wrong = 0, variants = 0;
    for (int v = 0; v < 72; v++) {
        float x[9], y[9];
        arrange(a, v % 3, (v / 3) % 2, x);
        arrange(b, (v / 6) % 3, (v / 18) % 2, y);
        bool got = v / 36 ? cvk_triangles_intersect(y, x) : cvk_triangles_intersect(x, y);
        wrong += got != c->expected;
        variants++;
    }
    CHECK(wrong == 0, "%s%s: %d of %d vertex orders say %s", c->name, suffix, wrong, variants,
          c->expected ? "apart" : "intersecting");
}

/* Every case as given, and rotated by a rotation that makes no coordinate plane special.
   Its coordinates are then rounded to float, as in a simulated cloth: the coplanar cases
   become pairs tilted by about 1e-8 against each other (orientations of ±1e-8, measured in
   exact arithmetic), so the predicate must find their grazing crossings; touching survives
   only where the triangles touch at coordinates they share, which round alike. */
static void hand_made_cases(void)
{
    const double ax[3] = {0.36, 0.48, 0.8}; /* unit */
    const double angle = 0.7, c = cos(angle), s = sin(angle);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        check_case(&cases[i], "", cases[i].a, cases[i].b);
        if (cases[i].exact_only)
            continue;
        float ra[9], rb[9];
        for (int k = 0; k < 3; k++) {
            const float* in[2] = {&cases[i].a[3 * k], &cases[i].b[3 * k]};
            float* out[2] = {&ra[3 * k], &rb[3 * k]};
            for (int t = 0; t < 2; t++) {
                double p[3] = {in[t][0], in[t][1], in[t][2]};
                double d = ax[0] * p[0] + ax[1] * p[1] + ax[2] * p[2];
                double cr[3] = {ax[1] * p[2] - ax[2] * p[1], ax[2] * p[0] - ax[0] * p[2],
                                ax[0] * p[1] - ax[1] * p[0]};
                for (int j = 0; j < 3; j++) /* Rodrigues */
                    out[t][j] = (float)(p[j] * c + cr[j] * s + ax[j] * d * (1 - c));
            }
        }
        check_case(&cases[i], " (rotated)", ra, rb);
    }
}

/* ---- against an independent test on random pairs ---------------------------------------- */

static double volume(const float* a, const float* b, const float* c, const float* d)
{
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = (double)b[k] - a[k];
        v[k] = (double)c[k] - a[k];
        w[k] = (double)d[k] - a[k];
    }
    return w[0] * (u[1] * v[2] - u[2] * v[1]) + w[1] * (u[2] * v[0] - u[0] * v[2]) +
           w[2] * (u[0] * v[1] - u[1] * v[0]);
}

/* Segment pq crosses triangle t (general position: no zero volumes). */
static bool segment_crosses(const float* p, const float* q, const float* t)
{
    if ((volume(&t[0], &t[3], &t[6], p) > 0) == (volume(&t[0], &t[3], &t[6], q) > 0))
        return false;
    bool s0 = volume(p, q, &t[0], &t[3]) > 0, s1 = volume(p, q, &t[3], &t[6]) > 0;
    bool s2 = volume(p, q, &t[6], &t[0]) > 0;
    return s0 == s1 && s1 == s2;
}

/* Two triangles in general position meet exactly when an edge of one crosses the other. */
static bool oracle(const float* a, const float* b)
{
    for (int i = 0; i < 3; i++) {
        if (segment_crosses(&a[3 * i], &a[3 * ((i + 1) % 3)], b))
            return true;
        if (segment_crosses(&b[3 * i], &b[3 * ((i + 1) % 3)], a))
            return true;
    }
    return false;
}

static void random_pairs(void)
{
    harness_rng rng = {12345};
    int wrong = 0, meeting = 0;
    const int pairs = 50000;
    for (int i = 0; i < pairs; i++) {
        float a[9], b[9];
        for (int k = 0; k < 9; k++) {
            a[k] = (float)harness_uniform(&rng, 0.0, 1.0);
            b[k] = (float)harness_uniform(&rng, 0.0, 1.0);
        }
        bool expected = oracle(a, b);
        meeting += expected;
        if (cvk_triangles_intersect(a, b) != expected && wrong++ < 3)
            fprintf(stderr, "pair %d: predicate says %d, edge test %d\n", i, !expected, expected);
    }
    CHECK(wrong == 0, "%d of %d random pairs disagree with the edge test", wrong, pairs);
    CHECK(meeting > pairs / 10 && meeting < pairs - pairs / 10,
          "only %d of %d random pairs meet: the comparison would prove little", meeting, pairs);
    printf("random pairs: %d of %d meet, %d disagreements\n", meeting, pairs, wrong);
}

/* ---- the count ---------------------------------------------------------------------------- */

static bool shares(const uint32_t* u, const uint32_t* v)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (u[i] == v[j])
                return true;
    return false;
}

/* Whether triangles i and j of the soup intersect (neither torn, no shared vertex). */
static bool pair_intersects(const float* xyz, const uint32_t* tri, uint32_t i, uint32_t j)
{
    const uint32_t* u = &tri[3 * (size_t)i];
    const uint32_t* v = &tri[3 * (size_t)j];
    if ((u[0] == u[1] && u[1] == u[2]) || (v[0] == v[1] && v[1] == v[2]) || shares(u, v))
        return false;
    float a[9], b[9];
    for (int k = 0; k < 3; k++) {
        memcpy(&a[3 * k], &xyz[3 * (size_t)u[k]], 3 * sizeof(float));
        memcpy(&b[3 * k], &xyz[3 * (size_t)v[k]], 3 * sizeof(float));
    }
    return cvk_triangles_intersect(a, b);
}

static uint64_t brute_force(const float* xyz, const uint32_t* tri, uint32_t count)
{
    uint64_t pairs = 0;
    for (uint32_t i = 0; i < count; i++)
        for (uint32_t j = i + 1; j < count; j++)
            pairs += pair_intersects(xyz, tri, i, j);
    return pairs;
}

/* The lowest intersecting pair by the O(n²) loop: the first i, then the first j. */
static bool brute_force_first(const float* xyz, const uint32_t* tri, uint32_t count, uint32_t* first,
                              uint32_t* second)
{
    for (uint32_t i = 0; i < count; i++)
        for (uint32_t j = i + 1; j < count; j++)
            if (pair_intersects(xyz, tri, i, j)) {
                *first = i;
                *second = j;
                return true;
            }
    return false;
}

static cvk_intersecting_pair first_pair(const float* xyz, uint32_t vertices, const uint32_t* tri,
                                        uint32_t triangles)
{
    cvk_error err;
    cvk_intersecting_pair pair;
    REQUIRE_OK(cvk_first_intersecting_pair(xyz, vertices, tri, NULL, triangles, &pair, &err), err);
    return pair;
}

static uint64_t count(const float* xyz, uint32_t vertices, const uint32_t* tri, uint32_t triangles)
{
    cvk_error err;
    uint64_t pairs = 0;
    REQUIRE_OK(cvk_count_intersecting_pairs(xyz, vertices, tri, NULL, triangles, &pairs, &err), err);
    return pairs;
}

/* Small triangles in a box, a third of them sharing a vertex with the one before, some torn,
   a few large ones across the box. */
static void random_soup(uint32_t seed)
{
    enum { TRIANGLES = 1500 };
    harness_rng rng = {seed};
    float* xyz = malloc(9 * TRIANGLES * sizeof(float));
    uint32_t* tri = malloc(3 * TRIANGLES * sizeof(uint32_t));
    uint32_t vertices = 0;
    for (uint32_t t = 0; t < TRIANGLES; t++) {
        double size = t % 100 == 0 ? 0.5 : 0.08;
        double centre[3];
        for (int c = 0; c < 3; c++)
            centre[c] = harness_uniform(&rng, 0.0, 1.0);
        for (int k = 0; k < 3; k++) {
            if (k == 0 && t > 0 && harness_next(&rng) % 3 == 0) {
                tri[3 * t] = tri[3 * (t - 1) + 1]; /* shared with the previous triangle */
                continue;
            }
            for (int c = 0; c < 3; c++)
                xyz[3 * vertices + c] = (float)(centre[c] + harness_uniform(&rng, -size, size));
            tri[3 * t + k] = vertices++;
        }
        if (harness_next(&rng) % 50 == 0)
            tri[3 * t + 1] = tri[3 * t + 2] = tri[3 * t]; /* torn */
    }
    uint64_t expected = brute_force(xyz, tri, TRIANGLES), got = count(xyz, vertices, tri, TRIANGLES);
    CHECK(got == expected, "seed %u: the grid counts %llu pairs, the O(n^2) loop %llu", seed,
          (unsigned long long)got, (unsigned long long)expected);
    CHECK(expected > 100, "seed %u: only %llu intersecting pairs: the soup proves little", seed,
          (unsigned long long)expected);
    printf("soup, seed %u: %llu intersecting pairs (O(n^2): %llu)\n", seed,
           (unsigned long long)got, (unsigned long long)expected);
    uint32_t first = 0, second = 0;
    bool found = brute_force_first(xyz, tri, TRIANGLES, &first, &second);
    cvk_intersecting_pair pair = first_pair(xyz, vertices, tri, TRIANGLES);
    CHECK(pair.found == found && pair.first == first && pair.second == second,
          "seed %u: the grid's first pair is %s(%u, %u), the O(n^2) loop's %s(%u, %u)", seed,
          pair.found ? "" : "none ", pair.first, pair.second, found ? "" : "none ", first, second);
    free(xyz);
    free(tri);
}

static void shared_vertex_excluded(void)
{
    /* Two triangles crossing each other; with a vertex index in common they are neighbours
       (not counted), with that vertex duplicated they are a pair. */
    const float xyz[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5f, 0.5f, -1, 0.5f, 3, 0, 0, 0, 0};
    const uint32_t shared[] = {0, 1, 2, 0, 3, 4};
    const uint32_t apart[] = {0, 1, 2, 5, 3, 4};
    uint64_t with_shared = count(xyz, 6, shared, 2), duplicated = count(xyz, 6, apart, 2);
    CHECK(with_shared == 0, "two triangles sharing a vertex counted as %llu pairs",
          (unsigned long long)with_shared);
    CHECK(duplicated == 1, "the same triangles without the shared index: %llu pairs, not 1",
          (unsigned long long)duplicated);
}

/* An n × n grid in user order, two triangles per cell; shape(u, v, out) places the vertex
   at (u, v) ∈ [0, 1]². */
typedef void (*shape_fn)(double u, double v, float out[3]);

/* n x n particles on `shape`, two triangles per quad. */
static uint32_t grid_soup(uint32_t n, shape_fn shape, float** out_xyz, uint32_t** out_tri)
{
    float* xyz = malloc(3 * (size_t)n * n * sizeof(float));
    uint32_t cells = (n - 1) * (n - 1);
    uint32_t* tri = malloc(6 * (size_t)cells * sizeof(uint32_t));
    for (uint32_t j = 0; j < n; j++)
        for (uint32_t i = 0; i < n; i++)
            shape(i / (double)(n - 1), j / (double)(n - 1), &xyz[3 * ((size_t)j * n + i)]);
    uint32_t t = 0;
    for (uint32_t j = 0; j + 1 < n; j++)
        for (uint32_t i = 0; i + 1 < n; i++) {
            uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
            uint32_t quad[6] = {a, b, d, a, d, c};
            memcpy(&tri[3 * (size_t)t], quad, sizeof quad);
            t += 2;
        }
    *out_xyz = xyz;
    *out_tri = tri;
    return t;
}

static uint64_t grid_count(uint32_t n, shape_fn shape, double* ms)
{
    float* xyz;
    uint32_t* tri;
    uint32_t t = grid_soup(n, shape, &xyz, &tri);
    double start = cvk_now_ms();
    uint64_t pairs = count(xyz, n * n, tri, t);
    *ms = cvk_now_ms() - start;
    free(xyz);
    free(tri);
    return pairs;
}

static void level(double u, double v, float out[3])
{
    out[0] = (float)u;
    out[1] = 0.5f;
    out[2] = (float)v;
}

/* In a plane through no coordinate axis, rounded to float. */
static void tilted(double u, double v, float out[3])
{
    out[0] = (float)(0.6 * u + 0.48 * v + 0.1);
    out[1] = (float)(0.8 * u - 0.36 * v + 0.3);
    out[2] = (float)(0.8 * v - 0.2);
}

/* Half flat; the other half folded back over it, rippling up and down through it. */
static void folded(double u, double v, float out[3])
{
    out[0] = (float)(u <= 0.5 ? u : 1.0 - u);
    out[1] = (float)(u <= 0.5 ? 0.0 : 0.1 * sin(4.0 * 3.14159265358979 * (u - 0.5)));
    out[2] = (float)v;
}

static void grids(void)
{
    double ms;
    uint64_t flat = grid_count(100, level, &ms);
    CHECK(flat == 0, "a flat 100 x 100 cloth has %llu intersecting pairs", (unsigned long long)flat);
    printf("flat 100 x 100 cloth (19602 triangles): %llu pairs in %.1f ms\n",
           (unsigned long long)flat, ms);
    uint64_t slanted = grid_count(100, tilted, &ms);
    CHECK(slanted == 0, "a tilted flat 100 x 100 cloth has %llu intersecting pairs",
          (unsigned long long)slanted);
    printf("tilted 100 x 100 cloth: %llu pairs in %.1f ms\n", (unsigned long long)slanted, ms);
    uint64_t fold = grid_count(41, folded, &ms);
    CHECK(fold > 0, "a cloth folded through itself has no intersecting pair");
    printf("folded 41 x 41 cloth: %llu pairs in %.1f ms\n", (unsigned long long)fold, ms);
}

/* The clean-start check's cost on the 160 x 160 drape cloth (contact-drape.json's largest):
   near-linear through the grid, so well under a second. */
static void first_pair_cost(void)
{
    float* xyz;
    uint32_t* tri;
    uint32_t t = grid_soup(160, tilted, &xyz, &tri);
    double start = cvk_now_ms();
    cvk_intersecting_pair pair = first_pair(xyz, 160 * 160, tri, t);
    double ms = cvk_now_ms() - start;
    CHECK(!pair.found, "a tilted flat 160 x 160 cloth intersects itself (triangles %u and %u)",
          pair.first, pair.second);
    CHECK(ms < 1000.0, "the first pair of a 160 x 160 cloth took %.0f ms", ms);
    printf("first pair of a flat 160 x 160 cloth (%u triangles): none, in %.1f ms\n", t, ms);
    free(xyz);
    free(tri);
    t = grid_soup(41, folded, &xyz, &tri);
    uint32_t first = 0, second = 0;
    bool found = brute_force_first(xyz, tri, t, &first, &second);
    pair = first_pair(xyz, 41 * 41, tri, t);
    CHECK(found && pair.found && pair.first == first && pair.second == second,
          "folded 41 x 41 cloth: the grid's first pair is (%u, %u), the O(n^2) loop's (%u, %u)",
          pair.first, pair.second, first, second);
    free(xyz);
    free(tri);
}

/* ---- through the library ------------------------------------------------------------------ */

static cvk_cloth_desc flat_cloth(uint32_t n, float size, float y)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = n;
    cloth.size[0] = cloth.size[1] = size;
    cloth.origin[0] = -0.5f * size;
    cloth.origin[1] = y;
    cloth.origin[2] = -0.5f * size;
    return cloth;
}

static void flat_sim(cvk_context* ctx)
{
    cvk_cloth_desc cloth = flat_cloth(30, 1.0f, 0.0f);
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 2, &err), err);
    uint64_t pairs = 99;
    REQUIRE_OK(cvk_sim_count_intersections(sim, &pairs, &err), err);
    CHECK(pairs == 0, "a falling flat cloth has %llu intersecting pairs", (unsigned long long)pairs);
    cvk_sim_destroy(sim);
}

/* Distance from p to the closed triangle t (9 floats), another way than the library's: the
   plane's distance when p projects inside, else the nearest edge. */
static double segment_distance(const double* p, const double* a, const double* b)
{
    double ab[3], ap[3];
    for (int c = 0; c < 3; c++) {
        ab[c] = b[c] - a[c];
        ap[c] = p[c] - a[c];
    }
    double len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    double s = len2 > 0 ? (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / len2 : 0.0;
    s = fmin(1.0, fmax(0.0, s));
    double d2 = 0.0;
    for (int c = 0; c < 3; c++)
        d2 += (ap[c] - s * ab[c]) * (ap[c] - s * ab[c]);
    return sqrt(d2);
}

static double point_triangle_distance(const double* p, double t[3][3])
{
    double e1[3], e2[3], n[3], w[3];
    for (int c = 0; c < 3; c++) {
        e1[c] = t[1][c] - t[0][c];
        e2[c] = t[2][c] - t[0][c];
        w[c] = p[c] - t[0][c];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    double best = fmin(segment_distance(p, t[0], t[1]),
                       fmin(segment_distance(p, t[1], t[2]), segment_distance(p, t[2], t[0])));
    if (n2 == 0.0)
        return best;
    /* Barycentric coordinates of the projection. */
    double d11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    double d12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    double d22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    double w1 = w[0] * e1[0] + w[1] * e1[1] + w[2] * e1[2];
    double w2 = w[0] * e2[0] + w[1] * e2[1] + w[2] * e2[2];
    double det = d11 * d22 - d12 * d12;
    double s = (d22 * w1 - d12 * w2) / det, r = (d11 * w2 - d12 * w1) / det;
    if (s >= 0 && r >= 0 && s + r <= 1)
        best = fmin(best, fabs(w[0] * n[0] + w[1] * n[1] + w[2] * n[2]) / sqrt(n2));
    return best;
}

/* Free particles within `thickness` of a triangle they are not a corner of nor joined by a
   spring to a corner of, by looking at every pair. */
static uint64_t self_contacts_directly(const cvk_build* b, const float* xyz, double thickness)
{
    size_t n = b->particle_count;
    bool* joined = calloc(n * n, sizeof(bool));
    for (uint32_t s = 0; s < b->spring_count; s++) {
        joined[(size_t)b->springs[s].a * n + b->springs[s].b] = true;
        joined[(size_t)b->springs[s].b * n + b->springs[s].a] = true;
    }
    uint64_t contacts = 0;
    for (uint32_t t = 0; t < b->triangle_count; t++) {
        uint32_t v[3];
        double corner[3][3];
        for (int k = 0; k < 3; k++) {
            v[k] = b->internal_of[b->triangles[3 * (size_t)t + k]];
            for (int c = 0; c < 3; c++)
                corner[k][c] = xyz[3 * (size_t)v[k] + c];
        }
        for (uint32_t p = 0; p < b->free_count; p++) {
            bool near = false;
            for (int k = 0; k < 3; k++)
                near = near || p == v[k] || joined[(size_t)p * n + v[k]];
            double x[3] = {xyz[3 * (size_t)p], xyz[3 * (size_t)p + 1], xyz[3 * (size_t)p + 2]};
            if (!near && point_triangle_distance(x, corner) < thickness)
                contacts++;
        }
    }
    free(joined);
    return contacts;
}

/* Two cloths 3 mm apart over a plane, 5 and 8 mm above it, thickness 1 cm: every particle
   touches the plane, none is inside it until one cloth is moved 3 mm below, and the
   particle–triangle pairs between the cloths match a direct count. */
static void contact_figures(cvk_context* ctx)
{
    const float thickness = 0.01f;
    cvk_cloth_desc cloths[2] = {flat_cloth(16, 0.5f, 0.005f), flat_cloth(16, 0.5f, 0.008f)};
    cloths[1].origin[0] += 0.013f; /* particles of one above the triangles' insides of the other */
    cvk_collider_desc plane = cvk_default_collider_desc();
    plane.type = CVK_COLLIDER_PLANE;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = 2;
    scene.colliders = &plane;
    scene.collider_count = 1;
    scene.collision.thickness = thickness;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    const cvk_build* b = &sim->build;
    /* The figures are the host's own: measure the pairs between cloths without asking the
       device to resolve them. */
    sim->collide->self = true;
    size_t n = b->particle_count;
    float* xyz = malloc(3 * n * sizeof(float));
    memcpy(xyz, b->position, 3 * n * sizeof(float));
    cvk_sim_stats st;
    REQUIRE_OK(cvk_sim_contact_stats(sim, xyz, &st, &err), err);
    CHECK(st.collider_contacts == b->free_count, "%llu of %u particles touch the plane",
          (unsigned long long)st.collider_contacts, b->free_count);
    CHECK(st.max_penetration == 0.0, "deepest inside the plane: %g m, not 0", st.max_penetration);
    CHECK(st.intersecting_pairs == 0, "two parallel cloths: %llu intersecting pairs",
          (unsigned long long)st.intersecting_pairs);
    uint64_t expected = self_contacts_directly(b, xyz, thickness);
    CHECK(st.self_contacts == expected && expected > 0,
          "%llu particle-triangle contacts; looking at every pair finds %llu",
          (unsigned long long)st.self_contacts, (unsigned long long)expected);
    printf("contacts: %llu with the plane, %llu particle-triangle (direct: %llu)\n",
           (unsigned long long)st.collider_contacts, (unsigned long long)st.self_contacts,
           (unsigned long long)expected);
    for (uint32_t p = 0; p < b->particle_count; p++)
        if (b->user_of[p] < cloths[0].grid[0] * cloths[0].grid[1])
            xyz[3 * (size_t)p + 1] = -0.003f;
    REQUIRE_OK(cvk_sim_contact_stats(sim, xyz, &st, &err), err);
    CHECK(fabs(st.max_penetration - 0.003) < 1e-6, "one cloth 3 mm below the plane: deepest %g m",
          st.max_penetration);
    CHECK(st.collider_contacts == b->free_count, "%llu of %u particles touch the plane",
          (unsigned long long)st.collider_contacts, b->free_count);
    sim->collide->self = false;
    sim->collide->colliding = false;
    REQUIRE_OK(cvk_sim_contact_stats(sim, xyz, &st, &err), err);
    CHECK(st.collider_contacts == 0 && st.self_contacts == 0 && st.max_penetration == 0.0,
          "without collision the figures are %llu, %llu, %g", (unsigned long long)st.collider_contacts,
          (unsigned long long)st.self_contacts, st.max_penetration);
    sim->collide->colliding = true;
    free(xyz);
    cvk_sim_destroy(sim);
}

/* Groups (the scene's instances): two crossing triangles count only in one group, and the
   first pair is the lowest of one group. */
static void groups_kept_apart(void)
{
    /* triangles 0 and 1 cross (one flat, one upright through it), 2 is 0 again */
    const float xyz[] = {-1, 0, -1, 1, 0, -1, 0, 0, 1,       /* flat in y = 0 */
                         0, -1, 0, 0, 1, 0, 0.2f, 0, -0.5f,  /* upright through it */
                         -1, 0, -1, 1, 0, -1, 0, 0, 1};
    const uint32_t tri[] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    cvk_error err;
    uint64_t pairs = 0;
    const uint32_t apart[] = {0, 1, 1}, together[] = {0, 0, 1};
    REQUIRE_OK(cvk_count_intersecting_pairs(xyz, 9, tri, NULL, 3, &pairs, &err), err);
    CHECK(pairs == 3, "one group: %llu pairs, expected 3 (0-1, 0-2, 1-2)", (unsigned long long)pairs);
    REQUIRE_OK(cvk_count_intersecting_pairs(xyz, 9, tri, apart, 3, &pairs, &err), err);
    CHECK(pairs == 1, "groups 0, 1, 1: %llu pairs, expected 1 (1-2)", (unsigned long long)pairs);
    REQUIRE_OK(cvk_count_intersecting_pairs(xyz, 9, tri, together, 3, &pairs, &err), err);
    CHECK(pairs == 1, "groups 0, 0, 1: %llu pairs, expected 1 (0-1)", (unsigned long long)pairs);
    cvk_intersecting_pair pair;
    REQUIRE_OK(cvk_first_intersecting_pair(xyz, 9, tri, apart, 3, &pair, &err), err);
    CHECK(pair.found && pair.first == 1 && pair.second == 2, "groups 0, 1, 1: first pair %u-%u",
          pair.first, pair.second);
}

int main(void)
{
    groups_kept_apart();
    hand_made_cases();
    random_pairs();
    shared_vertex_excluded();
    for (uint32_t seed = 1; seed <= 5; seed++)
        random_soup(seed * 2654435761u);
    grids();
    first_pair_cost();
    cvk_context* ctx = harness_context();
    flat_sim(ctx);
    contact_figures(ctx);
    return harness_finish(ctx);
}
