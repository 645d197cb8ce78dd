/* The torn border the mesh generation draws follows the cut, not the grid's steps. The measure
   is the border's zig-zag: at every vertex where the torn border passes (two border edges of
   the live triangles that were not the cloth's own border), the angle between the edge coming
   in and the edge going out; a straight cut turns 0°, a staircase 90° at every vertex. The
   reference is the cloth's fixed split (every cell cut along its [i + 1, j] − [i, j + 1]
   diagonal, a triangle drawn while the springs of its three edges hold), computed on the host
   from the same spring flags: what the mesh generation drew before a cell could take its
   other diagonal.
   - a grid cut along its [1, 1] diagonal (every spring across the line torn): the fixed split
     draws a staircase (90° a vertex); the drawn border is straight (under 1°);
   - cut along [1, −1], the fixed split's own diagonal: the drawn triangles are the fixed split's,
     index for index;
   - cut at 1:2: the fixed split's border turns 60° a vertex, the drawn one under 10°;
   - no torn spring: the fixed split, index for index, every vertex at its particle;
   - a vertex is drawn off its particle only on the torn border, at most half a cell, never on
     the cloth's outline;
   - assets/scenes/tear.json at frame 105 (the picture of docs/tear.png): the drawn border turns
     under three quarters of the fixed split's turn a vertex;
   - the mesh generated twice from the same state is the same bytes. */
#include "harness.h"
#include "recorded.h"

#include "features/tear.h"
#include "render/mesh.h"
#include "regenerate.h"

/* ---- device buffers ---- */

static void upload_flags(cvk_context* ctx, cvk_sim* sim, const uint32_t* flags)
{
    cvk_error err;
    cvk_submitter sub;
    VkCommandBuffer cmd;
    REQUIRE_OK(cvk_submitter_create(ctx, &sub, &err), err);
    REQUIRE_OK(cvk_command_buffer_allocate(ctx, &sub, &cmd, &err), err);
    REQUIRE_OK(cvk_buffer_upload(ctx, &sub, cmd, &sim->spring_alive, flags,
                                 (VkDeviceSize)sim->build.spring_count * 4u, &err), err);
    cvk_submitter_destroy(ctx, &sub);
}

/* ---- the measure ---- */

typedef struct edge {
    uint32_t lo, hi;
} edge;

static int compare_edges(const void* pa, const void* pb)
{
    const edge *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    return a->hi < b->hi ? -1 : a->hi > b->hi;
}

/* The edges that lie on exactly one non-degenerate triangle, sorted; *count of them. */
static edge* border_edges(const uint32_t* indices, uint32_t triangles, uint32_t* count)
{
    edge* all = malloc((3 * (size_t)triangles + 1) * sizeof *all);
    edge* border = malloc((3 * (size_t)triangles + 1) * sizeof *border);
    if (!all || !border)
        exit(1);
    size_t n = 0;
    for (uint32_t t = 0; t < triangles; t++) {
        const uint32_t* v = &indices[3 * (size_t)t];
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])
            continue;
        for (int e = 0; e < 3; e++) {
            uint32_t a = v[e], b = v[(e + 1) % 3];
            all[n++] = (edge){a < b ? a : b, a < b ? b : a};
        }
    }
    qsort(all, n, sizeof *all, compare_edges);
    uint32_t m = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && compare_edges(&all[i], &all[j]) == 0)
            j++;
        if (j - i == 1)
            border[m++] = all[i];
        i = j;
    }
    free(all);
    *count = m;
    return border;
}

typedef struct zigzag {
    uint32_t vertices; /* where the torn border passes: two torn border edges */
    double mean_turn;  /* degrees */
} zigzag;

/* The torn border's turning: border edges of `indices` that are not in `outer` (the whole
   cloth's border), and at each vertex with exactly two of them, the angle between them. */
