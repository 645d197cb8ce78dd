/* collide: GPU time of the spatial hash (lib/contact/hash.h) and of a neighbour query over it against
   point count, per pass. Points are random in a cube holding one point per cell on average
   (cell size 1 cm, like a cloth's thickness against its spacing); the query counts, for every
   point, the others within one cell size over the 27 cells around it. Each operation of the
   build is timed on its own (GPU timestamps), so the scan's share is visible. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "plot.h"
#include "sim/internal.h"

#define WORKGROUP 64u
#define CPU_MAX_GROUPS 4u   /* as the simulation on a CPU device (lib/sim/sim.c) */
#define SPACING 0.01f       /* m: cell size, query radius and mean point spacing */

/* The build's operations by pipeline label, then the query. */
#define STAGES 7
static const char* const stage_pass[STAGES] = {
    "hash: clear", "hash: count", "hash: chunk sums", "hash: scan chunks", "hash: scan",
    "hash: scatter", "hash: neighbours",
};
static const char* const stage_column[STAGES] = {
    "clear_ms", "count_ms", "chunk_sums_ms", "scan_chunks_ms", "scan_ms", "scatter_ms",
    "neighbours_ms",
};

static const char* const columns[] = {
    "points", "cell_size", "table_size", "clear_ms", "count_ms", "chunk_sums_ms",
    "scan_chunks_ms", "scan_ms", "scatter_ms", "hash_ms", "neighbours_ms", "total_ms",
    "total_ms_min", "total_ms_max", "ns_per_point", "neighbours_per_point", "dispatches",
};

/* The device objects of one point count. */
typedef struct run {
    cvk_context* ctx;
    cvk_submitter submitter;
    VkCommandBuffer cmd;
    cvk_buffer points, found;
    cvk_hash hash;
    cvk_descriptors query;
    cvk_plan plan;
    cvk_pipelines pipelines;
    VkQueryPool pool;
    uint32_t query_count;
    uint32_t* pass_of;
} run;

typedef struct measured {
    double stage_ms[STAGES];   /* medians */
    bench_timing total;
    double neighbours;         /* per point, mean */
    uint32_t dispatches;
} measured;

static const cvk_binding found_binding[1] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}};

static void run_destroy(run* r)
{
    free(r->pass_of);
    if (r->pool)
        vkDestroyQueryPool(r->ctx->device, r->pool, NULL);
    cvk_pipelines_destroy(r->ctx, &r->pipelines);
    cvk_plan_destroy(&r->plan);
    cvk_descriptors_destroy(r->ctx, &r->query);
    cvk_hash_destroy(r->ctx, &r->hash);
    cvk_buffer_destroy(r->ctx, &r->found);
    cvk_buffer_destroy(r->ctx, &r->points);
    cvk_submitter_destroy(r->ctx, &r->submitter);
}

/* n points, uniform in a cube of n cells. */
static float* random_points(uint32_t n)
{
    float* p = malloc(16 * (size_t)n);
    if (!p)
        return NULL;
    float side = cbrtf((float)n) * SPACING;
    uint32_t state = 2463534242u;
    for (uint32_t i = 0; i < 4 * n; i++) {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        p[i] = i % 4 == 3 ? 0.0f : side * (float)(state >> 8) / (float)(1u << 24);
    }
    return p;
}

/* Every operation of the build in a pass of its own, named by its pipeline, so the frame's
   timestamps time each; then the query, one point per invocation. */
