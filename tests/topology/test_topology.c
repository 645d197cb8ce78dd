/* The mesh-file reader (lib/topology/topology_mesh.c): counts of the example meshes, welding, file
   order, the transform, quads, bend springs, other formats, and every bad input with its exact
   message. Test files are written into a temporary folder at run time. */
#include <errno.h>
#include <pthread.h>
#include <stdint.h>
#include <sys/stat.h>
#include <unistd.h>

#include "harness.h"
#include "topology/topology.h"

static char temp_dir[256];
static char written[32][64];
static int written_count;

/* Writes text (size bytes; size 0: strlen) to temp_dir/name; the full path goes to path. */
static void write_file(const char* name, const char* text, size_t size, char path[512])
{
    snprintf(path, 512, "%s/%s", temp_dir, name);
    FILE* f = fopen(path, "wb");
    if (!f || fwrite(text, 1, size ? size : strlen(text), f) != (size ? size : strlen(text))) {
        fprintf(stderr, "cannot write %s: %s\n", path, strerror(errno));
        exit(1);
    }
    fclose(f);
    if (written_count < 32)
        snprintf(written[written_count++], 64, "%s", name);
}

static cvk_cloth_desc mesh_desc(const char* path, float structural, float shear, float bend)
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.mesh = path;
    c.transform = (cvk_transform){.scale = {1, 1, 1}, .rotation = {1, 0, 0, 0}};
    c.stiffness = (cvk_stiffness){.structural = structural, .shear = shear, .bend = bend};
    return c;
}

static cvk_topology read_ok(const char* label, const cvk_cloth_desc* c)
{
    cvk_topology t;
    cvk_error err = {0};
    cvk_result r = cvk_topology_mesh(c, 0, &t, &err);
    if (r != CVK_SUCCESS) {
        fprintf(stderr, "%s: cvk_topology_mesh returned %s: %s\n", label, cvk_result_name(r),
                err.message);
        exit(1);
    }
    return t;
}

static uint32_t count_type(const cvk_topology* t, uint32_t type)
{
    uint32_t n = 0;
    for (uint32_t s = 0; s < t->spring_count; s++)
        n += t->springs[s].type == type;
    return n;
}

/* The particle at (x, y, z) exactly, or UINT32_MAX. */
static uint32_t particle_at(const cvk_topology* t, float x, float y, float z)
{
    for (uint32_t v = 0; v < t->vertex_count; v++)
        if (t->position[3 * v] == x && t->position[3 * v + 1] == y && t->position[3 * v + 2] == z)
            return v;
    return UINT32_MAX;
}

/* Index of the spring joining a and b (either way round), or UINT32_MAX. */
static uint32_t find_spring(const cvk_topology* t, uint32_t a, uint32_t b)
{
    for (uint32_t s = 0; s < t->spring_count; s++)
        if ((t->springs[s].a == a && t->springs[s].b == b) ||
            (t->springs[s].a == b && t->springs[s].b == a))
            return s;
    return UINT32_MAX;
}

/* The facts every topology holds: springs join distinct particles, no pair twice, each
   triangle edge's spring joins that edge's ends, mass and pinned are allocated and zero. */
static void check_consistent(const char* label, const cvk_topology* t)
{
    bool distinct = true, unique = true, along = true, zero = true;
    for (uint32_t s = 0; s < t->spring_count; s++) {
        distinct = distinct && t->springs[s].a != t->springs[s].b &&
                   t->springs[s].a < t->vertex_count && t->springs[s].b < t->vertex_count;
        unique = unique && find_spring(t, t->springs[s].a, t->springs[s].b) == s;
    }
    for (uint32_t i = 0; i < 3 * t->triangle_count; i++) {
        uint32_t s = t->triangle_springs[i];
        uint32_t a = t->triangles[i], b = t->triangles[i % 3 == 2 ? i - 2 : i + 1];
        along = along && (s == CVK_NO_SPRING || find_spring(t, a, b) == s);
    }
    for (uint32_t v = 0; v < t->vertex_count; v++)
        zero = zero && t->mass[v] == 0.0f && t->pinned[v] == 0;
    CHECK(distinct, "%s: a spring joins a particle to itself or to none", label);
    CHECK(unique, "%s: two springs join the same pair", label);
    CHECK(along, "%s: a triangle edge names a spring that does not join its ends", label);
    CHECK(zero, "%s: mass or pinned not allocated as zeros", label);
    CHECK(t->colour == NULL && t->colour_count == 0, "%s: a mesh has a closed-form colouring", label);
}

/* ---- the example meshes ---------------------------------------------------------------------- */

