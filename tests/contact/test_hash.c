/* The spatial hash on the device against a host reference: keys (cvk_hash_slot), slot starts
   (counting on the host), entries (each slot's points once, in any order, each with its
   position bit for bit), the parameters, and
   the neighbour query against a brute force. Points lie on a grid of 1/1024 m in [-1, 1)³, so
   every squared distance is exact in float and the radius² sits halfway between two possible
   values: device and host cannot disagree about a pair by rounding. */
#include <stdint.h>

#include "harness.h"
#include "contact/hash.h"
#include "shared/layout.h"

#define GRID 1024.0f /* points per m along each axis */
#define WORKGROUP 64

typedef struct fixture {
    cvk_context* ctx;
    cvk_submitter submitter;
    VkCommandBuffer cmd;
} fixture;

/* One case: points as integer grid coordinates (x = k / GRID). */
typedef struct hash_case {
    const char* name;
    const int32_t* k;       /* 3 per point */
    uint32_t count, capacity;
    float cell_size;        /* m */
    float radius;           /* m, below cell_size; 0: no neighbour check */
    uint32_t max_groups;
    const float* raw;       /* points given directly (3 per point) instead of k, keys only */
    uint32_t walk_items;    /* the query's items per invocation (cvk_plan_walk_groups); 0: 1 */
} hash_case;

/* What the device produced. */
typedef struct hash_result {
    uint32_t params[4];
    uint32_t *keys, *starts, *found;
    uint32_t* entries; /* 4 per entry: its point's xyz bits, its index */
} hash_result;

static void* alloc_or_die(size_t bytes)
{
    void* p = calloc(bytes ? bytes : 1, 1);
    if (!p) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    return p;
}

static float radius2_of(float radius)
{
    /* Halfway between two grid values of the squared distance (integers / GRID²). */
    double m = floor((double)radius * radius * GRID * GRID);
    return (float)((m + 0.5) / ((double)GRID * GRID));
}

static float* points_of(const hash_case* c)
{
    float* p = alloc_or_die(4 * sizeof(float) * c->capacity);
    for (uint32_t i = 0; i < c->count; i++)
        for (int a = 0; a < 3; a++)
            p[4 * i + a] = c->raw ? c->raw[3 * i + a] : (float)c->k[3 * i + a] / GRID;
    return p;
}

static const cvk_binding found_binding[1] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}};

/* The plan: the build, then the neighbour query (its own set 0, the hash's set as set 1). */
static void make_plan(const hash_case* c, const cvk_hash* hash, const cvk_descriptors* query,
                      cvk_plan* plan)
{
    cvk_error err;
    cvk_plan_init(plan, 1, WORKGROUP, c->max_groups);
    plan->walk_items = c->walk_items;
    REQUIRE_OK(cvk_hash_add_passes(hash, plan, c->count, false, &err), err);
    cvk_hash_query_push push = {c->count, radius2_of(c->radius)};
    cvk_op* op = cvk_plan_dispatch(plan, cvk_plan_pass(plan, "neighbours"),
                                   CVK_PIPE_HASH_NEIGHBOURS, query->pipeline_layout,
                                   query->sets[0], CVK_DOMAIN_PARTICLES, 0, c->count, &push,
                                   sizeof push);
    if (op)
        op->set1 = hash->set;
    if (op)
        op->groups = cvk_plan_walk_groups(plan, op->count);
    REQUIRE_OK(cvk_plan_check(plan, &err), err);
}

static void run_plan(fixture* f, const cvk_plan* plan)
{
    cvk_error err;
    cvk_pipelines pipelines = {0};
    cvk_spec_inputs inputs = {.workgroup_size = WORKGROUP};
    bool created;
    REQUIRE_OK(cvk_plan_require_pipelines(plan, f->ctx, &pipelines, &inputs, &created, &err), err);
    REQUIRE_OK(cvk_command_buffer_begin(f->cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, &err),
               err);
    cvk_plan_record_warm_up(plan, &pipelines, f->cmd);
    cvk_plan_record_frame(plan, &pipelines, NULL, f->cmd);
    REQUIRE_OK(cvk_command_buffer_end(f->cmd, &err), err);
    REQUIRE_OK(cvk_submit_and_wait(f->ctx, &f->submitter, &f->cmd, 1, &err), err);
    cvk_pipelines_destroy(f->ctx, &pipelines);
}

