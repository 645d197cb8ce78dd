/* Mesh generation: the triangle and adjacency tables are built once on the host; every frame
   one compute dispatch (shaders/render/mesh.comp) writes positions, normals and indices from the
   particles, straight into the buffers that are drawn. */
#include "render/mesh.h"

#include <stdlib.h>
#include <string.h>

#include "core/cookie.h"
#include "core/error.h"
#include "core/shaders.h"
#include "render/edge_key.h"
#include "render/split.h"

/* Mirrors the bindings of shaders/render/mesh.comp. */
enum {
    BINDING_POSITIONS,
    BINDING_SPRING_ALIVE,
    BINDING_TRIANGLE_VERTICES,
    BINDING_TRIANGLE_PARTICLES,
    BINDING_TRIANGLE_SPRINGS,
    BINDING_PARTICLE_OF,
    BINDING_VERTEX_TRIANGLES,
    BINDING_VERTICES,
    BINDING_INDICES,
    BINDING_RIM_EDGES,
    BINDING_RIM_VERTICES,
    BINDING_COUNT
};

#define VERTEX_STRIDE 32u

/* ---- tables, on the host ----------------------------------------------------------------- */

/* The triangle tables hold 2 · triangle_count rows of 4: row t the build's triangle t, row
   triangle_count + t the triangle that takes its place when its quad is drawn split along its
   other diagonal (a copy of row t where there is none). Row t's fourth entries: in
   triangle_vertices the spring along the quad's split diagonal, in triangle_springs the spring
   along its other diagonal, or NONE where t has no other split. */
typedef struct tables {
    uint32_t* triangle_vertices;  /* 4 per row */
    uint32_t* triangle_particles; /* 4 per row */
    uint32_t* triangle_springs;   /* 4 per row */
    bool* tearable;               /* per spring: it may tear (NULL: none may) */
    uint32_t* particle_of;        /* per vertex its particle, | CVK_MESH_HELD where it stays put */
    uint32_t* vertex_triangles;   /* max_adjacent per vertex, slot-major */
    uint32_t* rim_edges;          /* 8 per rim edge (at least one) */
    uint32_t* rim_indices;        /* 6 per rim edge (at least one) */
} tables;

static void tables_free(tables* t)
{
    free(t->triangle_vertices);
    free(t->triangle_particles);
    free(t->triangle_springs);
    free(t->tearable);
    free(t->particle_of);
    free(t->vertex_triangles);
    free(t->rim_edges);
    free(t->rim_indices);
}

/* The build's triangles, whatever topology they came from, padded to 4 entries for the
   shader: vertices in user order, their particles, the spring along each edge. */
static void make_triangles(const cvk_build* b, tables* t, cvk_mesh_range* ranges)
{
    size_t other = 4 * (size_t)b->triangle_count;
    for (uint32_t tri = 0; tri < b->triangle_count; tri++) {
        for (int e = 0; e < 3; e++) {
            uint32_t user = b->triangles[3 * (size_t)tri + e];
            t->triangle_vertices[4 * (size_t)tri + e] = user;
            t->triangle_particles[4 * (size_t)tri + e] = b->internal_of[user];
            t->triangle_springs[4 * (size_t)tri + e] = b->triangle_springs[3 * (size_t)tri + e];
        }
        t->triangle_vertices[4 * (size_t)tri + 3] = UINT32_MAX;
        t->triangle_springs[4 * (size_t)tri + 3] = UINT32_MAX;
        memcpy(&t->triangle_vertices[other + 4 * (size_t)tri], &t->triangle_vertices[4 * (size_t)tri], 16);
        memcpy(&t->triangle_particles[other + 4 * (size_t)tri], &t->triangle_particles[4 * (size_t)tri], 16);
        memcpy(&t->triangle_springs[other + 4 * (size_t)tri], &t->triangle_springs[4 * (size_t)tri], 16);
    }
    for (uint32_t c = 0; c < b->cloth_count; c++) {
        ranges[c].first_index = 3u * b->cloths[c].first_triangle;
        ranges[c].index_count = 3u * b->cloths[c].triangle_count;
    }
}

