/* Triangle–triangle intersection, and the count of intersecting pairs in a triangle soup.

   The predicate is Guigue and Devillers' ("Fast and robust triangle-triangle overlap test using
   orientation predicates", JGT 8(1), 2003): it decides from the signs of 4 × 4 determinants
   alone, never constructing the line of intersection, so every decision is a sign and the
   only question is whether that sign is right. Each sign is the determinant of differences
   of the float inputs evaluated in double, with Shewchuk's static error bound for orient3d
   and orient2d ("Adaptive precision floating-point arithmetic and fast robust geometric
   predicates", 1997): a determinant within its bound of zero is taken as zero, i.e. points
   coplanar to within rounding count as coplanar and a pair touching to within rounding
   counts as touching. Outside that band (about 1e-15 of the coordinates' magnitude, far
   below the 6e-8 of a float) every sign is the exact sign for the float inputs, so the answer
   is the exact one.

   Zero orientations are where published code goes wrong, so they are handled explicitly:
   - both triangles in one plane: a 2D test in the coordinate plane where they are largest
     (closed: an edge of one meets an edge of the other, or a vertex of one lies in the other);
   - one triangle collapsed to a segment or a point (its normal zero to within rounding):
     it is the union of its edges, each tested against the other triangle;
   - a vertex or an edge in the other's plane: the canonical permutation of the paper, with
     a zero on the side of the lone vertex's partners (≤ 0), which is what makes touching
     count.
   Two triangles both collapsed to segments are reported as not intersecting (cloth never
   makes them: a triangle that thin has already been torn or inverted through a neighbour).

   The count puts every triangle's box in the cells of a uniform grid it overlaps, sorts the
   (cell, triangle) entries, and tests the pairs of each cell whose boxes overlap; a pair in
   several common cells is tested in one of them only (the cell of the low corner of the two
   boxes' intersection), so it is counted once. */
#include "contact/intersect.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* ---- signs with a static error bound ---------------------------------------------------- */

#define EPS 1.1102230246251565e-16 /* 2^-53 */
#define ORIENT3D_BOUND ((7.0 + 56.0 * EPS) * EPS)
#define ORIENT2D_BOUND ((3.0 + 16.0 * EPS) * EPS)

typedef double vec3[3];
typedef double vec2[2];

static int sign_of(double det, double bound)
{
    if (det > bound)
        return 1;
    if (det < -bound)
        return -1;
    return 0;
}

/* Which side of the plane of (a, b, c) d is on: 1 in front (where (b − a) × (c − a) points),
   −1 behind, 0 on it to within rounding. It is −orient3d(a, b, c, d) in Shewchuk's terms
   (det[a − d, b − d, c − d]), evaluated and bounded as he does. */
static int side(const double* a, const double* b, const double* c, const double* d)
{
    double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
    double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
    double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
    double bc = bdx * cdy - bdy * cdx, ca = cdx * ady - cdy * adx, ab = adx * bdy - ady * bdx;
    double det = adz * bc + bdz * ca + cdz * ab;
    double permanent = (fabs(bdx * cdy) + fabs(bdy * cdx)) * fabs(adz) +
                       (fabs(cdx * ady) + fabs(cdy * adx)) * fabs(bdz) +
                       (fabs(adx * bdy) + fabs(ady * bdx)) * fabs(cdz);
    return -sign_of(det, ORIENT3D_BOUND * permanent);
}

/* Sign of the 2D cross product (b − a) × (c − a): positive when a, b, c turn left. */
static int turn(const double* a, const double* b, const double* c)
{
    double left = (b[0] - a[0]) * (c[1] - a[1]), right = (b[1] - a[1]) * (c[0] - a[0]);
    return sign_of(left - right, ORIENT2D_BOUND * (fabs(left) + fabs(right)));
}

/* ---- two dimensions, closed sets, either orientation, degenerate triangles allowed ------ */

static bool between(const double* a, const double* b, const double* p)
{
    return fmin(a[0], b[0]) <= p[0] && p[0] <= fmax(a[0], b[0]) && fmin(a[1], b[1]) <= p[1] &&
           p[1] <= fmax(a[1], b[1]);
}