static void download(fixture* f, const cvk_buffer* b, void* data, VkDeviceSize bytes)
{
    cvk_error err;
    if (bytes)
        REQUIRE_OK(cvk_buffer_download(f->ctx, &f->submitter, f->cmd, b, data, bytes, &err), err);
}

/* Builds the hash of the case's points on the device, queries it, reads everything back;
   `then_count` (when not UINT32_MAX): a second build, over that many points, before the read. */
static hash_result run_device(fixture* f, const hash_case* c, uint32_t* table_size,
                              uint32_t then_count)
{
    cvk_error err;
    cvk_buffer points, found;
    VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                               VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    REQUIRE_OK(cvk_buffer_create(f->ctx, 16 * (VkDeviceSize)c->capacity, usage, CVK_MEMORY_DEVICE,
                                 "points", &points, &err), err);
    REQUIRE_OK(cvk_buffer_create(f->ctx, 8 * (VkDeviceSize)c->capacity, usage, CVK_MEMORY_DEVICE,
                                 "found", &found, &err), err);
    float* host_points = points_of(c);
    REQUIRE_OK(cvk_buffer_upload(f->ctx, &f->submitter, f->cmd, &points, host_points,
                                 16 * (VkDeviceSize)c->capacity, &err), err);
    free(host_points);
    cvk_hash hash;
    cvk_hash_desc desc = {c->capacity, c->cell_size, &points, false, NULL};
    REQUIRE_OK(cvk_hash_create(f->ctx, &desc, &hash, &err), err);
    *table_size = hash.table_size;
    cvk_descriptors query;
    REQUIRE_OK(cvk_descriptors_create_with(f->ctx, found_binding, 1, 1,
                                           VK_SHADER_STAGE_COMPUTE_BIT,
                                           sizeof(cvk_hash_query_push), &hash.set_layout, 1,
                                           &query, &err), err);
    cvk_descriptors_write(f->ctx, &query, 0, (cvk_resource[]){{.buffer = &found}});
    cvk_plan plan;
    make_plan(c, &hash, &query, &plan);
    run_plan(f, &plan);
    cvk_plan_destroy(&plan);
    if (then_count != UINT32_MAX) {
        hash_case again = *c;
        again.count = then_count;
        make_plan(&again, &hash, &query, &plan);
        run_plan(f, &plan);
        cvk_plan_destroy(&plan);
    }
    hash_result r = {
        .keys = alloc_or_die(4 * (size_t)c->capacity),
        .starts = alloc_or_die(4 * ((size_t)hash.table_size + 1)),
        .found = alloc_or_die(8 * (size_t)c->capacity),
        .entries = alloc_or_die(16 * (size_t)c->capacity),
    };
    download(f, &hash.params, r.params, sizeof r.params);
    download(f, &hash.keys, r.keys, 4 * (VkDeviceSize)c->count);
    download(f, &hash.starts, r.starts, 4 * ((VkDeviceSize)hash.table_size + 1));
    download(f, &found, r.found, 8 * (VkDeviceSize)c->count);
    download(f, &hash.entries, r.entries, 16 * (VkDeviceSize)c->count);
    cvk_descriptors_destroy(f->ctx, &query);
    cvk_hash_destroy(f->ctx, &hash);
    cvk_buffer_destroy(f->ctx, &found);
    cvk_buffer_destroy(f->ctx, &points);
    return r;
}

static void result_free(hash_result* r)
{
    free(r->keys);
    free(r->starts);
    free(r->entries);
    free(r->found);
}

/* The first index where two arrays differ, or n. */
static uint32_t first_difference(const uint32_t* a, const uint32_t* b, uint32_t n)
{
    uint32_t i = 0;
    while (i < n && a[i] == b[i])
        i++;
    return i;
}