/* Counts from scripts/make_meshes.py (the header line of each file), and the particle order:
   particle i is vertex line i + 1. */
static void check_example(const char* name, uint32_t v, uint32_t e, uint32_t f, int holes)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    char path[512];
    snprintf(path, sizeof path, "%s/assets/meshes/%s", root ? root : ".", name);
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 0.0f, 0.0f);
    cvk_topology t = read_ok(name, &c);
    CHECK(t.vertex_count == v, "%s: %u vertices, expected %u", name, t.vertex_count, v);
    CHECK(t.spring_count == e, "%s: %u edges, expected %u", name, t.spring_count, e);
    CHECK(t.triangle_count == f, "%s: %u triangles, expected %u", name, t.triangle_count, f);
    CHECK((int)v - (int)e + (int)f == 1 - holes, "%s: Euler characteristic %d, expected %d", name,
          (int)v - (int)e + (int)f, 1 - holes);
    check_consistent(name, &t);

    FILE* file = fopen(path, "r");
    char line[256];
    uint32_t n = 0, mismatches = 0;
    while (file && fgets(line, sizeof line, file)) {
        float x, y, z;
        if (sscanf(line, "v %f %f %f", &x, &y, &z) != 3)
            continue;
        mismatches += n >= t.vertex_count || t.position[3 * n] != x ||
                      t.position[3 * n + 1] != y || t.position[3 * n + 2] != z;
        n++;
    }
    if (file)
        fclose(file);
    CHECK(n == v && mismatches == 0, "%s: %u of %u vertex lines are not the particle of the same "
          "index", name, mismatches, n);
    cvk_topology_destroy(&t);
}

/* ---- welding and file order ------------------------------------------------------------------ */

/* A 2 × 2-cell grid as eight STL triangles (24 corners): nine particles in order of first
   appearance, sixteen edges. */
static void check_stl_welding(void)
{
    static const float cells[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    char text[4096] = "solid grid\n";
    for (int k = 0; k < 4; k++) {
        float x = cells[k][0], y = cells[k][1];
        char facet[512];
        snprintf(facet, sizeof facet,
                 "facet normal 0 0 1\nouter loop\nvertex %g %g 0\nvertex %g %g 0\nvertex %g %g 0\n"
                 "endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex %g %g 0\n"
                 "vertex %g %g 0\nvertex %g %g 0\nendloop\nendfacet\n",
                 x, y, x + 1, y, x, y + 1, x + 1, y, x + 1, y + 1, x, y + 1);
        strcat(text, facet);
    }
    strcat(text, "endsolid grid\n");
    char path[512];
    write_file("grid.stl", text, 0, path);
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 0.0f, 0.0f);
    cvk_topology t = read_ok("grid.stl", &c);
    CHECK(t.vertex_count == 9, "grid.stl: 24 corners welded to %u particles, expected 9",
          t.vertex_count);
    CHECK(t.triangle_count == 8 && t.spring_count == 16, "grid.stl: %u triangles, %u edges; "
          "expected 8 and 16", t.triangle_count, t.spring_count);
    /* First appearances: (0,0) (1,0) (0,1) (1,1) from the first cell, then (2,0) (2,1) ... */
    static const float order[9][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {2, 0}, {2, 1},
                                      {0, 2}, {1, 2}, {2, 2}};
    uint32_t wrong = 0;
    for (uint32_t v = 0; v < 9 && v < t.vertex_count; v++)
        wrong += particle_at(&t, order[v][0], order[v][1], 0.0f) != v;
    CHECK(wrong == 0, "grid.stl: %u particles out of first-appearance order", wrong);
    check_consistent("grid.stl", &t);
    cvk_topology_destroy(&t);
}

/* A square whose two triangles use their own copies of the shared corners (a UV seam), one copy
   off by 1e-8 (within the tolerance, 1e-6 of the diagonal), and a vertex no face uses: one piece
   of four particles, five edges and a bend spring across the seam. A copy 1e-4 away stays apart. */