static zigzag measure(const uint32_t* indices, uint32_t triangles, const float* xyz, uint32_t vertex_count,
                      const edge* outer, uint32_t outer_count)
{
    uint32_t count;
    edge* border = border_edges(indices, triangles, &count);
    uint32_t* degree = calloc(vertex_count, sizeof *degree);
    uint32_t* other = malloc(2 * (size_t)vertex_count * sizeof *other);
    if (!degree || !other)
        exit(1);
    for (uint32_t k = 0; k < count; k++) {
        if (bsearch(&border[k], outer, outer_count, sizeof *outer, compare_edges))
            continue;
        uint32_t ends[2] = {border[k].lo, border[k].hi};
        for (int e = 0; e < 2; e++) {
            uint32_t v = ends[e];
            if (degree[v] < 2)
                other[2 * (size_t)v + degree[v]] = ends[1 - e];
            degree[v]++;
        }
    }
    zigzag z = {0, 0.0};
    double sum = 0.0;
    for (uint32_t v = 0; v < vertex_count; v++) {
        if (degree[v] != 2)
            continue;
        const float* p = &xyz[3 * (size_t)v];
        const float* a = &xyz[3 * (size_t)other[2 * (size_t)v]];
        const float* b = &xyz[3 * (size_t)other[2 * (size_t)v + 1]];
        double in[3], out[3], li = 0.0, lo = 0.0, dot = 0.0;
        for (int c = 0; c < 3; c++) {
            in[c] = (double)p[c] - a[c];
            out[c] = (double)b[c] - p[c];
            li += in[c] * in[c];
            lo += out[c] * out[c];
            dot += in[c] * out[c];
        }
        double cosine = dot / sqrt(li * lo);
        sum += acos(cosine > 1.0 ? 1.0 : cosine < -1.0 ? -1.0 : cosine);
        z.vertices++;
    }
    z.mean_turn = z.vertices ? sum / z.vertices * 180.0 / 3.14159265358979323846 : 0.0;
    free(border);
    free(degree);
    free(other);
    return z;
}

/* The fixed split's indices: each build triangle, three equal indices once a spring along it
   is torn. */
static uint32_t* fixed_split(const cvk_build* b, const uint32_t* alive)
{
    uint32_t* indices = malloc((3 * (size_t)b->triangle_count + 1) * sizeof *indices);
    if (!indices)
        exit(1);
    for (uint32_t t = 0; t < b->triangle_count; t++) {
        const uint32_t* v = &b->triangles[3 * (size_t)t];
        bool live = true;
        for (int e = 0; e < 3; e++) {
            uint32_t s = b->triangle_springs[3 * (size_t)t + e];
            live = live && (s == UINT32_MAX || alive[s]);
        }
        for (int e = 0; e < 3; e++)
            indices[3 * (size_t)t + e] = live ? v[e] : v[0];
    }
    return indices;
}

/* What one torn state gives: the drawn mesh's zig-zag and the fixed split's, and whether the
   drawn triangles are the fixed split's, index for index. */
typedef struct comparison {
    zigzag drawn, fixed;
    bool same_indices;
} comparison;

static comparison compare(cvk_context* ctx, cvk_sim* sim, cvk_mesh* mesh, const uint32_t* alive)
{
    const cvk_build* b = &sim->build;
    uint32_t* intact = malloc(((size_t)b->spring_count + 1) * sizeof *intact);
    if (!intact)
        exit(1);
    for (uint32_t s = 0; s < b->spring_count; s++)
        intact[s] = 1;
    uint32_t* whole = fixed_split(b, intact);
    uint32_t outer_count;
    edge* outer = border_edges(whole, b->triangle_count, &outer_count);
    cvk_mesh_buffers info = cvk_mesh_get_buffers(mesh);
    float* vertices = harness_read_buffer(ctx, info.vertex_buffer, (VkDeviceSize)info.vertex_count * info.vertex_stride);
    uint32_t* indices = harness_read_buffer(ctx, info.index_buffer, (VkDeviceSize)info.index_count * 4u);
    float* xyz = malloc(3 * (size_t)info.vertex_count * sizeof *xyz);
    if (!xyz)
        exit(1);
    for (uint32_t v = 0; v < info.vertex_count; v++)
        memcpy(&xyz[3 * (size_t)v], &vertices[8 * (size_t)v], 3 * sizeof(float));
    float* particles = harness_read_all(sim); /* where the fixed split drew its vertices */
    uint32_t* fixed = fixed_split(b, alive);
    comparison c = {
        .drawn = measure(indices, info.index_count / 3, xyz, info.vertex_count, outer, outer_count),
        .fixed = measure(fixed, b->triangle_count, particles, info.vertex_count, outer, outer_count),
        .same_indices = memcmp(indices, fixed, (size_t)info.index_count * 4u) == 0,
    };
    free(fixed);
    free(particles);
    free(xyz);
    free(indices);
    free(vertices);
    free(outer);
    free(whole);
    free(intact);
    return c;
}