static void make_plan(run* r, uint32_t n, cvk_error* err, cvk_result* result)
{
    const cvk_context* ctx = r->ctx;
    uint32_t max_groups = ctx->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU
                              ? CPU_MAX_GROUPS
                              : ctx->properties.limits.maxComputeWorkGroupCount[0];
    cvk_plan_init(&r->plan, 1, WORKGROUP, max_groups);
    *result = cvk_hash_add_passes(&r->hash, &r->plan, n, false, err);
    if (*result != CVK_SUCCESS)
        return;
    for (uint32_t i = 0; i < r->plan.op_count; i++) {
        cvk_op* op = &r->plan.ops[i];
        op->pass = cvk_plan_pass(&r->plan, cvk_pipeline_label(op->pipeline));
    }
    cvk_hash_query_push push = {n, SPACING * SPACING};
    cvk_op* op = cvk_plan_dispatch(&r->plan, cvk_plan_pass(&r->plan, stage_pass[STAGES - 1]),
                                   CVK_PIPE_HASH_NEIGHBOURS, r->query.pipeline_layout,
                                   r->query.sets[0], CVK_DOMAIN_PARTICLES, 0, n, &push,
                                   sizeof push);
    if (op) {
        op->set1 = r->hash.set;
        op->groups = cvk_plan_walk_groups(&r->plan, op->count);
    }
    *result = cvk_plan_check(&r->plan, err);
}

static cvk_result create_query_pool(run* r, cvk_error* err)
{
    r->query_count = cvk_plan_query_count(&r->plan, NULL);
    r->pass_of = calloc(r->query_count, sizeof *r->pass_of);
    if (!r->pass_of)
        return cvk_fail(err, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the query list");
    cvk_plan_query_count(&r->plan, r->pass_of);
    VkQueryPoolCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
        .queryType = VK_QUERY_TYPE_TIMESTAMP,
        .queryCount = r->query_count,
    };
    VkResult vr = vkCreateQueryPool(r->ctx->device, &info, NULL, &r->pool);
    return vr == VK_SUCCESS ? CVK_SUCCESS : cvk_fail_vk(err, "vkCreateQueryPool", vr);
}