static void check_seam_welding(void)
{
    char path[512];
    write_file("seam.obj",
               "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nv 1 0.00000001 0\nv 1 1 0\nv 0 1 0\n"
               "vt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0\nvt 1 1\nvt 0 0.5\n"
               "f 1/1 2/2 3/3\nf 5/4 6/5 7/6\n", 0, path);
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 0.0f, 1e3f);
    cvk_topology t = read_ok("seam.obj", &c);
    CHECK(t.vertex_count == 4, "seam.obj: %u particles, expected 4 (seam welded, unused vertex "
          "dropped)", t.vertex_count);
    CHECK(count_type(&t, CVK_SPRING_STRUCTURAL) == 5 && count_type(&t, CVK_SPRING_BEND) == 1,
          "seam.obj: %u structural and %u bend springs, expected 5 and 1",
          count_type(&t, CVK_SPRING_STRUCTURAL), count_type(&t, CVK_SPRING_BEND));
    cvk_topology_destroy(&t);

    write_file("apart.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0.0001 0\nv 1 1 0\nv 0 1 0\n"
               "f 1 2 3\nf 4 5 6\n", 0, path);
    c = mesh_desc(path, 1e6f, 0.0f, 0.0f);
    t = read_ok("apart.obj", &c);
    CHECK(t.vertex_count == 5, "apart.obj: %u particles, expected 5 (1e-4 is beyond the weld "
          "tolerance)", t.vertex_count);
    cvk_topology_destroy(&t);
}

/* Two objects of one OBJ file are one cloth, in file order. */
static void check_two_objects(void)
{
    char path[512];
    write_file("two.obj", "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no b\nv 5 0 0\nv 6 0 0\n"
               "v 5 1 0\nf 4 5 6\n", 0, path);
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 0.0f, 0.0f);
    cvk_topology t = read_ok("two.obj", &c);
    CHECK(t.vertex_count == 6 && t.triangle_count == 2, "two.obj: %u particles, %u triangles; "
          "expected 6 and 2", t.vertex_count, t.triangle_count);
    CHECK(t.vertex_count == 6 && t.position[0] == 0.0f && t.position[9] == 5.0f &&
          t.position[15] == 5.0f && t.position[16] == 1.0f,
          "two.obj: particles 0, 3 and 5 are not (0,0,0), (5,0,0), (5,1,0)");
    cvk_topology_destroy(&t);
}

/* OBJ particles follow the "v" lines, not the order faces use them: a quad whose face lists
   its corners 3 1 2 4, with an unused vertex line between and a seam copy of line 1. */
static void check_obj_vertex_order(void)
{
    char path[512];
    write_file("order.obj", "v 0 0 0\nv 1 0 0\nv 7 7 7\nv 0 1 0\nv 1 1 0\nv 0 0 0\n"
               "f 4 1 2 5\nf 2 6 4\n", 0, path);
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 0.0f, 0.0f);
    cvk_topology t = read_ok("order.obj", &c);
    static const float want[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    double worst = t.vertex_count == 4 ? harness_max_diff(t.position, &want[0][0], 12) : INFINITY;
    CHECK(worst == 0.0, "order.obj: %u particles not in the order of the v lines (off by %g)",
          t.vertex_count, worst);
    cvk_topology_destroy(&t);

    /* "v" lines of no face, far outside the mesh or beyond float range, are read again for the
       order too: they match no particle (their cell was once an infinite integer, undefined
       behaviour that UBSan reports; found by tests/fuzz/fuzz_mesh.c). */
    write_file("far.obj", "v 1e39 0 0\nv 0 0 0\nv 1 0 0\nv -1e30 5 5\nv 0 1 0\nv 1 1 0\n"
               "f 5 2 3 6\n", 0, path);
    c = mesh_desc(path, 1e6f, 0.0f, 0.0f);
    t = read_ok("far.obj", &c);
    worst = t.vertex_count == 4 ? harness_max_diff(t.position, &want[0][0], 12) : INFINITY;
    CHECK(worst == 0.0, "far.obj: %u particles not in the order of the v lines (off by %g)",
          t.vertex_count, worst);
    cvk_topology_destroy(&t);
}

/* ---- transform ------------------------------------------------------------------------------- */

/* Scale (2, 3, 4), then a quarter turn about z (given unnormalised as [1, 0, 0, 1]: the library
   normalises it), then translation (10, 20, 30): (x, y, z) -> (10 − 3y, 20 + 2x, 30 + 4z). */
static void check_transform(void)
{
    char path[512];
    write_file("transform.obj", "v 1 1 1\nv 2 0 0\nv 0 1 -1\nf 1 2 3\n", 0, path);
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 0.0f, 0.0f);
    c.transform = (cvk_transform){.scale = {2, 3, 4}, .rotation = {1, 0, 0, 1},
                                  .translation = {10, 20, 30}};
    cvk_topology t = read_ok("transform.obj", &c);
    static const float want[3][3] = {{7, 22, 34}, {10, 24, 30}, {7, 20, 26}};
    double worst = t.vertex_count == 3 ? harness_max_diff(t.position, &want[0][0], 9) : INFINITY;
    CHECK(worst < 1e-5, "transform: positions off by %g m from scale, rotate, translate", worst);
    cvk_topology_destroy(&t);
}