static uint32_t count_triangles(const cvk_build* b)
{
    return b->triangle_count;
}

/* Whether row r of the triangle tables names vertex v. */
static bool row_has(const tables* t, size_t r, uint32_t v)
{
    const uint32_t* row = &t->triangle_vertices[4 * r];
    return row[0] == v || row[1] == v || row[2] == v;
}

/* Per vertex, the triangles that may hold it: first those whose own row names it, in the
   order of the build (the order a cloth without another split always had, so its normals
   keep their bits), then those whose other split's row does. */
static cvk_result make_adjacency(cvk_mesh* m, tables* t, cvk_error* error)
{
    uint32_t* degree = calloc(m->vertex_count ? m->vertex_count : 1, sizeof *degree);
    if (!degree)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the mesh adjacency");
    size_t other = m->triangle_count;
    for (uint32_t tri = 0; tri < m->triangle_count; tri++)
        for (int e = 0; e < 3; e++) {
            degree[t->triangle_vertices[4 * (size_t)tri + e]]++;
            uint32_t v = t->triangle_vertices[4 * (other + tri) + e];
            if (!row_has(t, tri, v))
                degree[v]++;
        }
    m->max_adjacent = 1;
    for (uint32_t v = 0; v < m->vertex_count; v++)
        if (degree[v] > m->max_adjacent)
            m->max_adjacent = degree[v];
    size_t entries = (size_t)m->max_adjacent * m->vertex_count;
    t->vertex_triangles = malloc((entries ? entries : 1) * sizeof(uint32_t));
    if (!t->vertex_triangles) {
        free(degree);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the mesh adjacency");
    }
    memset(t->vertex_triangles, 0xff, entries * sizeof(uint32_t));
    memset(degree, 0, m->vertex_count * sizeof *degree);
    for (uint32_t tri = 0; tri < m->triangle_count; tri++)
        for (int e = 0; e < 3; e++) {
            uint32_t v = t->triangle_vertices[4 * (size_t)tri + e];
            t->vertex_triangles[(size_t)degree[v]++ * m->vertex_count + v] = tri;
        }
    for (uint32_t tri = 0; tri < m->triangle_count; tri++)
        for (int e = 0; e < 3; e++) {
            uint32_t v = t->triangle_vertices[4 * (other + tri) + e];
            if (!row_has(t, tri, v))
                t->vertex_triangles[(size_t)degree[v]++ * m->vertex_count + v] = tri;
        }
    free(degree);
    return CVK_SUCCESS;
}

/* The rows of the other splits (lib/render/split.h) in the tables' second half, and in row t's
   fourth entries the two diagonals' springs. */
static cvk_result make_other_splits(const cvk_mesh* m, tables* t, cvk_error* error)
{
    cvk_other_split* splits;
    cvk_result r = cvk_other_splits(m->sim, &splits, error);
    if (r != CVK_SUCCESS || !splits)
        return r;
    const cvk_build* b = &m->sim->build;
    size_t other = 4 * (size_t)b->triangle_count;
    for (uint32_t tri = 0; tri < b->triangle_count; tri++) {
        const cvk_other_split* o = &splits[tri];
        if (o->across == UINT32_MAX)
            continue;
        size_t row = other + 4 * (size_t)tri;
        for (int e = 0; e < 3; e++) {
            t->triangle_vertices[row + e] = o->vertices[e];
            t->triangle_particles[row + e] = b->internal_of[o->vertices[e]];
            t->triangle_springs[row + e] = o->springs[e];
        }
        t->triangle_vertices[4 * (size_t)tri + 3] = o->split;
        t->triangle_springs[4 * (size_t)tri + 3] = o->across;
    }
    free(splits);
    return CVK_SUCCESS;
}

