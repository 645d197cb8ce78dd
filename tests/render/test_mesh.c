/* Mesh generation on the device:
   - a w x h grid has 2 (w − 1)(h − 1) triangles, every index names a vertex, each cloth's
     range follows the previous one, and a 1 x N rope has none;
   - vertex positions are the particles' positions bit for bit, in user order;
   - on a flat cloth every normal is unit length and equals u_axis × v_axis normalised; lying
     flat with u × v up, they point to the side the default key light (from above) lights;
   - on a bumpy cloth normals are the area-weighted averages of the adjacent face normals
     (compared with a double-precision host computation);
   - a torn spring (its flag cleared, as tearing will do) turns exactly the triangles along it
     into degenerate ones while the index count stays the same;
   - the rim of a cloth with a material thickness t: on an 8 x 6 grid, one quad per border edge
     (24), each joining the edge's ends moved ±t/2 along their normals, its normal of unit
     length across the border and away from the cloth, wound to face it; with tearing every edge
     has one, collapsed to a point while the edge has two live triangles, and clearing one
     interior spring's flag opens the 4 other edges of its 2 triangles (28 quads);
   - recording the simulation and the mesh into one command buffer passes synchronisation
     validation. */
#include "harness.h"
#include "recorded.h"

#include "render/mesh.h"
#include "regenerate.h"

/* ---- reading device buffers back ---- */

typedef struct mesh_data {
    cvk_mesh_buffers info;
    float* vertices;   /* 8 floats per vertex: position, 1, normal, 0 */
    uint32_t* indices;
} mesh_data;

static mesh_data read_mesh(cvk_context* ctx, cvk_mesh* mesh)
{
    mesh_data d = {.info = cvk_mesh_get_buffers(mesh)};
    d.vertices = harness_read_buffer(ctx, d.info.vertex_buffer, (VkDeviceSize)d.info.vertex_count * d.info.vertex_stride);
    d.indices = harness_read_buffer(ctx, d.info.index_buffer, (VkDeviceSize)d.info.index_count * 4u);
    return d;
}

static void free_mesh(mesh_data* d)
{
    free(d->vertices);
    free(d->indices);
}

/* The structural spring between vertices ua and ub torn as tearing tears one (its flag
   cleared), and the mesh regenerated. */
static void tear_spring(cvk_context* ctx, cvk_sim* sim, cvk_mesh* mesh, uint32_t ua, uint32_t ub)
{
    cvk_error err;
    const cvk_build* b = &sim->build;
    uint32_t torn = UINT32_MAX;
    for (uint32_t s = 0; s < b->spring_count; s++) {
        uint32_t a = b->user_of[b->springs[s].a], bb = b->user_of[b->springs[s].b];
        if (b->springs[s].type == CVK_SPRING_STRUCTURAL && ((a == ua && bb == ub) || (a == ub && bb == ua)))
            torn = s;
    }
    if (torn == UINT32_MAX) {
        fprintf(stderr, "no structural spring between vertices %u and %u\n", ua, ub);
        exit(1);
    }
    uint32_t* flags = malloc((size_t)b->spring_count * 4u);
    if (!flags)
        exit(1);
    for (uint32_t s = 0; s < b->spring_count; s++)
        flags[s] = s != torn;
    cvk_submitter sub;
    VkCommandBuffer cmd;
    REQUIRE_OK(cvk_submitter_create(ctx, &sub, &err), err);
    REQUIRE_OK(cvk_command_buffer_allocate(ctx, &sub, &cmd, &err), err);
    REQUIRE_OK(cvk_buffer_upload(ctx, &sub, cmd, &sim->spring_alive, flags, (VkDeviceSize)b->spring_count * 4u,
                                 &err), err);
    cvk_submitter_destroy(ctx, &sub);
    free(flags);
    harness_regenerate(ctx, mesh);
}

static cvk_sim* make_sim(cvk_context* ctx, cvk_cloth_desc* cloths, uint32_t count)
{
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = count;
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    return sim;
}

static cvk_cloth_desc grid_cloth(uint32_t w, uint32_t h)
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = w;
    c.grid[1] = h;
    return c;
}

/* ---- the facts ---- */