/* ---- quads ----------------------------------------------------------------------------------- */

/* A 3 × 3-vertex grid written as four quads a b d c: the grid's own triangles (a, b, c),
   (b, d, c); 12 structural springs on the quads' sides, 8 shear springs on both diagonals
   (the split diagonal b–c carries shear, not structural), and bend springs across the four
   interior edges between the corners opposite them. */
static void check_quads(void)
{
    char path[512];
    write_file("quads.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n"
               "v 0 2 0\nv 1 2 0\nv 2 2 0\n"
               "f 1 2 5 4\nf 2 3 6 5\nf 4 5 8 7\nf 5 6 9 8\n", 0, path);
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 1e5f, 1e3f);
    cvk_topology t = read_ok("quads.obj", &c);
    check_consistent("quads", &t);
    uint32_t p[3][3]; /* p[i][j]: particle of grid vertex (i, j) */
    for (uint32_t j = 0; j < 3; j++)
        for (uint32_t i = 0; i < 3; i++)
            p[i][j] = particle_at(&t, (float)i, (float)j, 0.0f);
    CHECK(t.vertex_count == 9 && t.triangle_count == 8, "quads: %u particles, %u triangles; "
          "expected 9 and 8", t.vertex_count, t.triangle_count);
    uint32_t wrong_tri = 0, wrong_links = 0;
    for (uint32_t q = 0; q < 4 && t.triangle_count == 8; q++) {
        uint32_t i = q % 2, j = q / 2;
        uint32_t a = p[i][j], b = p[i + 1][j], d = p[i + 1][j + 1], cc = p[i][j + 1];
        const uint32_t* tri = &t.triangles[6 * q];
        wrong_tri += !(tri[0] == a && tri[1] == b && tri[2] == cc && tri[3] == b && tri[4] == d &&
                       tri[5] == cc);
        const uint32_t* ts = &t.triangle_springs[6 * q];
        uint32_t diagonal = find_spring(&t, b, cc);
        wrong_links += diagonal == UINT32_MAX || t.springs[diagonal].type != CVK_SPRING_SHEAR ||
                       ts[1] != diagonal || ts[5] != diagonal;
        wrong_links += t.springs[ts[0]].type != CVK_SPRING_STRUCTURAL;
    }
    CHECK(wrong_tri == 0, "quads: %u quads not split into (a,b,c), (b,d,c)", wrong_tri);
    CHECK(wrong_links == 0, "quads: %u quads whose split diagonal is not their shear spring",
          wrong_links);
    CHECK(count_type(&t, CVK_SPRING_STRUCTURAL) == 12 && count_type(&t, CVK_SPRING_SHEAR) == 8 &&
          count_type(&t, CVK_SPRING_BEND) == 4, "quads: %u structural, %u shear, %u bend springs; "
          "expected 12, 8, 4", count_type(&t, CVK_SPRING_STRUCTURAL),
          count_type(&t, CVK_SPRING_SHEAR), count_type(&t, CVK_SPRING_BEND));
    static const uint32_t bends[4][4] = {{0, 1, 2, 0}, {0, 2, 2, 1}, {1, 0, 0, 2}, {2, 0, 1, 2}};
    uint32_t missing = 0;
    for (int k = 0; k < 4; k++) {
        uint32_t s = find_spring(&t, p[bends[k][0]][bends[k][1]], p[bends[k][2]][bends[k][3]]);
        missing += s == UINT32_MAX || t.springs[s].type != CVK_SPRING_BEND;
    }
    CHECK(missing == 0, "quads: %u of the 4 expected bend springs missing", missing);
    cvk_topology_destroy(&t);

    /* Without shear the split diagonals carry no spring at all. */
    c = mesh_desc(path, 1e6f, 0.0f, 0.0f);
    t = read_ok("quads.obj", &c);
    uint32_t none = 0;
    for (uint32_t k = 0; k < t.triangle_count; k++)
        none += t.triangle_springs[3 * k + (k % 2 ? 2 : 1)] == CVK_NO_SPRING;
    CHECK(t.spring_count == 12 && none == 8, "quads without shear: %u springs (expected 12), %u of "
          "8 split diagonals without a spring", t.spring_count, none);
    cvk_topology_destroy(&t);
}

/* A convex pentagon is fanned from its first corner: 3 triangles, 5 structural springs, no
   spring on the two fan diagonals. */