static void check_params(const hash_case* c, const hash_result* r, uint32_t table_size,
                         uint32_t count)
{
    float cell, inv;
    memcpy(&cell, &r->params[0], 4);
    memcpy(&inv, &r->params[1], 4);
    CHECK(cell == c->cell_size && inv == 1.0f / c->cell_size && r->params[2] == table_size &&
              r->params[3] == count,
          "%s: params (cell %g, 1/cell %g, table %u, count %u), want (%g, %g, %u, %u)", c->name,
          (double)cell, (double)inv, r->params[2], r->params[3], (double)c->cell_size,
          (double)(1.0f / c->cell_size), table_size, count);
}

/* Keys, starts and entries against a counting sort on the host. */
static void check_table(const hash_case* c, const hash_result* r, uint32_t table_size)
{
    CHECK(table_size >= 2 * c->capacity && (table_size & (table_size - 1)) == 0,
          "%s: table size %u for capacity %u", c->name, table_size, c->capacity);
    cvk_hash host = {.capacity = c->capacity, .table_size = table_size, .cell_size = c->cell_size};
    float* p = points_of(c);
    uint32_t* keys = alloc_or_die(4 * (size_t)c->count);
    uint32_t* starts = alloc_or_die(4 * ((size_t)table_size + 1));
    uint32_t* cursor = alloc_or_die(4 * (size_t)table_size);
    uint32_t* entries = alloc_or_die(4 * (size_t)c->count);
    for (uint32_t i = 0; i < c->count; i++) {
        keys[i] = cvk_hash_slot(&host, &p[4 * i]);
        starts[keys[i] + 1]++;
    }
    for (uint32_t s = 0; s < table_size; s++)
        starts[s + 1] += starts[s];
    for (uint32_t i = 0; i < c->count; i++)
        entries[starts[keys[i]] + cursor[keys[i]]++] = i;
    uint32_t k = first_difference(r->keys, keys, c->count);
    CHECK(k == c->count, "%s: key of point %u is %u, cvk_hash_slot says %u", c->name, k,
          k < c->count ? r->keys[k] : 0, k < c->count ? keys[k] : 0);
    uint32_t s = first_difference(r->starts, starts, table_size + 1);
    CHECK(s == table_size + 1, "%s: start of slot %u is %u, counting says %u", c->name, s,
          s <= table_size ? r->starts[s] : 0, s <= table_size ? starts[s] : 0);
    /* the scatter's entries: every point once, in its slot's range (the order within a slot
       is the atomics'), with its position bit for bit */
    uint8_t* seen = calloc(c->count ? c->count : 1, 1);
    if (!seen)
        abort();
    uint32_t e = c->count;
    for (uint32_t i = 0; i < c->count && e == c->count; i++) {
        const uint32_t* entry = &r->entries[4 * (size_t)i];
        uint32_t q = entry[3];
        bool ok = q < c->count && !seen[q] && keys[q] == keys[entries[i]] &&
                  memcmp(entry, &p[4 * (size_t)q], 12) == 0;
        if (ok)
            seen[q] = 1;
        e = ok ? e : i;
    }
    CHECK(e == c->count,
          "%s: entry %u is (%08x %08x %08x, point %u), not a point of slot %u met once at its "
          "position", c->name, e, e < c->count ? r->entries[4 * (size_t)e] : 0,
          e < c->count ? r->entries[4 * (size_t)e + 1] : 0,
          e < c->count ? r->entries[4 * (size_t)e + 2] : 0,
          e < c->count ? r->entries[4 * (size_t)e + 3] : 0, e < c->count ? keys[entries[e]] : 0);
    free(seen);
    free(p);
    free(keys);
    free(starts);
    free(cursor);
    free(entries);
}