/* Whether a spring along one of the triangle's edges may tear (the triangle then goes). */
static bool may_tear(const tables* t, uint32_t triangle)
{
    for (int e = 0; e < 3; e++) {
        uint32_t s = t->triangle_springs[4 * (size_t)triangle + e];
        if (s != UINT32_MAX && t->tearable && t->tearable[s])
            return true;
    }
    return false;
}

/* The rim edges of one cloth with a thickness, appended from edges[*count]: its border edges,
   and with tearing every edge with a triangle that may go, and the other diagonal of every
   quad that may be drawn split along it. Per edge its ends and the triangles that may hold it
   (those whose row names it, then those whose other split's row does; at most 4, and the first
   two where only the rows name it). `half_edges` has room for the cloth's 6 per triangle. */
static void add_rim_edges(const cvk_cloth_range* cloth, uint32_t triangle_count, const tables* t,
                          cvk_edge_key* half_edges, uint32_t* edges, uint32_t* ends, uint32_t* count)
{
    uint32_t n = 0;
    size_t other = triangle_count;
    for (uint32_t tri = cloth->first_triangle; tri < cloth->first_triangle + cloth->triangle_count; tri++)
        for (uint32_t e = 0; e < 3; e++) {
            uint32_t a = t->triangle_vertices[4 * (size_t)tri + e];
            uint32_t b = t->triangle_vertices[4 * (size_t)tri + (e + 1) % 3];
            half_edges[n++] = cvk_edge_key_of(a, b, tri, e, 0);
            if (t->triangle_springs[4 * (size_t)tri + 3] == UINT32_MAX)
                continue;
            a = t->triangle_vertices[4 * (other + tri) + e];
            b = t->triangle_vertices[4 * (other + tri) + (e + 1) % 3];
            half_edges[n++] = cvk_edge_key_of(a, b, tri, e, 1);
        }
    cvk_sort_edge_keys(half_edges, n);
    float half_thickness = 0.5f * cloth->thickness;
    uint32_t bits;
    memcpy(&bits, &half_thickness, sizeof bits);
    for (uint32_t i = 0; i < n;) {
        uint32_t j = i + 1;
        while (j < n && cvk_same_edge(&half_edges[j], &half_edges[i]))
            j++;
        uint32_t own = 0, found = 0, candidates[4];
        bool tears = false;
        for (uint32_t h = i; h < j; h++) {
            own += !half_edges[h].other;
            uint32_t tri = half_edges[h].triangle;
            bool seen = false;
            for (uint32_t c = 0; c < found; c++)
                seen = seen || candidates[c] == tri;
            tears = tears || half_edges[h].other || may_tear(t, tri);
            if (!seen && found < 4)
                candidates[found++] = tri;
        }
        if (own == j - i && found > 2)
            found = 2; /* three or more triangles on an edge: the first two */
        if (own < 2 || tears) {
            uint32_t k = (*count)++;
            const cvk_edge_key* first = &half_edges[i];
            const uint32_t* row = &t->triangle_vertices[4 * ((first->other ? other : 0) + first->triangle)];
            uint32_t a = row[first->slot], b = row[(first->slot + 1) % 3];
            uint32_t entry[8] = {a, b, bits, 0, UINT32_MAX, UINT32_MAX, UINT32_MAX, UINT32_MAX};
            memcpy(&entry[4], candidates, found * sizeof *candidates);
            memcpy(&edges[8 * (size_t)k], entry, sizeof entry);
            ends[2 * (size_t)k] = a;
            ends[2 * (size_t)k + 1] = b;
        }
        i = j;
    }
}

/* Per vertex its particle, with CVK_MESH_HELD set where the drawing keeps it at its particle:
   the vertices of triangles none of whose springs may tear, and those on an edge of the
   cloth's own border (one triangle, or more than two). The others are smoothed along a torn
   border (mesh.comp, drawn_position). */
