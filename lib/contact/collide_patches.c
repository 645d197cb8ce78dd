/* Surface patches for the candidate search (collide.h, "Patches"): made once on the host from
   the rest mesh, and the host's reference of the activity a search computes on the device
   (shaders/contact/contact_patch.comp). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/collide.h"
#include "core/error.h"
#include "shared/layout.h"

/* Union-find over triangles, with path halving. */
static uint32_t find(uint32_t* parent, uint32_t t)
{
    while (parent[t] != t) {
        parent[t] = parent[parent[t]];
        t = parent[t];
    }
    return t;
}

static int compare_u64(const void* a, const void* b)
{
    uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
    return (x > y) - (x < y);
}

/* The mean rest edge length over the triangles (each edge once per triangle). */
static double mean_edge(const cvk_collide* c, const uint32_t* triangles, uint32_t tc)
{
    double sum = 0.0;
    for (uint32_t t = 0; t < tc; t++)
        for (int k = 0; k < 3; k++) {
            const float* p = &c->rest_xyz[4 * (size_t)triangles[4 * (size_t)t + k]];
            const float* q = &c->rest_xyz[4 * (size_t)triangles[4 * (size_t)t + (k + 1) % 3]];
            double d[3] = {(double)p[0] - q[0], (double)p[1] - q[1], (double)p[2] - q[2]};
            sum += sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
    return tc ? sum / (3.0 * tc) : 0.0;
}

/* Each cloth's rest bounding box, 6 doubles per cloth (low, high). */
static void cloth_boxes(const cvk_collide* c, const cvk_build* b, double* boxes)
{
    for (uint32_t k = 0; k < b->cloth_count; k++)
        for (int m = 0; m < 3; m++) {
            boxes[6 * (size_t)k + m] = INFINITY;
            boxes[6 * (size_t)k + m + 3] = -INFINITY;
        }
    for (uint32_t p = 0; p < b->particle_count; p++) {
        const float* r = &c->rest_xyz[4 * (size_t)p];
        double* box = &boxes[6 * (size_t)r[3]];
        for (int m = 0; m < 3; m++) {
            box[m] = fmin(box[m], r[m]);
            box[m + 3] = fmax(box[m + 3], r[m]);
        }
    }
}

/* Triangle t's cube: its cloth and the cell holding its rest centroid, of a grid over the
   cloth's rest box whose cells are as near `side` as divides the box evenly (no sliver of a
   cell at its far edge). */
static void cube_of(const cvk_collide* c, const uint32_t* triangles, const double* boxes,
                    uint32_t t, double side, int64_t key[4])
{
    double centre[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < 3; k++) {
        const float* p = &c->rest_xyz[4 * (size_t)triangles[4 * (size_t)t + k]];
        for (int m = 0; m < 3; m++)
            centre[m] += p[m] / 3.0;
    }
    uint32_t cloth = (uint32_t)c->rest_xyz[4 * (size_t)triangles[4 * (size_t)t] + 3];
    const double* box = &boxes[6 * (size_t)cloth];
    key[0] = cloth;
    for (int m = 0; m < 3; m++) {
        double extent = box[m + 3] - box[m];
        double cells = fmax(1.0, round(extent / side));
        int64_t cell = (int64_t)floor((centre[m] - box[m]) / extent * cells);
        key[m + 1] = extent > 0.0 ? (cell < (int64_t)cells ? cell : (int64_t)cells - 1) : 0;
    }
}

/* Patch of every triangle for cubes of side `side`, numbered in order of their first triangle;
   returns the patch count. */
static uint32_t group(const cvk_collide* c, const cvk_build* b, const uint32_t* triangles,
                      const uint32_t* incident, const double* boxes, double side,
                      uint32_t* parent, int64_t* keys, uint32_t* patch_of_triangle)
{
    uint32_t n = b->particle_count, tc = b->triangle_count;
    for (uint32_t t = 0; t < tc; t++) {
        parent[t] = t;
        cube_of(c, triangles, boxes, t, side, &keys[4 * (size_t)t]);
    }
    /* Triangles sharing a corner and a cube are one piece. */
    for (uint32_t p = 0; p < n; p++)
        for (uint32_t i = incident[p]; i < incident[p + 1]; i++) {
            uint32_t t = incident[n + 1 + i];
            for (uint32_t j = incident[p]; j < i; j++) {
                uint32_t u = incident[n + 1 + j];
                if (memcmp(&keys[4 * (size_t)t], &keys[4 * (size_t)u], 4 * sizeof(int64_t)) == 0) {
                    uint32_t rt = find(parent, t), ru = find(parent, u);
                    if (rt != ru)
                        parent[rt > ru ? rt : ru] = rt < ru ? rt : ru;
                    break;
                }
            }
        }
    uint32_t count = 0;
    for (uint32_t t = 0; t < tc; t++) {
        uint32_t root = find(parent, t);
        patch_of_triangle[t] = root == t ? count++ : patch_of_triangle[root];
    }
    return count;
}

/* Groups the triangles into patches: cubes of CVK_PATCH_EDGES mean rest edges, grown by half
   until there are at most CVK_MAX_PATCHES (or after 64 tries); returns the patch count. */
static uint32_t choose_patches(const cvk_collide* c, const cvk_build* b, const uint32_t* triangles,
                               const uint32_t* incident, double* boxes, uint32_t* parent,
                               int64_t* keys, uint32_t* patch_of_triangle)
{
    cloth_boxes(c, b, boxes);
    double side = CVK_PATCH_EDGES * mean_edge(c, triangles, b->triangle_count);
    uint32_t count = 0;
    for (int attempt = 0; attempt < 64; attempt++, side *= 1.5) {
        count = group(c, b, triangles, incident, boxes, side > 0.0 ? side : 1.0, parent, keys,
                      patch_of_triangle);
        if (count <= CVK_MAX_PATCHES)
            break;
    }
    return count;
}

enum { NEAR_MAX = 32 };

/* The patches of the triangles around particle p's triangles' corners, each once, in order
   of first sight (at most NEAR_MAX); returns how many. */
static uint32_t near_patches(const cvk_build* b, const uint32_t* triangles,
                             const uint32_t* incident, const uint32_t* patch_of_triangle,
                             uint32_t p, uint32_t near[NEAR_MAX])
{
    uint32_t n = b->particle_count, near_count = 0;
    for (uint32_t i = incident[p]; i < incident[p + 1]; i++) {
        const uint32_t* tri = &triangles[4 * (size_t)incident[n + 1 + i]];
        for (int k = 0; k < 3; k++)
            for (uint32_t j = incident[tri[k]]; j < incident[tri[k] + 1]; j++) {
                uint32_t a = patch_of_triangle[incident[n + 1 + j]];
                bool seen = false;
                for (uint32_t m = 0; m < near_count; m++)
                    seen = seen || near[m] == a;
                if (!seen && near_count < NEAR_MAX)
                    near[near_count++] = a;
            }
    }
    return near_count;
}

/* Rest neighbours: patches with triangles around one particle or around two particles of one
   triangle (so patches meeting only at a corner of their cubes are neighbours too), each pair
   once per direction as patch << 32 | neighbour, sorted. Returns them in a new array, their
   count in *unique; NULL when out of memory. */
static uint64_t* neighbour_pairs(const cvk_build* b, const uint32_t* triangles,
                                 const uint32_t* incident, const uint32_t* patch_of_triangle,
                                 size_t* unique)
{
    size_t pair_count = 0, pair_capacity = 16;
    uint64_t* pairs = malloc(pair_capacity * sizeof *pairs);
    for (uint32_t p = 0; pairs && p < b->particle_count; p++) {
        uint32_t near[NEAR_MAX];
        uint32_t near_count = near_patches(b, triangles, incident, patch_of_triangle, p, near);
        for (uint32_t i = 0; i < near_count; i++)
            for (uint32_t j = 0; j < i; j++) {
                if (pair_count + 2 > pair_capacity) {
                    uint64_t* grown = realloc(pairs, 2 * pair_capacity * sizeof *pairs);
                    if (!grown) {
                        free(pairs);
                        return NULL;
                    }
                    pairs = grown;
                    pair_capacity *= 2;
                }
                pairs[pair_count++] = (uint64_t)near[i] << 32 | near[j];
                pairs[pair_count++] = (uint64_t)near[j] << 32 | near[i];
            }
    }
    if (!pairs)
        return NULL;
    qsort(pairs, pair_count, sizeof *pairs, compare_u64);
    size_t distinct = 0;
    for (size_t i = 0; i < pair_count; i++)
        if (distinct == 0 || pairs[i] != pairs[distinct - 1])
            pairs[distinct++] = pairs[i];
    *unique = distinct;
    return pairs;
}

/* The table (shared/layout.h) into c: particles' patches, triangle offsets and ids, neighbour
   offsets and ids. False when out of memory. */
static bool write_table(cvk_collide* c, const cvk_build* b, const uint32_t* incident,
                        const uint32_t* patch_of_triangle, uint32_t count, const uint64_t* pairs,
                        size_t unique)
{
    uint32_t n = b->particle_count, tc = b->triangle_count;
    size_t size = (size_t)n + (count + 1) + tc + (count + 1) + unique;
    uint32_t* table = calloc(size, sizeof *table);
    if (!table)
        return false;
    for (uint32_t p = 0; p < n; p++) /* the patch of its lowest triangle */
        table[p] = incident[p] < incident[p + 1] ? patch_of_triangle[incident[n + 1 + incident[p]]]
                                                 : CVK_NO_PATCH;
    uint32_t* offsets = &table[n];
    uint32_t* ids = &table[(size_t)n + count + 1];
    for (uint32_t t = 0; t < tc; t++)
        offsets[patch_of_triangle[t] + 1]++;
    for (uint32_t a = 0; a < count; a++)
        offsets[a + 1] += offsets[a];
    for (uint32_t t = 0; t < tc; t++) /* in triangle order within a patch */
        ids[offsets[patch_of_triangle[t]]++] = t;
    for (uint32_t a = count; a > 0; a--)
        offsets[a] = offsets[a - 1];
    offsets[0] = 0;
    uint32_t at = n + count + 1 + tc;
    uint32_t* near = &table[at];
    uint32_t* near_ids = &table[(size_t)at + count + 1];
    for (size_t i = 0; i < unique; i++) {
        near[(pairs[i] >> 32) + 1]++;
        near_ids[i] = (uint32_t)pairs[i];
    }
    for (uint32_t a = 0; a < count; a++)
        near[a + 1] += near[a];
    c->patch_count = count;
    c->patch_neighbours = at;
    c->patch_table = table;
    c->patch_table_size = size;
    return true;
}

cvk_result cvk_collide_make_patches(cvk_collide* c, const cvk_build* b, const uint32_t* triangles,
                                    const uint32_t* incident, cvk_error* error)
{
    uint32_t tc = b->triangle_count;
    uint32_t* parent = malloc(sizeof(uint32_t) * (tc ? tc : 1));
    int64_t* keys = malloc(4 * sizeof(int64_t) * (tc ? tc : 1));
    uint32_t* patch_of_triangle = malloc(sizeof(uint32_t) * (tc ? tc : 1));
    double* boxes = malloc(6 * sizeof(double) * (b->cloth_count ? b->cloth_count : 1));
    uint64_t* pairs = NULL;
    bool ok = parent && keys && patch_of_triangle && boxes;
    if (ok) {
        uint32_t count = choose_patches(c, b, triangles, incident, boxes, parent, keys,
                                        patch_of_triangle);
        size_t unique = 0;
        pairs = neighbour_pairs(b, triangles, incident, patch_of_triangle, &unique);
        ok = pairs && write_table(c, b, incident, patch_of_triangle, count, pairs, unique);
    }
    free(parent);
    free(keys);
    free(patch_of_triangle);
    free(boxes);
    free(pairs);
    if (!ok)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the contact patches");
    return CVK_SUCCESS;
}

/* ---- the host's reference of a search's patch activity ---------------------------------- */

/* Triangle t's corners at x into v and its normal (the edges' cross product) into nv; returns
   the normal's length, 0 when one of its two shorter edges at rest is squeezed within its
   plane: then it counts as degenerate (the longest, the first of equals, does not count). */
static double triangle_normal(const cvk_collide* c, const cvk_build* b, const float* x,
                              uint32_t t, const float* v[3], double nv[3])
{
    for (int k = 0; k < 3; k++)
        v[k] = &x[4 * (size_t)b->internal_of[b->triangles[3 * (size_t)t + k]]];
    double e1[3], e2[3];
    for (int m = 0; m < 3; m++) {
        e1[m] = (double)v[1][m] - v[0][m];
        e2[m] = (double)v[2][m] - v[0][m];
    }
    nv[0] = e1[1] * e2[2] - e1[2] * e2[1];
    nv[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nv[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double len = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
    double now[3], rest[3];
    for (int k = 0; k < 3; k++) {
        const float* r0 = &c->rest_xyz[4 * (size_t)b->internal_of[b->triangles[3 * (size_t)t + k]]];
        const float* r1 = &c->rest_xyz[4 * (size_t)b->internal_of[b->triangles[3 * (size_t)t + (k + 1) % 3]]];
        now[k] = rest[k] = 0.0;
        for (int m = 0; m < 3; m++) {
            double e = (double)v[(k + 1) % 3][m] - v[k][m], r = (double)r1[m] - r0[m];
            now[k] += e * e;
            rest[k] += r * r;
        }
    }
    int longest = rest[0] >= rest[1] && rest[0] >= rest[2] ? 0 : rest[1] >= rest[2] ? 1 : 2;
    for (int k = 0; k < 3; k++)
        if (k != longest && now[k] < CVK_PATCH_SQUEEZE * CVK_PATCH_SQUEEZE * rest[k])
            len = 0.0;
    return len;
}

/* Patch a's box at x (low, high) and normal cone (unit axis: the mean of its triangles' unit
   normals; then the least cosine between the axis and a normal, −1 when a triangle is
   degenerate or there is no axis), in two passes over its triangles. */
static void patch_bounds(const cvk_collide* c, const cvk_build* b, const float* x, uint32_t a,
                         double box[6], double cone[4])
{
    uint32_t n = b->particle_count;
    const uint32_t* offsets = &c->patch_table[n];
    const uint32_t* ids = &c->patch_table[(size_t)n + c->patch_count + 1];
    double sum[3] = {0.0, 0.0, 0.0};
    for (int m = 0; m < 3; m++) {
        box[m] = INFINITY;
        box[m + 3] = -INFINITY;
    }
    for (int pass = 0; pass < 2; pass++) {
        double len_sum = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        if (pass == 1) {
            for (int m = 0; m < 3; m++)
                cone[m] = len_sum > 0.0 ? sum[m] / len_sum : 0.0;
            cone[3] = len_sum > 0.0 ? 1.0 : -1.0;
        }
        for (uint32_t i = offsets[a]; i < offsets[a + 1]; i++) {
            const float* v[3];
            double nv[3];
            double len = triangle_normal(c, b, x, ids[i], v, nv);
            if (pass == 0) {
                for (int k = 0; k < 3; k++)
                    for (int m = 0; m < 3; m++) {
                        box[m] = fmin(box[m], v[k][m]);
                        box[m + 3] = fmax(box[m + 3], v[k][m]);
                    }
                for (int m = 0; m < 3 && len > 0.0; m++)
                    sum[m] += nv[m] / len;
            } else {
                double d = len > 0.0 ? (nv[0] * cone[0] + nv[1] * cone[1] + nv[2] * cone[2]) / len
                                     : -1.0;
                cone[3] = fmin(cone[3], d);
            }
        }
    }
}

/* Whether patch a is active: its cone is wider than `limit` (radians), or its box comes within
   `radius` of another patch's that is not its rest neighbour, or is one and the two cones
   together are wider than `limit`. */
static bool patch_active(const cvk_collide* c, uint32_t a, double (*box)[6], double (*cone)[4],
                         double limit, double radius)
{
    uint32_t count = c->patch_count;
    const uint32_t* near = &c->patch_table[c->patch_neighbours];
    const uint32_t* near_ids = &c->patch_table[(size_t)c->patch_neighbours + count + 1];
    bool on = acos(fmax(-1.0, fmin(1.0, cone[a][3]))) > limit;
    for (uint32_t d = 0; d < count && !on; d++) {
        if (d == a)
            continue;
        bool overlap = true;
        for (int m = 0; m < 3; m++)
            overlap = overlap && box[a][m] - radius <= box[d][m + 3] &&
                      box[d][m] - radius <= box[a][m + 3];
        if (!overlap)
            continue;
        bool adjacent = false;
        for (uint32_t k = near[a]; k < near[a + 1]; k++)
            adjacent = adjacent || near_ids[k] == d;
        double axes = cone[a][0] * cone[d][0] + cone[a][1] * cone[d][1] + cone[a][2] * cone[d][2];
        on = !adjacent || acos(fmax(-1.0, fmin(1.0, axes))) +
                                  acos(fmax(-1.0, fmin(1.0, cone[d][3]))) > limit;
    }
    return on;
}

void cvk_collide_patch_activity(const cvk_collide* c, const cvk_build* b, const float* x,
                                double slack, uint8_t* active)
{
    uint32_t count = c->patch_count;
    double(*box)[6] = malloc(sizeof *box * (count ? count : 1));
    double(*cone)[4] = malloc(sizeof *cone * (count ? count : 1));
    if (!box || !cone) {
        memset(active, 1, count);
        free(box);
        free(cone);
        return;
    }
    for (uint32_t a = 0; a < count; a++)
        patch_bounds(c, b, x, a, box[a], cone[a]);
    double limit = (double)CVK_FLAT_DEGREES * (3.14159265358979323846 / 180.0) * (1.0 - slack);
    double radius = (double)c->detect_radius * (1.0 + slack);
    for (uint32_t a = 0; a < count; a++)
        active[a] = patch_active(c, a, box, cone, limit, radius) ? 1 : 0;
    free(box);
    free(cone);
}