static void check_pentagon(void)
{
    char path[512];
    write_file("pentagon.obj", "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf 1 2 3 4 5\n", 0, path);
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 1e5f, 1e3f);
    cvk_topology t = read_ok("pentagon.obj", &c);
    static const uint32_t want[9] = {0, 1, 2, 0, 2, 3, 0, 3, 4};
    bool fan = t.triangle_count == 3 && memcmp(t.triangles, want, sizeof want) == 0;
    CHECK(fan, "pentagon: not fanned from its first corner");
    CHECK(t.spring_count == 5 && fan && t.triangle_springs[2] == CVK_NO_SPRING &&
          t.triangle_springs[3] == CVK_NO_SPRING && t.triangle_springs[5] == CVK_NO_SPRING &&
          t.triangle_springs[6] == CVK_NO_SPRING, "pentagon: %u springs (expected 5), or a spring "
          "on a fan diagonal", t.spring_count);
    cvk_topology_destroy(&t);
}

/* ---- bend springs ---------------------------------------------------------------------------- */

/* Three triangles in a strip, 0 1 2 | 1 3 2 | 1 4 3: springs in order, structural on the edges
   as faces first meet them, then bend across 1–2 (between 0 and 3) and 1–3 (between 2 and 4). */
static void check_bend(void)
{
    char path[512];
    write_file("strip.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 0.5 0\n"
               "f 1 2 3\nf 2 4 3\nf 2 5 4\n", 0, path);
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 1e5f, 1e3f);
    cvk_topology t = read_ok("strip.obj", &c);
    static const uint32_t want[9][3] = {
        {0, 1, CVK_SPRING_STRUCTURAL}, {1, 2, CVK_SPRING_STRUCTURAL}, {2, 0, CVK_SPRING_STRUCTURAL},
        {1, 3, CVK_SPRING_STRUCTURAL}, {3, 2, CVK_SPRING_STRUCTURAL}, {1, 4, CVK_SPRING_STRUCTURAL},
        {4, 3, CVK_SPRING_STRUCTURAL}, {0, 3, CVK_SPRING_BEND},       {2, 4, CVK_SPRING_BEND}};
    uint32_t wrong = t.spring_count == 9 ? 0 : 9;
    for (uint32_t s = 0; s < 9 && t.spring_count == 9; s++) {
        const cvk_topo_spring* sp = &t.springs[s];
        bool same = sp->type == want[s][2] && ((sp->a == want[s][0] && sp->b == want[s][1]) ||
                                               (sp->a == want[s][1] && sp->b == want[s][0]));
        wrong += !same;
    }
    CHECK(wrong == 0, "strip: %u of 9 springs differ from the expected list (got %u springs)",
          wrong, t.spring_count);
    cvk_topology_destroy(&t);

    /* A closed tetrahedron: every edge interior, and every bend pair is already an edge, so it
       keeps its structural spring and no second one. */
    write_file("tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
               "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n", 0, path);
    c = mesh_desc(path, 1e6f, 0.0f, 1e3f);
    t = read_ok("tetra.obj", &c);
    CHECK(t.spring_count == 6 && count_type(&t, CVK_SPRING_STRUCTURAL) == 6,
          "tetrahedron: %u springs, %u structural; expected 6 structural only", t.spring_count,
          count_type(&t, CVK_SPRING_STRUCTURAL));
    check_consistent("tetrahedron", &t);
    cvk_topology_destroy(&t);
}

/* ---- other formats --------------------------------------------------------------------------- */

static bool same_topology(const cvk_topology* a, const cvk_topology* b)
{
    return a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count &&
           a->spring_count == b->spring_count &&
           memcmp(a->position, b->position, 3 * sizeof(float) * a->vertex_count) == 0 &&
           memcmp(a->triangles, b->triangles, 3 * sizeof(uint32_t) * a->triangle_count) == 0 &&
           memcmp(a->triangle_springs, b->triangle_springs, 3 * sizeof(uint32_t) * a->triangle_count) == 0 &&
           memcmp(a->springs, b->springs, sizeof(cvk_topo_spring) * a->spring_count) == 0;
}

/* base64 of n bytes into out (for a glTF data URI). */
static void base64(const unsigned char* in, size_t n, char* out)
{
    static const char abc[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) |
                     (i + 2 < n ? in[i + 2] : 0);
        out[o++] = abc[v >> 18];
        out[o++] = abc[(v >> 12) & 63];
        out[o++] = i + 1 < n ? abc[(v >> 6) & 63] : '=';
        out[o++] = i + 2 < n ? abc[v & 63] : '=';
    }
    out[o] = '\0';
}