static cvk_result make_particle_of(cvk_mesh* m, tables* t, cvk_error* error)
{
    const cvk_build* b = &m->sim->build;
    t->particle_of = malloc((m->vertex_count ? m->vertex_count : 1) * sizeof *t->particle_of);
    size_t n = 3 * (size_t)m->triangle_count;
    cvk_edge_key* half_edges = t->tearable && n ? malloc(n * sizeof *half_edges) : NULL;
    if (!t->particle_of || (t->tearable && n && !half_edges)) {
        free(half_edges);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the mesh's vertices");
    }
    for (uint32_t v = 0; v < m->vertex_count; v++)
        t->particle_of[v] = b->internal_of[v] | CVK_MESH_HELD;
    if (!half_edges)
        return CVK_SUCCESS;
    for (uint32_t tri = 0; tri < m->triangle_count; tri++)
        for (uint32_t e = 0; e < 3; e++) {
            uint32_t a = t->triangle_vertices[4 * (size_t)tri + e];
            uint32_t c = t->triangle_vertices[4 * (size_t)tri + (e + 1) % 3];
            half_edges[3 * (size_t)tri + e] = cvk_edge_key_of(a, c, tri, e, 0);
            if (may_tear(t, tri))
                t->particle_of[a] &= ~CVK_MESH_HELD;
        }
    cvk_sort_edge_keys(half_edges, n);
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && cvk_same_edge(&half_edges[j], &half_edges[i]))
            j++;
        if (j - i != 2) {
            t->particle_of[half_edges[i].lo] |= CVK_MESH_HELD;
            t->particle_of[half_edges[i].hi] |= CVK_MESH_HELD;
        }
        i = j;
    }
    free(half_edges);
    return CVK_SUCCESS;
}

/* The rim: edge table, ends and index buffer for every cloth with a thickness. */
static cvk_result make_rim(cvk_mesh* m, tables* t, cvk_error* error)
{
    const cvk_build* b = &m->sim->build;
    size_t most = 0, largest = 0;
    for (uint32_t c = 0; c < b->cloth_count; c++)
        if (b->cloths[c].thickness > 0.0f) {
            most += 6 * (size_t)b->cloths[c].triangle_count;
            if (b->cloths[c].triangle_count > largest)
                largest = b->cloths[c].triangle_count;
        }
    m->rims = calloc(b->cloth_count, sizeof *m->rims);
    t->rim_edges = calloc(8 * (most ? most : 1), sizeof(uint32_t));
    m->rim_ends = calloc(2 * (most ? most : 1), sizeof(uint32_t));
    cvk_edge_key* half_edges = most ? malloc(6 * largest * sizeof *half_edges) : NULL;
    bool failed = !m->rims || !t->rim_edges || !m->rim_ends || (most && !half_edges);
    if (!failed) {
        uint32_t count = 0;
        for (uint32_t c = 0; c < b->cloth_count; c++) {
            m->rims[c].first_index = 6 * count;
            if (b->cloths[c].thickness > 0.0f)
                add_rim_edges(&b->cloths[c], m->triangle_count, t, half_edges, t->rim_edges, m->rim_ends,
                              &count);
            m->rims[c].index_count = 6 * count - m->rims[c].first_index;
        }
        m->rim_edge_count = count;
        size_t quads = count ? count : 1;
        t->rim_indices = malloc(6 * quads * sizeof(uint32_t));
        failed = !t->rim_indices;
        for (size_t k = 0; !failed && k < quads; k++) {
            uint32_t q = 4 * (uint32_t)k;
            uint32_t six[6] = {q, q + 1, q + 2, q, q + 2, q + 3};
            memcpy(&t->rim_indices[6 * k], six, sizeof six);
        }
    }
    free(half_edges);
    if (failed)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the rim of the cloths' thickness");
    return CVK_SUCCESS;
}