/* Neighbour counts and index sums against a brute force in integer grid units. */
static void check_neighbours(const hash_case* c, const hash_result* r)
{
    double r2 = (double)radius2_of(c->radius) * GRID * GRID;
    uint32_t wrong = 0, first = 0, want_count = 0, want_sum = 0;
    for (uint32_t i = 0; i < c->count; i++) {
        uint32_t count = 0, sum = 0;
        for (uint32_t j = 0; j < c->count; j++) {
            int64_t d2 = 0;
            for (int a = 0; a < 3; a++) {
                int64_t d = (int64_t)c->k[3 * j + a] - c->k[3 * i + a];
                d2 += d * d;
            }
            if (j != i && (double)d2 <= r2) {
                count++;
                sum += j;
            }
        }
        if (r->found[2 * i] != count || r->found[2 * i + 1] != sum) {
            if (wrong++ == 0) {
                first = i;
                want_count = count;
                want_sum = sum;
            }
        }
    }
    CHECK(wrong == 0,
          "%s: %u of %u points have the wrong neighbours; point %u: %u neighbours (index sum "
          "%u), brute force %u (%u)", c->name, wrong, c->count, first,
          wrong ? r->found[2 * first] : 0, wrong ? r->found[2 * first + 1] : 0, want_count,
          want_sum);
}

static void run_case(fixture* f, const hash_case* c)
{
    uint32_t table_size;
    hash_result r = run_device(f, c, &table_size, UINT32_MAX);
    check_params(c, &r, table_size, c->count);
    check_table(c, &r, table_size);
    if (c->radius > 0.0f)
        check_neighbours(c, &r);
    result_free(&r);
}

/* n random grid points in [lo, hi)³ (grid units). */
static int32_t* random_points(uint32_t seed, uint32_t n, int32_t lo, int32_t hi)
{
    harness_rng rng = {seed};
    int32_t* k = alloc_or_die(3 * sizeof(int32_t) * n);
    for (uint32_t i = 0; i < 3 * n; i++)
        k[i] = lo + (int32_t)(harness_next(&rng) % (uint32_t)(hi - lo));
    return k;
}