static void triangle_counts(cvk_context* ctx)
{
    cvk_cloth_desc cloths[3] = {grid_cloth(7, 5), grid_cloth(1, 12), grid_cloth(2, 2)};
    cloths[1].origin[1] = 3.0f;
    cloths[2].origin[1] = 5.0f;
    cloths[2].stiffness.shear = 1e5f;
    cvk_sim* sim = make_sim(ctx, cloths, 3);
    cvk_error err;
    cvk_mesh* mesh;
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    mesh_data d = read_mesh(ctx, mesh);
    CHECK(d.info.vertex_count == 35 + 12 + 4, "vertex count %u", d.info.vertex_count);
    CHECK(d.info.index_count == 3 * (2 * 6 * 4 + 0 + 2), "index count %u, expected %d", d.info.index_count,
          3 * (2 * 6 * 4 + 2));
    CHECK(d.info.cloth_count == 3, "cloth count %u", d.info.cloth_count);
    uint32_t expected[3] = {3 * 2 * 6 * 4, 0, 3 * 2};
    uint32_t first = 0;
    for (uint32_t c = 0; c < 3 && d.info.cloth_count == 3; c++) {
        CHECK(d.info.cloths[c].first_index == first && d.info.cloths[c].index_count == expected[c],
              "cloth %u: indices %u + %u, expected %u + %u", c, d.info.cloths[c].first_index,
              d.info.cloths[c].index_count, first, expected[c]);
        /* A cloth's triangles use its own vertices only. */
        uint32_t lo = c == 0 ? 0 : c == 1 ? 35 : 47, hi = c == 0 ? 35 : c == 1 ? 47 : 51;
        uint32_t outside = 0;
        for (uint32_t i = first; i < first + expected[c]; i++)
            outside += d.indices[i] < lo || d.indices[i] >= hi;
        CHECK(outside == 0, "cloth %u: %u indices name another cloth's vertices", c, outside);
        first += expected[c];
    }
    uint32_t bad = 0, degenerate = 0;
    for (uint32_t i = 0; i < d.info.index_count; i++)
        bad += d.indices[i] >= d.info.vertex_count;
    for (uint32_t t = 0; t < d.info.index_count / 3; t++)
        degenerate += d.indices[3 * t] == d.indices[3 * t + 1] || d.indices[3 * t + 1] == d.indices[3 * t + 2];
    CHECK(bad == 0, "%u indices out of range", bad);
    CHECK(degenerate == 0, "%u degenerate triangles on an intact cloth", degenerate);
    printf("7x5 + 1x12 + 2x2 cloths: %u triangles, %u vertices\n", d.info.index_count / 3, d.info.vertex_count);
    free_mesh(&d);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
}

static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void flat_normals(cvk_context* ctx, const float u[3], const float v[3])
{
    cvk_cloth_desc cloth = grid_cloth(9, 6);
    memcpy(cloth.u_axis, u, sizeof cloth.u_axis);
    memcpy(cloth.v_axis, v, sizeof cloth.v_axis);
    cvk_sim* sim = make_sim(ctx, &cloth, 1);
    cvk_error err;
    cvk_mesh* mesh;
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    mesh_data d = read_mesh(ctx, mesh);
    double du[3] = {u[0], u[1], u[2]}, dv[3] = {v[0], v[1], v[2]}, n[3];
    cross3(du, dv, n);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double worst = 0.0;
    for (uint32_t i = 0; i < d.info.vertex_count; i++) {
        const float* normal = &d.vertices[8 * i + 4];
        for (int k = 0; k < 3; k++)
            worst = fmax(worst, fabs(normal[k] - n[k] / len));
    }
    CHECK(worst < 1e-5, "u = [%g %g %g], v = [%g %g %g]: normals differ from u x v normalised by up to %g",
          u[0], u[1], u[2], v[0], v[1], v[2], worst);
    /* Lying flat with u x v up, the cloth's normals face the default key light, which shines
       from above: the side they point to is the lit side. */
    if (n[1] > 0.99 * len) {
        const float* key = cvk_default_render_desc().key.direction;
        uint32_t away = 0;
        for (uint32_t i = 0; i < d.info.vertex_count; i++) {
            const float* normal = &d.vertices[8 * i + 4];
            away += normal[0] * key[0] + normal[1] * key[1] + normal[2] * key[2] <= 0.0f;
        }
        CHECK(away == 0, "%u normals of a flat cloth face away from the key light above it", away);
    }
    free_mesh(&d);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
}