static bool segments_meet_2d(const double* p, const double* q, const double* r, const double* s)
{
    int d1 = turn(p, q, r), d2 = turn(p, q, s), d3 = turn(r, s, p), d4 = turn(r, s, q);
    if (d1 * d2 < 0 && d3 * d4 < 0)
        return true;
    return (d1 == 0 && between(p, q, r)) || (d2 == 0 && between(p, q, s)) ||
           (d3 == 0 && between(r, s, p)) || (d4 == 0 && between(r, s, q));
}

/* p inside the closed triangle t; a triangle of zero area contains nothing here (its edges
   are tested as segments). */
static bool inside_2d(vec2 t[3], const double* p)
{
    if (turn(t[0], t[1], t[2]) == 0)
        return false;
    int s0 = turn(t[0], t[1], p), s1 = turn(t[1], t[2], p), s2 = turn(t[2], t[0], p);
    return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

static bool triangles_meet_2d(vec2 a[3], vec2 b[3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (segments_meet_2d(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]))
                return true;
    return inside_2d(b, a[0]) || inside_2d(a, b[0]);
}

/* Drops the coordinate along which `normal` is largest: the projection keeps the most area. */
static void project(vec3 t[3], const double normal[3], vec2 out[3])
{
    double nx = fabs(normal[0]), ny = fabs(normal[1]), nz = fabs(normal[2]);
    int u = 0, v = 1;
    if (nx >= ny && nx >= nz) {
        u = 1;
        v = 2;
    } else if (ny >= nz) {
        u = 0;
        v = 2;
    }
    for (int k = 0; k < 3; k++) {
        out[k][0] = t[k][u];
        out[k][1] = t[k][v];
    }
}

static bool coplanar_meet(vec3 a[3], vec3 b[3], const double normal[3])
{
    vec2 a2[3], b2[3];
    project(a, normal, a2);
    project(b, normal, b2);
    return triangles_meet_2d(a2, b2);
}

/* ---- three dimensions ------------------------------------------------------------------- */

static void normal_of(vec3 t[3], double n[3])
{
    double e1[3] = {t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]};
    double e2[3] = {t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]};
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

/* Collapsed to a segment or a point: every coordinate projection has zero area, to within
   rounding. */
static bool collapsed(vec3 t[3])
{
    static const int axes[3][2] = {{1, 2}, {2, 0}, {0, 1}};
    for (int k = 0; k < 3; k++) {
        vec2 p[3];
        for (int i = 0; i < 3; i++) {
            p[i][0] = t[i][axes[k][0]];
            p[i][1] = t[i][axes[k][1]];
        }
        if (turn(p[0], p[1], p[2]) != 0)
            return false;
    }
    return true;
}