static cvk_result make_tables(cvk_mesh* m, tables* t, cvk_error* error)
{
    const cvk_build* b = &m->sim->build;
    const cvk_tear* tear = m->sim->tear;
    size_t rows = 2 * (size_t)(m->triangle_count ? m->triangle_count : 1);
    t->triangle_vertices = calloc(4 * rows, sizeof(uint32_t));
    t->triangle_particles = calloc(4 * rows, sizeof(uint32_t));
    t->triangle_springs = calloc(4 * rows, sizeof(uint32_t));
    m->cloths = calloc(b->cloth_count, sizeof *m->cloths);
    if (!t->triangle_vertices || !t->triangle_particles || !t->triangle_springs || !m->cloths)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %u triangles",
                        m->triangle_count);
    if (tear && tear->count) {
        t->tearable = calloc(b->spring_count, sizeof *t->tearable);
        if (!t->tearable)
            return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the spring flags");
        for (uint32_t i = 0; i < tear->count; i++)
            t->tearable[tear->spring[i]] = true;
    }
    make_triangles(b, t, m->cloths);
    cvk_result r = make_other_splits(m, t, error);
    if (r == CVK_SUCCESS)
        r = make_adjacency(m, t, error);
    if (r == CVK_SUCCESS)
        r = make_particle_of(m, t, error);
    return r == CVK_SUCCESS ? make_rim(m, t, error) : r;
}

/* ---- device objects ---------------------------------------------------------------------- */

static cvk_result check_limits(const cvk_mesh* m, cvk_error* error)
{
    const VkPhysicalDeviceLimits* limits = &m->context->properties.limits;
    uint64_t entries = (uint64_t)m->max_adjacent * m->vertex_count;
    if (2ull * m->triangle_count > limits->maxTexelBufferElements || entries > limits->maxTexelBufferElements)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "%u triangles (two rows each) with up to %u around a vertex need %llu table "
                        "entries; %s allows %u texel buffer elements (maxTexelBufferElements)",
                        m->triangle_count, m->max_adjacent, (unsigned long long)entries,
                        m->context->properties.deviceName, limits->maxTexelBufferElements);
    /* Both buffers the generation writes are bound whole as storage buffers. */
    uint64_t index_bytes = 12ull * m->triangle_count;
    uint64_t vertex_bytes = (uint64_t)VERTEX_STRIDE * m->vertex_count;
    if (index_bytes > limits->maxStorageBufferRange)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "%u triangles need a %llu-byte index buffer; %s allows %u bytes "
                        "(maxStorageBufferRange)",
                        m->triangle_count, (unsigned long long)index_bytes,
                        m->context->properties.deviceName, limits->maxStorageBufferRange);
    uint64_t rim_bytes = 4ull * VERTEX_STRIDE * m->rim_edge_count;
    if (rim_bytes > limits->maxStorageBufferRange || 2ull * m->rim_edge_count > limits->maxTexelBufferElements)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "the rim of the cloths' thickness has %u edges: %llu bytes of vertices; %s allows "
                        "%u bytes (maxStorageBufferRange) and %u texel buffer elements",
                        m->rim_edge_count, (unsigned long long)rim_bytes, m->context->properties.deviceName,
                        limits->maxStorageBufferRange, limits->maxTexelBufferElements);
    if (vertex_bytes > limits->maxStorageBufferRange)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "%u vertices need a %llu-byte vertex buffer; %s allows %u bytes "
                        "(maxStorageBufferRange)",
                        m->vertex_count, (unsigned long long)vertex_bytes,
                        m->context->properties.deviceName, limits->maxStorageBufferRange);
    return CVK_SUCCESS;
}