/* The strip of check_bend as a glTF 2 file with an embedded buffer: 5 positions, 9 indices. */
static void write_gltf(char path[512])
{
    static const float pos[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 2, 0.5f, 0};
    static const uint16_t idx[9] = {0, 1, 2, 1, 3, 2, 1, 4, 3};
    unsigned char buffer[80] = {0};
    memcpy(buffer, pos, sizeof pos);
    memcpy(buffer + 60, idx, sizeof idx);
    char b64[128], text[2048];
    base64(buffer, 78, b64);
    snprintf(text, sizeof text,
             "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}],\n"
             " \"nodes\": [{\"mesh\": 0}],\n"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],\n"
             " \"buffers\": [{\"byteLength\": 78, \"uri\": \"data:application/octet-stream;base64,%s\"}],\n"
             " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 60},\n"
             "                 {\"buffer\": 0, \"byteOffset\": 60, \"byteLength\": 18}],\n"
             " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 5, \"type\": \"VEC3\",\n"
             "                \"min\": [0, 0, 0], \"max\": [2, 1, 0]},\n"
             "               {\"bufferView\": 1, \"componentType\": 5123, \"count\": 9, \"type\": \"SCALAR\"}]}\n",
             b64);
    write_file("strip.gltf", text, 0, path);
}

/* The strip of check_bend as PLY, STL and glTF 2 reads exactly as the OBJ does. */
static void check_formats(void)
{
    char path[512];
    write_file("strip2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 0.5 0\n"
               "f 1 2 3\nf 2 4 3\nf 2 5 4\n", 0, path);
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 1e5f, 1e3f);
    cvk_topology obj = read_ok("strip2.obj", &c);

    write_file("strip.ply", "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
               "property float y\nproperty float z\nelement face 3\n"
               "property list uchar int vertex_indices\nend_header\n"
               "0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 0.5 0\n3 0 1 2\n3 1 3 2\n3 1 4 3\n", 0, path);
    cvk_topology ply = read_ok("strip.ply", &c);
    CHECK(same_topology(&obj, &ply), "strip.ply reads differently from strip.obj");
    cvk_topology_destroy(&ply);

    write_file("strip.stl", "solid strip\n"
               "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
               "facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\n"
               "facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 2 0.5 0\nvertex 1 1 0\nendloop\nendfacet\n"
               "endsolid strip\n", 0, path);
    cvk_topology stl = read_ok("strip.stl", &c);
    CHECK(same_topology(&obj, &stl), "strip.stl reads differently from strip.obj");
    cvk_topology_destroy(&stl);

    write_gltf(path);
    cvk_topology gltf = read_ok("strip.gltf", &c);
    CHECK(same_topology(&obj, &gltf), "strip.gltf reads differently from strip.obj");
    cvk_topology_destroy(&gltf);
    cvk_topology_destroy(&obj);
}

/* ---- bad input ------------------------------------------------------------------------------- */

/* Reads path as cloth 3 and checks the result and the message; with prefix_only, only that the
   message starts with want and is one line (Assimp's own reasons vary between versions). */
static void expect_error(const char* path, cvk_result want, const char* want_message,
                         bool prefix_only)
{
    cvk_cloth_desc c = mesh_desc(path, 1e6f, 1e5f, 1e3f);
    cvk_topology t;
    memset(&t, 0xab, sizeof t);
    cvk_error err = {0};
    cvk_result r = cvk_topology_mesh(&c, 3, &t, &err);
    bool match = prefix_only ? strncmp(err.message, want_message, strlen(want_message)) == 0 &&
                                   !strchr(err.message, '\n')
                             : strcmp(err.message, want_message) == 0;
    CHECK(r == want && err.result == want, "%s: returned %s, expected %s", path,
          cvk_result_name(r), cvk_result_name(want));
    CHECK(match, "%s: message\n  \"%s\"\nexpected%s\n  \"%s\"", path, err.message,
          prefix_only ? " to start with" : "", want_message);
    CHECK(t.position == NULL && t.springs == NULL && t.triangles == NULL && t.vertex_count == 0,
          "%s: the topology is not left empty on failure", path);
    if (r == CVK_SUCCESS)
        cvk_topology_destroy(&t);
}

static void expect_invalid(const char* name, const char* text, const char* problem)
{
    char path[512], want[1024];
    write_file(name, text, 0, path);
    snprintf(want, sizeof want, "cloths.3.mesh: %s%s", path, problem);
    expect_error(path, CVK_ERROR_INVALID_ARGUMENT, want, false);
}