/* Segment pq against a triangle t that is not collapsed. */
static bool segment_meets(const double* p, const double* q, vec3 t[3])
{
    int sp = side(t[0], t[1], t[2], p), sq = side(t[0], t[1], t[2], q);
    if (sp * sq > 0)
        return false;
    if (sp == 0 && sq == 0) {
        double n[3];
        normal_of(t, n);
        vec3 seg[3] = {{p[0], p[1], p[2]}, {q[0], q[1], q[2]}, {q[0], q[1], q[2]}};
        return coplanar_meet(seg, t, n);
    }
    /* The line through p and q crosses the plane inside t when it passes every edge on the
       same side (or on it). */
    int s0 = side(p, q, t[0], t[1]), s1 = side(p, q, t[1], t[2]), s2 = side(p, q, t[2], t[0]);
    return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

static bool edges_meet(vec3 segment_like[3], vec3 t[3])
{
    for (int i = 0; i < 3; i++)
        if (segment_meets(segment_like[i], segment_like[(i + 1) % 3], t))
            return true;
    return false;
}

/* The paper's final test, once p1 is alone on the front of triangle 2 (q1, r1 behind it or
   on it) and p2 alone on the front of triangle 1: the two intervals the triangles cut on the
   planes' common line overlap. */
static bool intervals_overlap(const double* p1, const double* q1, const double* r1,
                              const double* p2, const double* q2, const double* r2)
{
    return side(q1, p2, p1, q2) <= 0 && side(p1, p2, r1, r2) <= 0;
}

/* Index of the vertex alone on its side and whether the other triangle must be flipped so
   that this vertex is on the front: signs s are not all equal and not all zero. The lone
   vertex is strictly on one side with the others on the other side or on the plane, or on
   the plane with both others strictly on one side. */
static int lone_vertex(const int s[3], bool* flip)
{
    for (int i = 0; i < 3; i++) {
        int a = s[(i + 1) % 3], b = s[(i + 2) % 3];
        if (s[i] != 0 && a != s[i] && b != s[i]) {
            *flip = s[i] < 0;
            return i;
        }
        if (s[i] == 0 && a != 0 && a == b) {
            *flip = a > 0;
            return i;
        }
    }
    *flip = false;
    return 0; /* not reached for the inputs described */
}

static bool general_meet(vec3 a[3], vec3 b[3], const int sa[3], const int sb[3])
{
    bool flip_b, flip_a;
    int i = lone_vertex(sa, &flip_b);
    int j = lone_vertex(sb, &flip_a);
    /* A cyclic turn keeps a triangle's orientation; swapping its last two flips it. */
    const double* p1 = a[i];
    const double* q1 = a[(i + 1) % 3];
    const double* r1 = a[(i + 2) % 3];
    const double* p2 = b[j];
    const double* q2 = b[(j + 1) % 3];
    const double* r2 = b[(j + 2) % 3];
    if (flip_a) {
        const double* t = q1;
        q1 = r1;
        r1 = t;
    }
    if (flip_b) {
        const double* t = q2;
        q2 = r2;
        r2 = t;
    }
    return intervals_overlap(p1, q1, r1, p2, q2, r2);
}

static bool all_same(const int s[3])
{
    return s[0] == s[1] && s[1] == s[2];
}

static bool triangles_meet(vec3 a[3], vec3 b[3])
{
    int sa[3], sb[3];
    for (int k = 0; k < 3; k++)
        sa[k] = side(b[0], b[1], b[2], a[k]);
    if (all_same(sa) && sa[0] != 0)
        return false;
    for (int k = 0; k < 3; k++)
        sb[k] = side(a[0], a[1], a[2], b[k]);
    if (all_same(sb) && sb[0] != 0)
        return false;
    bool flat_a = all_same(sb) && sb[0] == 0; /* b's vertices all in a's plane, or a collapsed */
    bool flat_b = all_same(sa) && sa[0] == 0;
    if (!flat_a && !flat_b)
        return general_meet(a, b, sa, sb);
    bool collapsed_a = collapsed(a), collapsed_b = collapsed(b);
    if (collapsed_a && collapsed_b)
        return false;
    if (collapsed_a)
        return edges_meet(a, b);
    if (collapsed_b)
        return edges_meet(b, a);
    /* One plane (to within rounding): compare in the plane of the larger triangle. */
    double na[3], nb[3];
    normal_of(a, na);
    normal_of(b, nb);
    double la = na[0] * na[0] + na[1] * na[1] + na[2] * na[2];
    double lb = nb[0] * nb[0] + nb[1] * nb[1] + nb[2] * nb[2];
    return coplanar_meet(a, b, la >= lb ? na : nb);
}

bool cvk_triangles_intersect(const float a[9], const float b[9])
{
    vec3 ta[3], tb[3];
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++) {
            ta[k][c] = a[3 * k + c];
            tb[k][c] = b[3 * k + c];
        }
    return triangles_meet(ta, tb);
}

/* ---- the broad phase -------------------------------------------------------------------- */

#define GRID_BITS 21
#define GRID_MAX ((1 << GRID_BITS) - 1)
#define ENTRIES_PER_BOX 8 /* average cells per box the cell size aims for, at most */

struct entry {
    uint64_t cell;  /* cell_key */
    uint32_t index; /* box */
};

typedef struct grid {
    const float* box;      /* 6 floats per box: min xyz, max xyz */
    uint32_t count;
    int32_t* cells;        /* 6 per box: its first and last cell per axis */
    float origin[3];       /* m: low corner of the grid */
    float cell;            /* m */
    struct entry* entries; /* sorted by cell, then box */
    size_t entry_count;
} grid;

/* The grid's origin, and a first cell size: the mean of the largest sides of the boxes that
   have a size (a box then spans about two cells per axis; points take one cell whatever it). */