static void random_cases(fixture* f)
{
    static const uint32_t sizes[] = {1, 2, 7, 100, 1000, 5000, 20000};
    static const float cells[] = {0.013f, 0.1f, 0.37f};
    for (uint32_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (uint32_t k = 0; k < sizeof cells / sizeof cells[0]; k++) {
            if (sizes[s] == 20000 && cells[k] > 0.2f)
                continue; /* the brute force and the query grow as n² · cell³ */
            uint32_t seed = 1 + 7 * s + k;
            int32_t* points = random_points(seed, sizes[s], -1024, 1024);
            char name[64];
            snprintf(name, sizeof name, "random n=%u cell=%g seed=%u", sizes[s], (double)cells[k],
                     seed);
            hash_case c = {name, points, sizes[s], sizes[s] + (s % 2) * sizes[s] / 3, cells[k],
                           0.9f * cells[k], s % 3 == 0 ? 1 : 8, NULL, 1};
            run_case(f, &c);
            free(points);
        }
}

/* 20000 points inside one cell of 0.1 m, and 500 points at one position among 500 others. */
static void crowded_cases(fixture* f)
{
    int32_t* one_cell = random_points(41, 20000, 0, 102); /* 102 / 1024 < 0.1 */
    hash_case c = {"20000 points in one cell", one_cell, 20000, 20000, 0.1f, 0.09f, 8, NULL, 1};
    run_case(f, &c);
    free(one_cell);
    int32_t* coincident = random_points(43, 1000, -300, 300);
    for (uint32_t i = 0; i < 500; i++)
        for (int a = 0; a < 3; a++)
            coincident[3 * (2 * i) + a] = 256;
    hash_case d = {"500 coincident points among 500", coincident, 1000, 1000, 0.05f, 0.04f, 8,
                   NULL, 1};
    run_case(f, &d);
    free(coincident);
}

/* No points: after a build of 50, a build of 0 leaves every start zero and count 0. */
static void empty_case(fixture* f)
{
    int32_t* points = random_points(47, 50, -100, 100);
    hash_case c = {"0 points after 50", points, 50, 50, 0.05f, 0.0f, 8, NULL, 1};
    uint32_t table_size;
    hash_result r = run_device(f, &c, &table_size, 0);
    check_params(&c, &r, table_size, 0);
    uint32_t nonzero = 0;
    for (uint32_t s = 0; s <= table_size; s++)
        nonzero += r.starts[s] != 0;
    CHECK(nonzero == 0, "0 points: %u of %u starts are not 0", nonzero, table_size + 1);
    result_free(&r);
    free(points);
}

/* A second build over the same hash: the first leaves its counts for the second to start from
   (they must be back at 0), with fewer points than the first. */
static void rebuild_case(fixture* f)
{
    int32_t* points = random_points(53, 3000, -600, 600);
    /* eight queries an invocation, as on a CPU device */
    hash_case c = {"1800 points after 3000", points, 3000, 3000, 0.05f, 0.04f, 8, NULL, 8};
    uint32_t table_size;
    hash_result r = run_device(f, &c, &table_size, 1800);
    c.count = 1800;
    check_params(&c, &r, table_size, 1800);
    check_table(&c, &r, table_size);
    check_neighbours(&c, &r);
    result_free(&r);
    free(points);
}

/* Points far away (clamped cells) and on cell borders: keys only. */
static void far_case(fixture* f)
{
    static const float raw[] = {
        1e12f, -1e12f, 3.0f,   -5e9f, 7e9f, 0.0f,  0.0f, -0.0f, 0.0f,
        0.1f,  -0.1f,  0.05f,  1e-30f, -1e-30f, 2.5f,  -1e12f, -1e12f, -1e12f,
    };
    hash_case c = {"far and border points", NULL, 6, 6, 0.05f, 0.0f, 8, raw, 1};
    run_case(f, &c);
}

static void check_refused(fixture* f)
{
    cvk_error err;
    cvk_buffer points;
    REQUIRE_OK(cvk_buffer_create(f->ctx, 16 * 8, VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT,
                                 CVK_MEMORY_DEVICE, "points", &points, &err), err);
    cvk_hash hash;
    cvk_hash_desc bad[] = {{0, 0.1f, &points, false, NULL}, {4, 0.0f, &points, false, NULL}, {4, -1.0f, &points, false, NULL},
                           {4, NAN, &points, false, NULL}, {9, 0.1f, &points, false, NULL}, {4, 0.1f, NULL, false, NULL}};
    /* Each refused for its own reason, in its own words (lib/contact/hash.c: at most 2^30
       points, a vec4 of 16 bytes a point, and the buffer above holds 8). */
    const char* why[] = {
        "hash: capacity is 0 points; it must be 1 to 1073741824",
        "hash: cell size is 0 m; it must be positive and finite with a finite reciprocal",
        "hash: cell size is -1 m; it must be positive and finite with a finite reciprocal",
        "hash: cell size is nan m; it must be positive and finite with a finite reciprocal",
        "hash: the points buffer must hold a vec4 per point (9 points)",
        "hash: the points buffer must hold a vec4 per point (4 points)",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        cvk_result r = cvk_hash_create(f->ctx, &bad[i], &hash, &err);
        CHECK(r == CVK_ERROR_INVALID_ARGUMENT && strcmp(err.message, why[i]) == 0,
              "bad description %zu: %s\n    %s\nexpected\n    %s", i, cvk_result_name(r),
              err.message, why[i]);
    }
    cvk_hash_desc good = {4, 0.1f, &points, false, NULL};
    REQUIRE_OK(cvk_hash_create(f->ctx, &good, &hash, &err), err);
    cvk_plan plan;
    cvk_plan_init(&plan, 1, WORKGROUP, 8);
    cvk_result r = cvk_hash_add_passes(&hash, &plan, 5, false, &err);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT &&
              strcmp(err.message, "hash: 5 points to hash; the hash was made for at most 4") == 0,
          "5 points in a hash of 4: %s (%s)", cvk_result_name(r), err.message);
    cvk_plan_destroy(&plan);
    cvk_hash_destroy(f->ctx, &hash);
    cvk_buffer_destroy(f->ctx, &points);
}

int main(void)
{
    cvk_error err;
    fixture f = {harness_context(), {0}, VK_NULL_HANDLE};
    REQUIRE_OK(cvk_submitter_create(f.ctx, &f.submitter, &err), err);
    REQUIRE_OK(cvk_command_buffer_allocate(f.ctx, &f.submitter, &f.cmd, &err), err);
    random_cases(&f);
    crowded_cases(&f);
    empty_case(&f);
    rebuild_case(&f);
    far_case(&f);
    check_refused(&f);
    cvk_submitter_destroy(f.ctx, &f.submitter);
    return harness_finish(f.ctx);
}