static cvk_result create_buffers(cvk_mesh* m, const cvk_mesh_desc* desc, const tables* t,
                                 VkCommandBuffer cmd, cvk_error* error)
{
    cvk_context* ctx = m->context;
    VkDeviceSize tris = m->triangle_count;
    VkDeviceSize rim = m->rim_edge_count ? m->rim_edge_count : 1; /* one unused edge without a rim */
    VkBufferUsageFlags table = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    struct {
        cvk_buffer* buffer;
        VkDeviceSize size;
        VkBufferUsageFlags usage;
        const char* what;
        const void* data;
        VkBufferView* view;
        VkFormat format;
    } list[] = {
        {&m->vertices, (VkDeviceSize)m->vertex_count * VERTEX_STRIDE,
         VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
             VK_BUFFER_USAGE_TRANSFER_SRC_BIT | desc->vertex_usage,
         "mesh vertices", NULL, NULL, VK_FORMAT_UNDEFINED},
        {&m->indices, tris * 12u,
         VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
             VK_BUFFER_USAGE_TRANSFER_SRC_BIT | desc->index_usage,
         "mesh indices", NULL, NULL, VK_FORMAT_UNDEFINED},
        {&m->triangle_vertices, 2u * tris * 16u, table, "triangle vertices", t->triangle_vertices,
         &m->view_triangle_vertices, VK_FORMAT_R32G32B32A32_UINT},
        {&m->triangle_particles, 2u * tris * 16u, table, "triangle particles", t->triangle_particles,
         &m->view_triangle_particles, VK_FORMAT_R32G32B32A32_UINT},
        {&m->triangle_springs, 2u * tris * 16u, table, "triangle springs", t->triangle_springs,
         &m->view_triangle_springs, VK_FORMAT_R32G32B32A32_UINT},
        {&m->particle_of, (VkDeviceSize)m->vertex_count * 4u, table, "vertex particles",
         t->particle_of, &m->view_particle_of, VK_FORMAT_R32_UINT},
        {&m->vertex_triangles, (VkDeviceSize)m->max_adjacent * m->vertex_count * 4u, table,
         "vertex triangles", t->vertex_triangles, &m->view_vertex_triangles, VK_FORMAT_R32_UINT},
        {&m->rim_edges, rim * 32u, table, "rim edges", t->rim_edges, &m->view_rim_edges,
         VK_FORMAT_R32G32B32A32_UINT},
        {&m->rim_vertices, rim * 4u * VERTEX_STRIDE,
         VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
         "rim vertices", NULL, NULL,
         VK_FORMAT_UNDEFINED},
        {&m->rim_indices, rim * 24u, VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
         "rim indices", t->rim_indices, NULL, VK_FORMAT_UNDEFINED},
    };
    for (size_t i = 0; i < sizeof list / sizeof list[0]; i++) {
        cvk_result r = cvk_buffer_create(ctx, list[i].size, list[i].usage, CVK_MEMORY_DEVICE,
                                         list[i].what, list[i].buffer, error);
        if (r == CVK_SUCCESS && list[i].data)
            r = cvk_buffer_upload(ctx, &m->submitter, cmd, list[i].buffer, list[i].data, list[i].size,
                                  error);
        if (r == CVK_SUCCESS && list[i].view)
            r = cvk_buffer_view_create(ctx, list[i].buffer, list[i].format, list[i].view, error);
        if (r != CVK_SUCCESS)
            return r;
    }
    return CVK_SUCCESS;
}

#define TEXEL {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 0}
#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
static const cvk_binding mesh_bindings[BINDING_COUNT] = {
    [BINDING_POSITIONS] = TEXEL,          [BINDING_SPRING_ALIVE] = TEXEL,
    [BINDING_TRIANGLE_VERTICES] = TEXEL,  [BINDING_TRIANGLE_PARTICLES] = TEXEL,
    [BINDING_TRIANGLE_SPRINGS] = TEXEL,   [BINDING_PARTICLE_OF] = TEXEL,
    [BINDING_VERTEX_TRIANGLES] = TEXEL,   [BINDING_VERTICES] = STORAGE,
    [BINDING_INDICES] = STORAGE,          [BINDING_RIM_EDGES] = TEXEL,
    [BINDING_RIM_VERTICES] = STORAGE,
};
#undef TEXEL
#undef STORAGE