static cvk_result setup(run* r, uint32_t n, cvk_error* err)
{
    VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                               VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    float* host = random_points(n);
    if (!host)
        return cvk_fail(err, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %u points", n);
    cvk_result res = cvk_submitter_create(r->ctx, &r->submitter, err);
    if (res == CVK_SUCCESS)
        res = cvk_command_buffer_allocate(r->ctx, &r->submitter, &r->cmd, err);
    if (res == CVK_SUCCESS)
        res = cvk_buffer_create(r->ctx, 16 * (VkDeviceSize)n, usage, CVK_MEMORY_DEVICE, "points",
                                &r->points, err);
    if (res == CVK_SUCCESS)
        res = cvk_buffer_create(r->ctx, 8 * (VkDeviceSize)n, usage, CVK_MEMORY_DEVICE, "found",
                                &r->found, err);
    if (res == CVK_SUCCESS)
        res = cvk_buffer_upload(r->ctx, &r->submitter, r->cmd, &r->points, host,
                                16 * (VkDeviceSize)n, err);
    free(host);
    cvk_hash_desc desc = {n, SPACING, &r->points, false, NULL};
    if (res == CVK_SUCCESS)
        res = cvk_hash_create(r->ctx, &desc, &r->hash, err);
    if (res == CVK_SUCCESS)
        res = cvk_descriptors_create_with(r->ctx, found_binding, 1, 1, VK_SHADER_STAGE_COMPUTE_BIT,
                                          sizeof(cvk_hash_query_push), &r->hash.set_layout, 1,
                                          &r->query, err);
    if (res != CVK_SUCCESS)
        return res;
    cvk_descriptors_write(r->ctx, &r->query, 0, (cvk_resource[]){{.buffer = &r->found}});
    make_plan(r, n, err, &res);
    bool created;
    cvk_spec_inputs inputs = {.workgroup_size = WORKGROUP};
    if (res == CVK_SUCCESS)
        res = cvk_plan_require_pipelines(&r->plan, r->ctx, &r->pipelines, &inputs, &created, err);
    if (res == CVK_SUCCESS)
        res = create_query_pool(r, err);
    return res;
}

/* One frame of the plan (timed when `timed`): submitted and waited for. */
static cvk_result run_frame(run* r, bool timed, cvk_error* err)
{
    cvk_result res = cvk_command_buffer_begin(r->cmd, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT,
                                              err);
    if (res != CVK_SUCCESS)
        return res;
    cvk_plan_record_warm_up(&r->plan, &r->pipelines, r->cmd);
    cvk_plan_queries queries = {timed ? r->pool : VK_NULL_HANDLE, r->query_count};
    cvk_plan_record_frame(&r->plan, &r->pipelines, &queries, r->cmd);
    res = cvk_command_buffer_end(r->cmd, err);
    if (res == CVK_SUCCESS)
        res = cvk_submit_and_wait(r->ctx, &r->submitter, &r->cmd, 1, err);
    return res;
}

/* The frame's time per stage (ms) from its timestamps; the total. */
static cvk_result read_times(run* r, double* stage_ms, double* total_ms, cvk_error* err)
{
    uint64_t* stamps = calloc(r->query_count, sizeof *stamps);
    if (!stamps)
        return cvk_fail(err, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for timestamps");
    VkResult vr = vkGetQueryPoolResults(r->ctx->device, r->pool, 0, r->query_count,
                                        r->query_count * sizeof *stamps, stamps, sizeof *stamps,
                                        VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
    if (vr != VK_SUCCESS) {
        free(stamps);
        return cvk_fail_vk(err, "vkGetQueryPoolResults", vr);
    }
    uint32_t bits = r->ctx->timestamp_valid_bits;
    uint64_t mask = bits >= 64 ? UINT64_MAX : (1ull << bits) - 1;
    double period_ms = r->ctx->properties.limits.timestampPeriod * 1e-6;
    for (uint32_t s = 0; s < STAGES; s++)
        stage_ms[s] = 0.0;
    for (uint32_t q = 1; q < r->query_count; q++) {
        const char* name = r->plan.pass_names[r->pass_of[q]];
        for (uint32_t s = 0; s < STAGES; s++)
            if (!strcmp(name, stage_pass[s]))
                stage_ms[s] += (double)((stamps[q] - stamps[q - 1]) & mask) * period_ms;
    }
    *total_ms = (double)((stamps[r->query_count - 1] - stamps[0]) & mask) * period_ms;
    free(stamps);
    return CVK_SUCCESS;
}

/* Mean neighbours per point, from the query's output. */
static cvk_result read_neighbours(run* r, uint32_t n, double* mean, cvk_error* err)
{
    uint32_t* found = malloc(8 * (size_t)n);
    if (!found)
        return cvk_fail(err, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %u results", n);
    cvk_result res = cvk_buffer_download(r->ctx, &r->submitter, r->cmd, &r->found, found,
                                         8 * (VkDeviceSize)n, err);
    double sum = 0.0;
    for (uint32_t i = 0; i < n; i++)
        sum += found[2 * i];
    *mean = sum / n;
    free(found);
    return res;
}

static cvk_result measure(bench* b, run* r, uint32_t n, measured* m, cvk_error* err)
{
    uint32_t timed = b->o->repeat;
    double* samples = calloc((size_t)timed * (STAGES + 1), sizeof *samples);
    if (!samples)
        return cvk_fail(err, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for samples");
    cvk_result res = CVK_SUCCESS;
    for (uint32_t i = 0; res == CVK_SUCCESS && i < b->o->warmup + 1; i++)
        res = run_frame(r, false, err); /* at least one: lavapipe compiles on first dispatch */
    for (uint32_t i = 0; res == CVK_SUCCESS && i < timed; i++) {
        double stage[STAGES] = {0}, total = 0.0;
        res = run_frame(r, true, err);
        if (res == CVK_SUCCESS)
            res = read_times(r, stage, &total, err);
        for (uint32_t s = 0; s < STAGES; s++)
            samples[(size_t)s * timed + i] = stage[s];
        samples[(size_t)STAGES * timed + i] = total;
    }
    if (res == CVK_SUCCESS) {
        for (uint32_t s = 0; s < STAGES; s++)
            m->stage_ms[s] = bench_timing_of(&samples[(size_t)s * timed], timed).median;
        m->total = bench_timing_of(&samples[(size_t)STAGES * timed], timed);
        m->dispatches = r->plan.op_count;
        res = read_neighbours(r, n, &m->neighbours, err);
    }
    free(samples);
    return res;
}

static void add_row(bench* b, uint32_t n, const cvk_hash* hash, const measured* m)
{
    bench_table* t = &b->table;
    bench_table_row(t);
    bench_table_int(t, "points", n);
    bench_table_num(t, "cell_size", SPACING);
    bench_table_int(t, "table_size", hash->table_size);
    double hash_ms = 0.0;
    for (uint32_t s = 0; s < STAGES; s++) {
        bench_table_num(t, stage_column[s], m->stage_ms[s]);
        if (s + 1 < STAGES)
            hash_ms += m->stage_ms[s];
    }
    bench_table_num(t, "hash_ms", hash_ms);
    bench_table_num(t, "total_ms", m->total.median);
    bench_table_num(t, "total_ms_min", m->total.min);
    bench_table_num(t, "total_ms_max", m->total.max);
    bench_table_num(t, "ns_per_point", m->total.median * 1e6 / n);
    bench_table_num(t, "neighbours_per_point", m->neighbours);
    bench_table_int(t, "dispatches", m->dispatches);
}

static void print_row(uint32_t n, const measured* m)
{
    printf("%9u", n);
    for (uint32_t s = 0; s < STAGES; s++)
        printf(" %9.3f", m->stage_ms[s]);
    printf(" %9.3f [%.3f-%.3f] %6.1f ns/point, %.2f neighbours/point\n", m->total.median,
           m->total.min, m->total.max, m->total.median * 1e6 / n, m->neighbours);
    fflush(stdout);
}

static void write_plot(bench* b)
{
    bench_text* t = &b->plot;
    bench_plot_styles(t);
    bench_text_add(t, "set title \"spatial hash and neighbour query, GPU ms per pass, on %s\"\n"
                      "set logscale xy\nset xlabel \"points\"\nset ylabel \"ms\"\n"
                      "set format x \"%%.0e\"\nset key top left font \",8\"\n", b->device);
    const char* sep = "plot ";
    const char* series[] = {"total_ms", "hash_ms", "neighbours_ms", "count_ms", "scan_ms",
                            "chunk_sums_ms", "scatter_ms"};
    for (uint32_t s = 0; s < sizeof series / sizeof series[0]; s++) {
        bench_text_add(t, "%s\"collide.csv\" using \"points\":\"%s\" with linespoints "
                          "linestyle %u title \"%s\"", sep, series[s], s + 1, series[s]);
        sep = ", \\\n     ";
    }
    bench_text_add(t, "\n");
}

int bench_collide(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    if (!cvk_context_get_info(b->ctx).timestamps) {
        fprintf(stderr, "clothvk-bench: collide: the device cannot write timestamps\n");
        return APP_EXIT_FAILURE;
    }
    printf("points, cell %.3g m, radius %.3g m; GPU ms per pass, median of %u after %u warm-up\n"
           "%9s", (double)SPACING, (double)SPACING, b->o->repeat, b->o->warmup, "points");
    for (uint32_t s = 0; s < STAGES; s++)
        printf(" %9.9s", stage_pass[s] + 6); /* without "hash: " */
    printf(" %9s\n", "total");
    for (uint32_t i = 0; i < b->o->point_count; i++) {
        uint32_t n = b->o->points[i];
        run r = {.ctx = b->ctx};
        measured m = {0};
        cvk_error err;
        cvk_result res = setup(&r, n, &err);
        if (res == CVK_SUCCESS)
            res = measure(b, &r, n, &m, &err);
        if (res == CVK_SUCCESS)
            add_row(b, n, &r.hash, &m);
        run_destroy(&r);
        if (res != CVK_SUCCESS) {
            bench_fail(&err);
            return APP_EXIT_FAILURE;
        }
        print_row(n, &m);
    }
    write_plot(b);
    return APP_EXIT_OK;
}