/* Host reference: area-weighted vertex normals of the mesh's triangles, in double. */
static void reference_normals(const mesh_data* d, double* out)
{
    memset(out, 0, 3 * sizeof(double) * d->info.vertex_count);
    for (uint32_t t = 0; t < d->info.index_count / 3; t++) {
        const uint32_t* tri = &d->indices[3 * t];
        const float* a = &d->vertices[8 * tri[0]];
        const float* b = &d->vertices[8 * tri[1]];
        const float* c = &d->vertices[8 * tri[2]];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3];
        cross3(e1, e2, n);
        for (int k = 0; k < 3; k++)
            for (int e = 0; e < 3; e++)
                out[3 * tri[k] + e] += n[e];
    }
}

static void bumpy_normals_and_tearing(cvk_context* ctx)
{
    cvk_cloth_desc cloth = grid_cloth(12, 10);
    cloth.stiffness.shear = 1e5f;
    /* A cloth that may tear (it is never stepped: the test tears a spring itself); without
       tearing the mesh pass never reads the springs. */
    cloth.tearing.max_stretch = 5.0f;
    cvk_sim* sim = make_sim(ctx, &cloth, 1);
    uint64_t n = cvk_sim_particle_count(sim);
    float* xyz = harness_read_all(sim);
    harness_rng rng = {12345};
    for (uint64_t p = 0; p < n; p++)
        xyz[3 * p + 1] += (float)harness_uniform(&rng, -0.03, 0.03);
    cvk_error err;
    REQUIRE_OK(cvk_sim_write_positions(sim, xyz, n, &err), err);
    cvk_mesh* mesh;
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    mesh_data d = read_mesh(ctx, mesh);

    uint64_t mismatched = 0;
    for (uint64_t i = 0; i < 3 * n; i++)
        mismatched += memcmp(&d.vertices[8 * (i / 3) + i % 3], &xyz[i], sizeof(float)) != 0;
    CHECK(mismatched == 0, "%llu vertex coordinates differ from the particles'", (unsigned long long)mismatched);

    double* ref = malloc(3 * sizeof(double) * n);
    if (!ref)
        exit(1);
    reference_normals(&d, ref);
    double worst = 0.0, worst_length = 0.0;
    for (uint64_t v = 0; v < n; v++) {
        double len = sqrt(ref[3 * v] * ref[3 * v] + ref[3 * v + 1] * ref[3 * v + 1] + ref[3 * v + 2] * ref[3 * v + 2]);
        const float* normal = &d.vertices[8 * v + 4];
        double got = sqrt((double)normal[0] * normal[0] + (double)normal[1] * normal[1] + (double)normal[2] * normal[2]);
        worst_length = fmax(worst_length, fabs(got - 1.0));
        for (int k = 0; k < 3; k++)
            worst = fmax(worst, fabs(normal[k] - ref[3 * v + k] / len));
    }
    CHECK(worst < 2e-5, "normals differ from the area-weighted host normals by up to %g", worst);
    CHECK(worst_length < 2e-6, "normal length differs from 1 by up to %g", worst_length);
    printf("bumpy 12x10: normals within %.2g of the host's area-weighted normals, |n| within %.2g of 1\n", worst,
           worst_length);

    /* Tear the structural spring between [4, 3] and [5, 3], as tearing will. */
    uint32_t ua = 3 * 12 + 4, ub = ua + 1;
    tear_spring(ctx, sim, mesh, ua, ub);
    mesh_data torn_mesh = read_mesh(ctx, mesh);
    CHECK(torn_mesh.info.index_count == d.info.index_count, "index count changed from %u to %u",
          d.info.index_count, torn_mesh.info.index_count);
    uint32_t changed = 0, degenerate = 0, along_edge = 0;
    for (uint32_t t = 0; t < d.info.index_count / 3; t++) {
        const uint32_t* before = &d.indices[3 * t];
        const uint32_t* after = &torn_mesh.indices[3 * t];
        bool dead = after[0] == after[1] && after[1] == after[2];
        bool has_edge = (before[0] == ua || before[1] == ua || before[2] == ua) &&
                        (before[0] == ub || before[1] == ub || before[2] == ub);
        changed += memcmp(before, after, 12) != 0;
        degenerate += dead;
        along_edge += dead && has_edge;
    }
    CHECK(degenerate == 2 && along_edge == 2 && changed == 2,
          "tearing one interior edge: %u triangles changed, %u degenerate, %u of them along the edge "
          "(expected 2, 2, 2)", changed, degenerate, along_edge);
    printf("tearing the spring %u-%u: %u triangles became degenerate, index count still %u\n", ua, ub,
           degenerate, torn_mesh.info.index_count);
    free_mesh(&torn_mesh);
    free(ref);
    free(xyz);
    free_mesh(&d);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
}