/* Makes `path` a sparse file of `size` bytes (no disk is used). */
static bool truncate_to(const char* path, uint64_t size)
{
    FILE* f = fopen(path, "wb");
    if (!f)
        return false;
    fclose(f);
    return truncate(path, (off_t)size) == 0;
}

static void check_bad_input(void)
{
    char path[512], want[1024];
    snprintf(path, sizeof path, "%s/missing.obj", temp_dir);
    snprintf(want, sizeof want, "cloths.3.mesh: cannot read %s: No such file or directory", path);
    expect_error(path, CVK_ERROR_IO, want, false);

    snprintf(path, sizeof path, "%s/fifo.obj", temp_dir);
    if (mkfifo(path, 0600) == 0) { /* reading it would block: refused before opening */
        snprintf(want, sizeof want, "cloths.3.mesh: cannot read %s: it is not a regular file",
                 path);
        expect_error(path, CVK_ERROR_IO, want, false);
        remove(path);
    }

    /* A sparse file past the size bound: refused from its size, before Assimp reads it. */
    snprintf(path, sizeof path, "%s/huge.obj", temp_dir);
    bool made = truncate_to(path, CVK_MAX_MESH_BYTES + 1);
    CHECK(made, "could not make the sparse file %s: %s", path, strerror(errno));
    if (made) {
        snprintf(want, sizeof want, "cloths.3.mesh: cannot read %s: 1073741825 bytes; a mesh "
                 "file is at most 1073741824", path);
        expect_error(path, CVK_ERROR_IO, want, false);
    }
    remove(path);

    snprintf(path, sizeof path, "%s/folder.obj", temp_dir);
    mkdir(path, 0700);
    snprintf(want, sizeof want, "cloths.3.mesh: cannot read %s: it is a directory", path);
    expect_error(path, CVK_ERROR_IO, want, false);
    rmdir(path);

    unsigned char garbage[300];
    harness_rng rng = {12345};
    for (size_t i = 0; i < sizeof garbage; i++)
        garbage[i] = (unsigned char)harness_next(&rng);
    write_file("garbage.stl", (const char*)garbage, sizeof garbage, path);
    snprintf(want, sizeof want, "cloths.3.mesh: cannot read %s: ", path);
    expect_error(path, CVK_ERROR_IO, want, true);

    expect_invalid("lines.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\nl 2 3\np 1\n", " has no triangles");
    expect_invalid("points.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\n", " has no triangles");
    expect_invalid("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 nan 0\nf 1 2 3\nf 2 4 3\n",
                   ": vertex 3 has a coordinate that is not a finite number");
    expect_invalid("collinear.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n"
                   "f 1 2 3\nf 3 4 5\n", ": face 1 is degenerate (zero area)");
    expect_invalid("welded.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 1 0.0000000001\n"
                   "f 1 2 3\nf 2 3 4\n", ": face 1 is degenerate (zero area)");
    expect_invalid("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                   "f 1 2 3\nf 2 1 4\nf 1 2 5\n",
                   ": the edge between vertices 0 and 1 is shared by 3 faces (non-manifold)");
    expect_invalid("twice.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 3\n",
                   ": the faces on the edge between vertices 0 and 1 both have corner 2 (a face "
                   "repeated)");
    expect_invalid("far.obj", "v 0 0 0\nv 1e30 0 0\nv 0 1e30 0\nf 1 2 3\n",
                   ": vertex 1 lies 1e+30 m from the origin on axis x (after the transform); "
                   "positions are single-precision metres, at most 100000 m");
    expect_invalid("tiny.obj", "v 0 0 0\nv 1e-30 0 0\nv 0 1e-30 0\nf 1 2 3\n",
                   ": the mesh is 1.41421e-30 m across (after the transform); positions are "
                   "single-precision metres, at least 0.0001 m across");
    expect_invalid("concave.obj", "v 0 0 0\nv 2 0 0\nv 1 0.5 0\nv 2 2 0\nv 0 2 0\nf 1 2 3 4 5\n",
                   ": face 0 has 5 corners and is not planar and convex, so it cannot be split "
                   "into triangles; triangulate it");
    expect_invalid("range.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                   "property float y\nproperty float z\nelement face 1\n"
                   "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n"
                   "3 0 1 7\n", ": face 0 refers to vertex 7 of a mesh of 3 vertices");
    /* Counts in a PLY header are checked before Assimp reserves memory for them (4e9 faces
       were "std::bad_alloc"). */
    expect_invalid("huge.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                   "property float y\nproperty float z\nelement face 4000000000\n"
                   "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n"
                   "3 0 1 2\n", ": the mesh is too large: its header declares 4000000000 face "
                   "elements, and a mesh may have at most 1073741824");
    expect_invalid("vertices.ply", "ply\nformat binary_little_endian 1.0\n"
                   "element vertex 1073741825\nproperty float x\nend_header\n",
                   ": the mesh is too large: its header declares 1073741825 vertex elements, and "
                   "a mesh may have at most 1073741824");
    expect_invalid("short.ply", "ply\nformat ascii 1.0\ncomment 50 faces, none given\n"
                   "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 50\nproperty list uchar int vertex_indices\nend_header\n"
                   "0 0 0\n1 0 0\n", ": its header declares 53 elements in all, more than the "
                   "12 bytes after it hold (a count is wrong or the file is cut short)");
}