static cvk_result create_pipeline(cvk_mesh* m, cvk_error* error)
{
    cvk_descriptors d;
    cvk_result r = cvk_descriptors_create(m->context, mesh_bindings, BINDING_COUNT, 1,
                                          VK_SHADER_STAGE_COMPUTE_BIT, sizeof(cvk_mesh_push), &d,
                                          error);
    if (r != CVK_SUCCESS)
        return r;
    m->set_layout = d.set_layout;
    m->pipeline_layout = d.pipeline_layout;
    m->descriptor_pool = d.pool;
    m->set = d.sets[0];
    const cvk_resource res[BINDING_COUNT] = {
        [BINDING_POSITIONS] = {.view = m->sim->view_positions},
        [BINDING_SPRING_ALIVE] = {.view = m->sim->view_spring_alive},
        [BINDING_TRIANGLE_VERTICES] = {.view = m->view_triangle_vertices},
        [BINDING_TRIANGLE_PARTICLES] = {.view = m->view_triangle_particles},
        [BINDING_TRIANGLE_SPRINGS] = {.view = m->view_triangle_springs},
        [BINDING_PARTICLE_OF] = {.view = m->view_particle_of},
        [BINDING_VERTEX_TRIANGLES] = {.view = m->view_vertex_triangles},
        [BINDING_VERTICES] = {.buffer = &m->vertices},
        [BINDING_INDICES] = {.buffer = &m->indices},
        [BINDING_RIM_EDGES] = {.view = m->view_rim_edges},
        [BINDING_RIM_VERTICES] = {.buffer = &m->rim_vertices},
    };
    cvk_descriptors_write(m->context, &d, 0, res);
    cvk_spirv spirv = cvk_shader(CVK_SHADER_MESH_COMP);
    /* mesh.comp's TEARING: without it, no spring is read */
    uint32_t tearing = m->sim->tear && m->sim->tear->count > 0;
    cvk_spec spec = {.values = {m->sim->plan.workgroup_size, m->max_adjacent, tearing}, .count = 3};
    return cvk_compute_pipeline_create(m->context, spirv.code, spirv.bytes, m->pipeline_layout, &spec,
                                       spirv.name, &m->pipeline, error);
}

/* Generates the mesh once, so its buffers hold the starting cloth from the beginning; on
   lavapipe this also compiles the pipeline outside any timed frame. */
static cvk_result generate_once(cvk_mesh* m, VkCommandBuffer cmd, cvk_error* error)
{
    cvk_result r = cvk_command_buffer_begin(cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, error);
    if (r == CVK_SUCCESS)
        r = cvk_mesh_record(m, cmd, error);
    if (r != CVK_SUCCESS)
        return r;
    /* Whoever draws next records its own barrier; this one covers anything that reads first. */
    cvk_cmd_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_READ_BIT);
    r = cvk_command_buffer_end(cmd, error);
    if (r != CVK_SUCCESS)
        return r;
    return cvk_submit_and_wait(m->context, &m->submitter, &cmd, 1, error);
}

cvk_mesh_desc cvk_default_mesh_desc(void)
{
    return (cvk_mesh_desc){
        .vertex_usage = 0,
        .index_usage = 0,
        .cookie_ = CVK_COOKIE_MESH,
    };
}