/* ---- the facts ---- */

/* A flat w x w grid with tearing, every spring across the line side(i, j) torn. */
typedef bool (*side_fn)(int i, int j);
static bool across_diagonal(int i, int j) { return i - j > 1; }       /* along [1, 1] */
static bool across_anti(int i, int j) { return i + j > 12; }          /* along [1, −1] */
static bool across_slope(int i, int j) { return 2 * i - j > 6; }      /* along [1, 2] */
static bool nowhere(int i, int j) { (void)i; (void)j; return false; }

static comparison cut(cvk_context* ctx, side_fn side, const char* name)
{
    const uint32_t w = 14;
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = w;
    cloth.stiffness.shear = 1e4f;
    cloth.tearing.max_stretch = 0.5f;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    cvk_mesh* mesh;
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    const cvk_build* b = &sim->build;
    uint32_t* alive = malloc(((size_t)b->spring_count + 1) * sizeof *alive);
    if (!alive)
        exit(1);
    uint32_t torn = 0;
    for (uint32_t s = 0; s < b->spring_count; s++) {
        uint32_t ua = b->user_of[b->springs[s].a], ub = b->user_of[b->springs[s].b];
        bool sa = side((int)(ua % w), (int)(ua / w)), sb = side((int)(ub % w), (int)(ub / w));
        alive[s] = sa == sb;
        torn += sa != sb;
    }
    upload_flags(ctx, sim, alive);
    harness_regenerate(ctx, mesh);
    comparison c = compare(ctx, sim, mesh, alive);
    printf("%s: %u springs torn; drawn border %u vertices, mean turn %.1f°; fixed split %u vertices, %.1f°\n",
           name, torn, c.drawn.vertices, c.drawn.mean_turn, c.fixed.vertices, c.fixed.mean_turn);
    /* Only vertices on the torn border move, at most half a cell; the cloth's outline and an
       intact cloth are drawn at their particles, bit for bit. */
    cvk_mesh_buffers drawn = cvk_mesh_get_buffers(mesh);
    float* vertices = harness_read_buffer(ctx, drawn.vertex_buffer, (VkDeviceSize)drawn.vertex_count * drawn.vertex_stride);
    float* particles = harness_read_all(sim);
    double cell = cloth.size[0] / (w - 1), most = 0.0;
    /* On the torn border: an end of a torn spring. */
    bool* at_cut = calloc((size_t)w * w, sizeof *at_cut);
    if (!at_cut)
        exit(1);
    for (uint32_t s = 0; s < b->spring_count; s++)
        if (!alive[s])
            at_cut[b->user_of[b->springs[s].a]] = at_cut[b->user_of[b->springs[s].b]] = true;
    uint32_t moved = 0, outline_moved = 0, inside_moved = 0;
    for (uint32_t v = 0; v < drawn.vertex_count; v++) {
        bool differs = memcmp(&vertices[8 * (size_t)v], &particles[3 * (size_t)v], 3 * sizeof(float)) != 0;
        uint32_t i = v % w, j = v / w;
        moved += differs;
        outline_moved += differs && (i == 0 || j == 0 || i == w - 1 || j == w - 1);
        inside_moved += differs && !at_cut[v];
        double d2 = 0.0;
        for (int k = 0; k < 3; k++)
            d2 += ((double)vertices[8 * (size_t)v + k] - particles[3 * (size_t)v + k]) *
                  ((double)vertices[8 * (size_t)v + k] - particles[3 * (size_t)v + k]);
        most = fmax(most, sqrt(d2));
    }
    CHECK(outline_moved == 0 && inside_moved == 0 && (torn > 0 || moved == 0) &&
              most <= 0.5 * cell * (1.0 + 1e-6),
          "%s: %u vertices drawn off their particles (%u on the outline, %u off the torn border), "
          "the farthest %.3g cells off", name, moved, outline_moved, inside_moved, most / cell);
    printf("%s: %u vertices drawn off their particles, %u of them off the torn border\n", name,
           moved, inside_moved);
    free(at_cut);
    free(vertices);
    free(particles);
    /* the same state drawn again: the same bytes */
    cvk_mesh_buffers info = cvk_mesh_get_buffers(mesh);
    VkDeviceSize vbytes = (VkDeviceSize)info.vertex_count * info.vertex_stride;
    void* v1 = harness_read_buffer(ctx, info.vertex_buffer, vbytes);
    harness_regenerate(ctx, mesh);
    void* v2 = harness_read_buffer(ctx, info.vertex_buffer, vbytes);
    CHECK(memcmp(v1, v2, vbytes) == 0, "%s: the mesh generated twice differs", name);
    free(v1);
    free(v2);
    free(alive);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
    return c;
}