/* The rim's quads: how many are open (not collapsed to a point), and how many of the open
   ones are wrong: each must join its ends moved ±half along the normals (the flat cloth in
   y = 0, normals along ±y), have a unit normal across the border, pointing away from the
   cloth's centre c, or, within `reach` of the hole's centre h (x, z), into the hole, and be
   wound to face where its normal points. */
static uint32_t open_rim_quads(cvk_context* ctx, cvk_mesh* mesh, float half, const double c[2], const double h[2],
                               double reach, uint32_t* bad)
{
    float* rim = harness_read_buffer(ctx, mesh->rim_vertices.buffer, (VkDeviceSize)mesh->rim_edge_count * 4 * 32);
    uint32_t open = 0;
    *bad = 0;
    for (uint32_t k = 0; k < mesh->rim_edge_count; k++) {
        const float* q = &rim[32 * (size_t)k]; /* 4 vertices of 8 floats: position, 1, normal, 0 */
        bool point = true;
        for (int i = 1; i < 4; i++)
            point = point && memcmp(&q[8 * i], q, 3 * sizeof(float)) == 0;
        if (point)
            continue;
        open++;
        /* (a−, b−, b+, a+) */
        double e[3], up[3], turn[3];
        for (int j = 0; j < 3; j++) {
            e[j] = (double)q[8 + j] - q[j];
            up[j] = (double)q[16 + j] - q[j];
        }
        cross3(e, up, turn);
        const float* n = &q[4];
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        double mid[2] = {0.5 * (q[0] + q[8]), 0.5 * (q[2] + q[10])};
        bool in_hole = hypot(mid[0] - h[0], mid[1] - h[1]) < reach;
        double away = in_hole ? -(n[0] * (mid[0] - h[0]) + n[2] * (mid[1] - h[1]))
                              : n[0] * (mid[0] - c[0]) + n[2] * (mid[1] - c[1]);
        bool ok = fabs(len - 1.0) < 1e-5 && fabs(n[1]) < 1e-6 && away > 0.0 &&
                  turn[0] * n[0] + turn[1] * n[1] + turn[2] * n[2] > 0.0;
        /* a+ − a− and b+ − b−: the thickness along y, nothing across */
        for (int end = 0; end < 2; end++) {
            const float* minus = &q[8 * end];
            const float* plus = &q[8 * (3 - end)];
            ok = ok && fabs(fabs((double)plus[1] - minus[1]) - 2.0 * half) < 1e-6 && plus[0] == minus[0] &&
                 plus[2] == minus[2];
        }
        *bad += !ok;
    }
    free(rim);
    return open;
}