static void measure(grid* g)
{
    double side_sum = 0.0;
    uint32_t sized = 0;
    for (int c = 0; c < 3; c++)
        g->origin[c] = INFINITY;
    for (uint32_t i = 0; i < g->count; i++) {
        const float* box = &g->box[6 * (size_t)i];
        float largest = 0.0f;
        for (int c = 0; c < 3; c++) {
            largest = fmaxf(largest, box[3 + c] - box[c]);
            g->origin[c] = fminf(g->origin[c], box[c]);
        }
        side_sum += largest;
        sized += largest > 0.0f;
    }
    g->cell = sized ? (float)(side_sum / sized) : 1.0f;
    if (!(g->cell > 0.0f))
        g->cell = 1.0f;
}

static int32_t cell_index(float x, float origin, float cell)
{
    double c = floor(((double)x - origin) / cell);
    return c > GRID_MAX ? GRID_MAX : (int32_t)c;
}

/* Cell ranges for the current cell size; the number of entries they make, or SIZE_MAX when a
   range leaves the grid's index space or the entries would be more than `limit`. */
static size_t assign_cells(grid* g, size_t limit)
{
    size_t total = 0;
    for (uint32_t i = 0; i < g->count; i++) {
        const float* box = &g->box[6 * (size_t)i];
        int32_t* cells = &g->cells[6 * (size_t)i];
        size_t n = 1;
        for (int c = 0; c < 3; c++) {
            cells[c] = cell_index(box[c], g->origin[c], g->cell);
            cells[3 + c] = cell_index(box[3 + c], g->origin[c], g->cell);
            if (cells[3 + c] >= GRID_MAX)
                return SIZE_MAX;
            n *= (size_t)(cells[3 + c] - cells[c] + 1);
        }
        total += n;
        if (total > limit)
            return SIZE_MAX;
    }
    return total;
}

static uint64_t cell_key(int32_t x, int32_t y, int32_t z)
{
    return ((uint64_t)x << (2 * GRID_BITS)) | ((uint64_t)y << GRID_BITS) | (uint64_t)z;
}

static int compare_entries(const void* a, const void* b)
{
    const struct entry* x = a;
    const struct entry* y = b;
    if (x->cell != y->cell)
        return x->cell < y->cell ? -1 : 1;
    return x->index < y->index ? -1 : x->index > y->index;
}

/* Grows the cell until the boxes make at most ENTRIES_PER_BOX entries each on average (a few
   huge boxes must not fill memory), then lists and sorts the entries. */
static bool fill_grid(grid* g)
{
    size_t total, limit = (size_t)ENTRIES_PER_BOX * g->count;
    while ((total = assign_cells(g, limit)) == SIZE_MAX)
        g->cell *= 2.0f;
    g->entries = malloc((total ? total : 1) * sizeof *g->entries);
    if (!g->entries)
        return false;
    size_t e = 0;
    for (uint32_t i = 0; i < g->count; i++) {
        const int32_t* c = &g->cells[6 * (size_t)i];
        for (int32_t x = c[0]; x <= c[3]; x++)
            for (int32_t y = c[1]; y <= c[4]; y++)
                for (int32_t z = c[2]; z <= c[5]; z++)
                    g->entries[e++] = (struct entry){cell_key(x, y, z), i};
    }
    g->entry_count = e;
    qsort(g->entries, e, sizeof *g->entries, compare_entries);
    return true;
}

/* Whether the pair (i, j), both listed in `cell`, is handed over there: their boxes overlap and
   `cell` holds the low corner of the overlap (one cell per pair). */
static bool overlap_here(const grid* g, uint32_t i, uint32_t j, uint64_t cell)
{
    const float* a = &g->box[6 * (size_t)i];
    const float* b = &g->box[6 * (size_t)j];
    for (int c = 0; c < 3; c++)
        if (a[3 + c] < b[c] || b[3 + c] < a[c])
            return false;
    const int32_t* ca = &g->cells[6 * (size_t)i];
    const int32_t* cb = &g->cells[6 * (size_t)j];
    int32_t low[3];
    for (int c = 0; c < 3; c++)
        low[c] = ca[c] > cb[c] ? ca[c] : cb[c];
    return cell_key(low[0], low[1], low[2]) == cell;
}