static void synthetic_cuts(cvk_context* ctx)
{
    comparison diagonal = cut(ctx, across_diagonal, "cut along [1, 1]");
    CHECK(diagonal.fixed.mean_turn > 80.0 && diagonal.fixed.vertices >= 20,
          "the fixed split's border along [1, 1] turns %.1f° at %u vertices: not the staircase it is",
          diagonal.fixed.mean_turn, diagonal.fixed.vertices);
    CHECK(diagonal.drawn.mean_turn < 1.0 && diagonal.drawn.vertices >= 20,
          "the drawn border along [1, 1] turns %.1f° at %u vertices (a straight cut turns 0°)",
          diagonal.drawn.mean_turn, diagonal.drawn.vertices);
    comparison anti = cut(ctx, across_anti, "cut along [1, -1]");
    CHECK(anti.same_indices && anti.drawn.mean_turn < 1.0,
          "along the fixed split's own diagonal the drawn mesh %s the fixed split's (turn %.1f°)",
          anti.same_indices ? "is" : "is not", anti.drawn.mean_turn);
    comparison slope = cut(ctx, across_slope, "cut along [1, 2]");
    CHECK(slope.fixed.mean_turn > 45.0 && slope.drawn.mean_turn < 10.0,
          "along [1, 2] the drawn border turns %.1f°, the fixed split's %.1f°", slope.drawn.mean_turn,
          slope.fixed.mean_turn);
    comparison whole = cut(ctx, nowhere, "no cut");
    CHECK(whole.same_indices && whole.drawn.vertices == 0, "an intact cloth is not drawn as the fixed split");
}

/* The shipped showcase at the frame of its picture. */
static void tear_scene(cvk_context* ctx)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    if (!root) {
        printf("note: CLOTHVK_SOURCE_ROOT is not set; tear.json not checked\n");
        return;
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/assets/scenes/tear.json", root);
    cvk_error err;
    cvk_scene* scene = NULL;
    REQUIRE_OK(cvk_scene_load(path, NULL, 0, &scene, &err), err);
    cvk_sim* sim = NULL;
    REQUIRE_OK(harness_sim_create(ctx, cvk_scene_get_desc(scene), &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 105, &err), err);
    cvk_mesh* mesh;
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    uint32_t* alive = malloc(((size_t)sim->build.spring_count + 1) * sizeof *alive);
    if (!alive)
        exit(1);
    REQUIRE_OK(cvk_tear_read_flags(sim, alive, &err), err);
    uint32_t torn = 0;
    for (uint32_t s = 0; s < sim->build.spring_count; s++)
        torn += !alive[s];
    comparison c = compare(ctx, sim, mesh, alive);
    printf("tear.json, frame 105: %u springs torn; drawn border %u vertices, mean turn %.1f°; fixed split %u "
           "vertices, %.1f°\n",
           torn, c.drawn.vertices, c.drawn.mean_turn, c.fixed.vertices, c.fixed.mean_turn);
    CHECK(torn > 0 && c.drawn.mean_turn < 0.75 * c.fixed.mean_turn,
          "tear.json at frame 105: the drawn border turns %.1f° a vertex, the fixed split's %.1f°",
          c.drawn.mean_turn, c.fixed.mean_turn);
    free(alive);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
    cvk_scene_destroy(scene);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    synthetic_cuts(ctx);
    tear_scene(ctx);
    return harness_finish(ctx);
}