static void rim(cvk_context* ctx)
{
    const float half = 0.01f;
    for (int tearing = 0; tearing < 2; tearing++) {
        cvk_cloth_desc cloth = grid_cloth(8, 6);
        cloth.thickness = 2.0f * half;
        cloth.tearing.max_stretch = tearing ? 0.5f : 0.0f;
        cvk_sim* sim = make_sim(ctx, &cloth, 1);
        cvk_error err;
        cvk_mesh* mesh;
        REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
        /* the grid spans origin + [0, size] along u = x and v = z; the spring torn below runs
           from [3, 2] to [4, 2], and its two triangles make the hole */
        double dx = cloth.size[0] / 7.0, dz = cloth.size[1] / 5.0;
        double c[2] = {cloth.origin[0] + 0.5 * cloth.size[0], cloth.origin[2] + 0.5 * cloth.size[1]};
        double h[2] = {cloth.origin[0] + 3.5 * dx, cloth.origin[2] + 2.0 * dz};
        double reach = 1.2 * fmax(dx, dz);
        uint32_t edges = tearing ? 7 * 6 + 8 * 5 + 7 * 5 : 2 * (7 + 5);
        CHECK(mesh->rim_edge_count == edges, "an 8 x 6 grid %s tearing has %u rim edges, expected %u",
              tearing ? "with" : "without", mesh->rim_edge_count, edges);
        CHECK(mesh->rims[0].index_count == 6 * edges, "the rim's index range holds %u indices, expected %u",
              mesh->rims[0].index_count, 6 * edges);
        uint32_t bad;
        uint32_t open = open_rim_quads(ctx, mesh, half, c, h, reach, &bad);
        CHECK(open == 24 && bad == 0, "%s tearing: %u open rim quads (expected the 24 border edges), %u wrong",
              tearing ? "with" : "without", open, bad);
        if (tearing) {
            /* Tear the structural spring between [3, 2] and [4, 2]. */
            tear_spring(ctx, sim, mesh, 2 * 8 + 3, 2 * 8 + 4);
            uint32_t bad_torn;
            uint32_t open_torn = open_rim_quads(ctx, mesh, half, c, h, reach, &bad_torn);
            CHECK(open_torn == 28 && bad_torn == 0, "tearing one interior spring opens %u rim quads (expected 28: "
                  "the border's and the hole's 4), %u wrong", open_torn, bad_torn);
            printf("rim: 8 x 6 grid, %u border quads; with tearing %u edges, one torn spring: %u open\n", open, edges,
                   open_torn);
        }
        cvk_mesh_destroy(mesh);
        cvk_sim_destroy(sim);
    }
}

/* One command buffer: three frames of simulation, the mesh, then a copy of the vertices: the
   barriers of the contract (the library's and the one the caller records) are all it takes. */
static void record_with_simulation(cvk_context* ctx)
{
    cvk_cloth_desc cloth = grid_cloth(16, 16);
    static const uint32_t pins[2][2] = {{0, 0}, {15, 0}};
    cloth.pins = pins;
    cloth.pin_count = 2;
    cvk_sim* sim = make_sim(ctx, &cloth, 1);
    cvk_error err;
    cvk_mesh* mesh;
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    cvk_submitter sub;
    VkCommandBuffer cmd;
    REQUIRE_OK(cvk_submitter_create(ctx, &sub, &err), err);
    REQUIRE_OK(cvk_command_buffer_allocate(ctx, &sub, &cmd, &err), err);
    REQUIRE_OK(cvk_command_buffer_begin(cmd, 0, &err), err);
    REQUIRE_OK(cvk_sim_record(sim, cmd, 3, &err), err);
    REQUIRE_OK(cvk_mesh_record(mesh, cmd, &err), err);
    REQUIRE_OK(cvk_command_buffer_end(cmd, &err), err);
    REQUIRE_OK(cvk_submit_and_wait(ctx, &sub, &cmd, 1, &err), err);
    REQUIRE_OK(cvk_submit_and_wait(ctx, &sub, &cmd, 1, &err), err);
    cvk_submitter_destroy(ctx, &sub);
    float* xyz = harness_read_all(sim);
    mesh_data d = read_mesh(ctx, mesh);
    uint64_t mismatched = 0;
    for (uint64_t i = 0; i < 3 * cvk_sim_particle_count(sim); i++)
        mismatched += memcmp(&d.vertices[8 * (i / 3) + i % 3], &xyz[i], sizeof(float)) != 0;
    CHECK(mismatched == 0, "after 6 recorded frames, %llu vertex coordinates differ from the particles'",
          (unsigned long long)mismatched);
    CHECK(xyz[3 * 255 + 1] < 0.99f, "the cloth did not fall (corner at y = %g)", xyz[3 * 255 + 1]);
    free(xyz);
    free_mesh(&d);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    triangle_counts(ctx);
    flat_normals(ctx, (const float[3]){1, 0, 0}, (const float[3]){0, 0, 1});
    flat_normals(ctx, (const float[3]){0, 0, 1}, (const float[3]){1, 0, 0});
    flat_normals(ctx, (const float[3]){1, 0, 0}, (const float[3]){0, 1, 0});
    flat_normals(ctx, (const float[3]){0.6f, 0.8f, 0}, (const float[3]){0, 0, -2});
    bumpy_normals_and_tearing(ctx);
    rim(ctx);
    record_with_simulation(ctx);
    return harness_finish(ctx);
}