cvk_result cvk_box_pairs(const float* boxes, uint32_t count, uint32_t split, cvk_box_pair_fn pair,
                         void* user, const char* what, cvk_error* error)
{
    grid g = {.box = boxes, .count = count};
    g.cells = malloc(6 * (size_t)(count ? count : 1) * sizeof *g.cells);
    bool ok = g.cells != NULL;
    if (ok) {
        measure(&g);
        ok = fill_grid(&g);
    }
    if (!ok) {
        free(g.cells);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "%s: out of host memory for a grid of %u boxes", what, count);
    }
    for (size_t first = 0, end; first < g.entry_count; first = end) {
        uint64_t cell = g.entries[first].cell;
        for (end = first + 1; end < g.entry_count && g.entries[end].cell == cell;)
            end++;
        /* Entries of a cell are sorted by box, so i < j; with a split, the boxes below it
           come first, and each meets only those from it on. */
        size_t from = first; /* with a split: the cell's first box at or past it */
        while (split && from < end && g.entries[from].index < split)
            from++;
        for (size_t x = first; x < (split ? from : end); x++) {
            uint32_t i = g.entries[x].index;
            for (size_t y = split ? from : x + 1; y < end; y++)
                if (overlap_here(&g, i, g.entries[y].index, cell))
                    pair(user, i, g.entries[y].index);
        }
    }
    free(g.cells);
    free(g.entries);
    return CVK_SUCCESS;
}

/* ---- the count -------------------------------------------------------------------------- */

/* The triangles of a soup the count tests, and what it found: how many pairs intersect, and
   the lowest of them. */
typedef struct soup {
    const float* xyz;
    const uint32_t* triangles;
    const uint32_t* groups; /* per triangle, or NULL: pairs of one group only */
    uint32_t* kept;         /* the triangles tested (not torn, finite, indices in range) */
    uint64_t pairs;
    uint32_t first, second; /* the lowest pair so far (triangle indices), when pairs > 0 */
} soup;

static bool keep_triangle(const float* xyz, uint32_t vertex_count, const uint32_t* v)
{
    if (v[0] == v[1] && v[1] == v[2])
        return false; /* torn */
    for (int k = 0; k < 3; k++) {
        if (v[k] >= vertex_count)
            return false;
        for (int c = 0; c < 3; c++)
            if (!isfinite(xyz[3 * (size_t)v[k] + c]))
                return false;
    }
    return true;
}

static bool share_vertex(const uint32_t* u, const uint32_t* v)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (u[i] == v[j])
                return true;
    return false;
}

static void load(const soup* s, uint32_t t, float out[9])
{
    const uint32_t* v = &s->triangles[3 * (size_t)t];
    for (int k = 0; k < 3; k++)
        memcpy(&out[3 * k], &s->xyz[3 * (size_t)v[k]], 3 * sizeof(float));
}

/* Kept triangles i < j whose boxes overlap (cvk_box_pair_fn). */
static void test_pair(void* user, uint32_t i, uint32_t j)
{
    soup* s = user;
    uint32_t lo = s->kept[i], hi = s->kept[j]; /* kept is increasing */
    if ((s->groups && s->groups[lo] != s->groups[hi]) ||
        share_vertex(&s->triangles[3 * (size_t)lo], &s->triangles[3 * (size_t)hi]))
        return;
    float a[9], b[9];
    load(s, lo, a);
    load(s, hi, b);
    if (!cvk_triangles_intersect(a, b))
        return;
    if (s->pairs == 0 || lo < s->first || (lo == s->first && hi < s->second)) {
        s->first = lo;
        s->second = hi;
    }
    s->pairs++;
}