/* ---- two threads reading bad files at once ---------------------------------------------------- */

typedef struct reader_thread {
    char path[512];
    char first[sizeof ((cvk_error*)0)->message]; /* the message of the file read alone */
    int others;                        /* reads whose message differed from it */
    int successes;                     /* reads that did not fail */
} reader_thread;

#define THREAD_READS 400

static void* read_again(void* arg)
{
    reader_thread* t = arg;
    cvk_cloth_desc c = mesh_desc(t->path, 1e6f, 1e5f, 1e3f);
    for (int i = 0; i < THREAD_READS; i++) {
        cvk_topology top;
        cvk_error err = {0};
        if (cvk_topology_mesh(&c, 3, &top, &err) == CVK_SUCCESS) {
            cvk_topology_destroy(&top);
            t->successes++;
        } else if (strcmp(err.message, t->first) != 0) {
            t->others++;
        }
    }
    return NULL;
}

/* Two threads each read a bad file of another format 400 times at once, and every read gets its
   own file's message. Through Assimp's C interface, whose last error is one string for the
   process, a thread read the other's message in 2-8 % of its reads on the 2-core VM
   (lib/topology/assimp_import.h). */
static void check_threads(void)
{
    reader_thread t[2] = {0};
    write_file("threads.stl", "not an STL file\n", 0, t[0].path);
    write_file("threads.obj", "v 1 2\n", 0, t[1].path);
    for (int i = 0; i < 2; i++) {
        cvk_cloth_desc c = mesh_desc(t[i].path, 1e6f, 1e5f, 1e3f);
        cvk_topology top;
        cvk_error err = {0};
        cvk_result r = cvk_topology_mesh(&c, 3, &top, &err);
        CHECK(r == CVK_ERROR_IO, "%s: returned %s alone, expected CVK_ERROR_IO", t[i].path,
              cvk_result_name(r));
        snprintf(t[i].first, sizeof t[i].first, "%s", err.message);
    }
    CHECK(strcmp(t[0].first, t[1].first) != 0, "the two files gave one message: %s", t[0].first);
    pthread_t thread[2];
    bool started[2];
    for (int i = 0; i < 2; i++) {
        started[i] = pthread_create(&thread[i], NULL, read_again, &t[i]) == 0;
        CHECK(started[i], "could not start thread %d", i);
    }
    for (int i = 0; i < 2; i++)
        if (started[i])
            pthread_join(thread[i], NULL);
    for (int i = 0; i < 2; i++) {
        CHECK(t[i].successes == 0, "%s: %d of %d reads did not fail", t[i].path, t[i].successes,
              THREAD_READS);
        CHECK(t[i].others == 0, "%s: %d of %d reads beside another thread gave another message "
              "than \"%s\"", t[i].path, t[i].others, THREAD_READS, t[i].first);
    }
    if (t[0].others == 0 && t[1].others == 0)
        printf("two threads, %d reads each of %s and %s: each its own message\n", THREAD_READS,
               t[0].path, t[1].path);
}

int main(void)
{
    snprintf(temp_dir, sizeof temp_dir, "%s/clothvk-topology-XXXXXX",
             getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    if (!mkdtemp(temp_dir)) {
        fprintf(stderr, "cannot make a temporary folder: %s\n", strerror(errno));
        return 1;
    }
    check_example("poncho.obj", 755, 2106, 1351, 1);
    check_example("flag.obj", 654, 1833, 1180, 0);
    check_stl_welding();
    check_seam_welding();
    check_two_objects();
    check_obj_vertex_order();
    check_transform();
    check_quads();
    check_pentagon();
    check_bend();
    check_formats();
    check_bad_input();
    check_threads();

    for (int i = 0; i < written_count; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s/%.63s", temp_dir, written[i]);
        unlink(path);
    }
    rmdir(temp_dir);
    return harness_finish(NULL);
}