cvk_result cvk_mesh_create(cvk_sim* sim, const cvk_mesh_desc* desc, cvk_mesh** out_mesh,
                           cvk_error* error)
{
    if (out_mesh)
        *out_mesh = NULL;
    if (!sim || !out_mesh)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_mesh_create needs a simulation and an output pointer");
    cvk_mesh_desc defaults = cvk_default_mesh_desc();
    if (!desc)
        desc = &defaults;
    if (desc->cookie_ != CVK_COOKIE_MESH)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_mesh_create: the description "
                        "did not come from cvk_default_mesh_desc()");
    cvk_mesh* m = calloc(1, sizeof *m);
    if (!m)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the mesh");
    m->sim = sim;
    m->context = sim->device.context;
    m->graphics_queue = sim->device.context->graphics;
    m->vertex_count = sim->build.particle_count;
    m->triangle_count = count_triangles(&sim->build);

    tables t = {0};
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    cvk_result r = make_tables(m, &t, error);
    uint32_t items = m->vertex_count > m->triangle_count ? m->vertex_count : m->triangle_count;
    if (m->rim_edge_count > items)
        items = m->rim_edge_count;
    uint32_t wg = sim->plan.workgroup_size;
    m->groups = (items + wg - 1) / wg;
    if (m->groups > sim->plan.max_groups)
        m->groups = sim->plan.max_groups;
    if (r == CVK_SUCCESS)
        r = check_limits(m, error);
    if (r == CVK_SUCCESS)
        r = cvk_submitter_create(m->context, &m->submitter, error);
    if (r == CVK_SUCCESS)
        r = cvk_command_buffer_allocate(m->context, &m->submitter, &cmd, error);
    if (r == CVK_SUCCESS)
        r = create_buffers(m, desc, &t, cmd, error);
    tables_free(&t);
    if (r == CVK_SUCCESS)
        r = create_pipeline(m, error);
    if (r == CVK_SUCCESS)
        r = generate_once(m, cmd, error);
    if (r != CVK_SUCCESS) {
        cvk_mesh_destroy(m);
        return r;
    }
    *out_mesh = m;
    return CVK_SUCCESS;
}

void cvk_mesh_destroy(cvk_mesh* m)
{
    if (!m)
        return;
    VkDevice dev = m->context->device;
    if (m->submitter.pool) /* work recorded by cvk_mesh_record may still use the buffers */
        cvk_queue_idle(m->context);
    if (m->pipeline)
        vkDestroyPipeline(dev, m->pipeline, NULL);
    if (m->descriptor_pool)
        vkDestroyDescriptorPool(dev, m->descriptor_pool, NULL);
    VkBufferView views[] = {m->view_triangle_vertices, m->view_triangle_particles,
                            m->view_triangle_springs, m->view_particle_of, m->view_vertex_triangles,
                            m->view_rim_edges};
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++)
        if (views[i])
            vkDestroyBufferView(dev, views[i], NULL);
    cvk_buffer* buffers[] = {&m->vertices, &m->indices, &m->triangle_vertices, &m->triangle_particles,
                             &m->triangle_springs, &m->particle_of, &m->vertex_triangles,
                             &m->rim_edges, &m->rim_vertices, &m->rim_indices};
    for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; i++)
        cvk_buffer_destroy(m->context, buffers[i]);
    cvk_submitter_destroy(m->context, &m->submitter);
    free(m->cloths);
    free(m->rims);
    free(m->rim_ends);
    free(m);
}

cvk_mesh_buffers cvk_mesh_get_buffers(const cvk_mesh* m)
{
    return (cvk_mesh_buffers){
        .vertex_buffer = m->vertices.buffer,
        .vertex_count = m->vertex_count,
        .vertex_stride = VERTEX_STRIDE,
        .position_offset = 0,
        .normal_offset = 16,
        .index_buffer = m->indices.buffer,
        .index_type = VK_INDEX_TYPE_UINT32,
        .index_count = 3u * m->triangle_count,
        .cloth_count = m->sim->build.cloth_count,
        .cloths = m->cloths,
    };
}

cvk_result cvk_mesh_record(cvk_mesh* m, VkCommandBuffer cmd, cvk_error* error)
{
    if (!m || !cmd)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_mesh_record needs a mesh and a command buffer");
    VkPipelineStageFlags after = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    if (m->graphics_queue)
        after |= VK_PIPELINE_STAGE_VERTEX_INPUT_BIT;
    cvk_cmd_barrier(cmd, after, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    cvk_mesh_push push = {m->vertex_count, m->triangle_count, m->rim_edge_count};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m->pipeline_layout, 0, 1, &m->set, 0,
                            NULL);
    vkCmdPushConstants(cmd, m->pipeline_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
    vkCmdDispatch(cmd, m->groups, 1, 1);
    return CVK_SUCCESS;
}