/* Every pair of the soup whose boxes overlap, each tested once. */
static cvk_result scan_soup(const float* xyz, uint32_t vertex_count, const uint32_t* triangles,
                            const uint32_t* groups, uint32_t triangle_count, soup* out,
                            cvk_error* error)
{
    *out = (soup){.xyz = xyz, .triangles = triangles, .groups = groups};
    size_t n = triangle_count ? triangle_count : 1;
    out->kept = malloc(n * sizeof *out->kept);
    float* box = malloc(6 * n * sizeof *box);
    if (!out->kept || !box) {
        free(out->kept);
        free(box);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "intersection test: out of host memory for %u triangles", triangle_count);
    }
    uint32_t count = 0;
    for (uint32_t t = 0; t < triangle_count; t++) {
        const uint32_t* v = &triangles[3 * (size_t)t];
        if (!keep_triangle(xyz, vertex_count, v))
            continue;
        for (int c = 0; c < 3; c++) {
            float x0 = xyz[3 * (size_t)v[0] + c], x1 = xyz[3 * (size_t)v[1] + c];
            float x2 = xyz[3 * (size_t)v[2] + c];
            box[6 * (size_t)count + c] = fminf(x0, fminf(x1, x2));
            box[6 * (size_t)count + 3 + c] = fmaxf(x0, fmaxf(x1, x2));
        }
        out->kept[count++] = t;
    }
    cvk_result r = cvk_box_pairs(box, count, 0, test_pair, out, "intersection test", error);
    free(box);
    free(out->kept);
    out->kept = NULL;
    return r;
}

cvk_result cvk_count_intersecting_pairs(const float* xyz, uint32_t vertex_count,
                                        const uint32_t* triangles, const uint32_t* groups,
                                        uint32_t triangle_count, uint64_t* out_pairs,
                                        cvk_error* error)
{
    soup found;
    cvk_result r = scan_soup(xyz, vertex_count, triangles, groups, triangle_count, &found, error);
    *out_pairs = r == CVK_SUCCESS ? found.pairs : 0;
    return r;
}

static void centroid(const float* xyz, const uint32_t* v, double out[3])
{
    for (int c = 0; c < 3; c++)
        out[c] = ((double)xyz[3 * (size_t)v[0] + c] + xyz[3 * (size_t)v[1] + c] +
                  xyz[3 * (size_t)v[2] + c]) / 3.0;
}

cvk_result cvk_first_intersecting_pair(const float* xyz, uint32_t vertex_count,
                                       const uint32_t* triangles, const uint32_t* groups,
                                       uint32_t triangle_count, cvk_intersecting_pair* out,
                                       cvk_error* error)
{
    *out = (cvk_intersecting_pair){0};
    soup found;
    cvk_result r = scan_soup(xyz, vertex_count, triangles, groups, triangle_count, &found, error);
    if (r != CVK_SUCCESS || found.pairs == 0)
        return r;
    out->found = true;
    out->first = found.first;
    out->second = found.second;
    double a[3], b[3];
    centroid(xyz, &triangles[3 * (size_t)found.first], a);
    centroid(xyz, &triangles[3 * (size_t)found.second], b);
    for (int c = 0; c < 3; c++)
        out->near[c] = (float)(0.5 * (a[c] + b[c]));
    return CVK_SUCCESS;
}

static void sub3(const double* a, const double* b, double* out)
{
    for (int c = 0; c < 3; c++)
        out[c] = a[c] - b[c];
}

static double dot3(const double* a, const double* b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Squared distance from p to the closed triangle (a, b, c): the closest point by Voronoi
   regions (Ericson, Real-Time Collision Detection, 5.1.5). */
double cvk_point_triangle_distance2(const double p[3], const double a[3], const double b[3],
                                    const double c[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], q[3], d[3];
    sub3(b, a, ab);
    sub3(c, a, ac);
    sub3(p, a, ap);
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    sub3(p, b, bp);
    double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    sub3(p, c, cp);
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    double s = 0.0, t = 0.0; /* q = a + s·ab + t·ac */
    if (d1 <= 0.0 && d2 <= 0.0) {
    } else if (d3 >= 0.0 && d4 <= d3) {
        s = 1.0;
    } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        s = d1 / (d1 - d3);
    } else if (d6 >= 0.0 && d5 <= d6) {
        t = 1.0;
    } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        t = d2 / (d2 - d6);
    } else if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        s = 1.0 - t;
    } else {
        double denom = va + vb + vc;
        s = vb / denom;
        t = vc / denom;
    }
    for (int k = 0; k < 3; k++)
        q[k] = a[k] + s * ab[k] + t * ac[k];
    sub3(p, q, d);
    return dot3(d, d);
}
