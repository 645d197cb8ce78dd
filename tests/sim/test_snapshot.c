/* Exact snapshots (cvk_sim_save_snapshot / cvk_sim_load_snapshot):
   - run N frames, save, run M more: A; a new simulation loads the snapshot and runs M: B;
     A equals B bit for bit, frame counter included, for rbgs, jacobi, chebyshev and gs-cpu;
   - a device solver's snapshot loads into another device solver, gs-cpu's not into rbgs;
   - a snapshot of another scene, a truncated one, bytes that are not a snapshot and a save
     buffer of the wrong size are refused with their sentences, changing nothing; so are a bit
     flipped in the header or anywhere in the state (the CRC-32) and format version 3. */
#include "harness.h"

#define N_FRAMES 5
#define M_FRAMES 4

/* A 16 x 12 cloth pinned at two corners, with shear springs and damping: it swings and
   stretches, and its projective-dynamics state includes the rest memory. */
typedef struct swinging {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    uint32_t pins[2][2];
} swinging;

static void make_swinging(swinging* w, uint32_t columns, cvk_linear_solver linear)
{
    memset(w->pins, 0, sizeof w->pins);
    w->pins[1][0] = columns - 1;
    w->cloth = cvk_default_cloth_desc();
    w->cloth.grid[0] = columns;
    w->cloth.grid[1] = 12;
    w->cloth.stiffness.shear = 1e5f;
    w->cloth.pins = (const uint32_t(*)[2])w->pins;
    w->cloth.pin_count = 2;
    w->scene = cvk_default_scene_desc();
    w->scene.cloths = &w->cloth;
    w->scene.cloth_count = 1;
    w->scene.solver.linear = linear;
    w->scene.damping = 0.02f; /* a rest memory to carry (lib/solvers/solve_pd.h) */
}

static cvk_sim* make_sim(cvk_context* ctx, const cvk_scene_desc* scene)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    return sim;
}

static void* save(cvk_sim* sim, uint64_t* size)
{
    cvk_error err;
    *size = cvk_sim_snapshot_size(sim);
    void* data = malloc(*size);
    if (!data) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    REQUIRE_OK(cvk_sim_save_snapshot(sim, data, *size, &err), err);
    return data;
}

static float* positions(cvk_sim* sim)
{
    cvk_error err;
    uint64_t n = cvk_sim_particle_count(sim);
    float* x = malloc(3 * n * sizeof(float));
    if (!x) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    REQUIRE_OK(cvk_sim_read_positions(sim, x, n, &err), err);
    return x;
}

static uint64_t frames_of(cvk_sim* sim)
{
    cvk_sim_stats st;
    cvk_error err;
    REQUIRE_OK(cvk_sim_get_stats(sim, &st, &err), err);
    return st.frames;
}

static void resume_is_exact(cvk_context* ctx, cvk_linear_solver linear)
{
    const char* name = cvk_linear_solver_name(linear);
    swinging w;
    make_swinging(&w, 16, linear);
    cvk_sim* a = make_sim(ctx, &w.scene);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(a, N_FRAMES, &err), err);
    uint64_t size;
    void* snap = save(a, &size);
    float* at_snap = positions(a);
    REQUIRE_OK(cvk_sim_step(a, M_FRAMES, &err), err);
    cvk_sim* b = make_sim(ctx, &w.scene);
    REQUIRE_OK(cvk_sim_load_snapshot(b, snap, size, &err), err);
    REQUIRE_OK(cvk_sim_step(b, M_FRAMES, &err), err);
    uint64_t size_a, size_b;
    void* end_a = save(a, &size_a);
    void* end_b = save(b, &size_b);
    CHECK(size_a == size_b && memcmp(end_a, end_b, size_a) == 0,
          "%s: the resumed run's state differs from the uninterrupted run's", name);
    float *xa = positions(a), *xb = positions(b);
    uint64_t n = cvk_sim_particle_count(a);
    CHECK(memcmp(xa, xb, 3 * n * sizeof(float)) == 0,
          "%s: resumed positions differ from the uninterrupted run's by up to %g m", name,
          harness_max_diff(xa, xb, 3 * n));
    double moved = harness_max_diff(at_snap, xa, 3 * n);
    CHECK(moved > 1e-3, "%s: the cloth moved only %g m after the snapshot: nothing was tested",
          name, moved);
    CHECK(frames_of(b) == N_FRAMES + M_FRAMES, "%s: the resumed run counts %llu frames, not %d",
          name, (unsigned long long)frames_of(b), N_FRAMES + M_FRAMES);
    printf("snapshot (%s): %llu bytes; resumed run equals the original bit for bit after %d "
           "frames (the cloth moved %.3g m)\n", name, (unsigned long long)size, M_FRAMES, moved);
    free(snap);
    free(at_snap);
    free(end_a);
    free(end_b);
    free(xa);
    free(xb);
    cvk_sim_destroy(a);
    cvk_sim_destroy(b);
}

/* A refused load returns `result` with exactly `message`. */
static void check_refusal(cvk_result r, const cvk_error* err, cvk_result result,
                          const char* message, const char* what)
{
    CHECK(r == result, "%s: returned %s, not %s", what, cvk_result_name(r),
          cvk_result_name(result));
    CHECK(strcmp(err->message, message) == 0, "%s: message \"%s\", expected \"%s\"", what,
          err->message, message);
}

/* CRC-32 (the polynomial of zlib's crc32, reflected, bit by bit) over a snapshot's bytes but
   its CRC field's four at byte 64. */
static uint32_t crc32_but_field(const unsigned char* p, uint64_t size)
{
    uint32_t crc = 0xffffffffu;
    for (uint64_t i = 0; i < size; i++) {
        if (i >= 64 && i < 68)
            continue;
        crc ^= p[i];
        for (int k = 0; k < 8; k++)
            crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

static void refusals(cvk_context* ctx)
{
    swinging w, other;
    make_swinging(&w, 16, CVK_LINEAR_RBGS);
    make_swinging(&other, 15, CVK_LINEAR_RBGS);
    cvk_sim* a = make_sim(ctx, &w.scene);
    cvk_sim* b = make_sim(ctx, &other.scene);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(a, 2, &err), err);
    uint64_t size, other_size;
    unsigned char* snap = save(a, &size);
    unsigned char* other_snap = save(b, &other_size);
    char expected[512];
    snprintf(expected, sizeof expected, "cvk_sim_load_snapshot: the snapshot is %llu bytes; its "
             "header says %llu (truncated or padded)", (unsigned long long)(size - 1),
             (unsigned long long)size);
    check_refusal(cvk_sim_load_snapshot(a, snap, size - 1, &err), &err,
                  CVK_ERROR_INVALID_ARGUMENT, expected, "a truncated snapshot");
    check_refusal(cvk_sim_load_snapshot(a, snap, 10, &err), &err, CVK_ERROR_INVALID_ARGUMENT,
                  "cvk_sim_load_snapshot: the data is not a clothvk snapshot (10 bytes without "
                  "its header)", "ten bytes");
    /* One flipped bit anywhere, header or state, is damage; the CRC-32 field is at byte 64,
       over every other byte (lib/sim/snapshot.c), measured here bit by bit. */
    uint32_t crc;
    memcpy(&crc, snap + 64, 4);
    CHECK(crc == crc32_but_field(snap, size), "the header's CRC-32 %08x, the snapshot's %08x",
          crc, crc32_but_field(snap, size));
    const uint64_t flips[] = {16, 72, size / 2, size - 1}; /* frames, state start, middle, end */
    for (int i = 0; i < 4; i++) {
        snap[flips[i]] ^= 0x10;
        cvk_result r = cvk_sim_load_snapshot(a, snap, size, &err);
        uint32_t computed = crc32_but_field(snap, size);
        snap[flips[i]] ^= 0x10;
        CHECK(r == CVK_ERROR_INVALID_ARGUMENT, "a bit flipped at byte %llu: returned %s",
              (unsigned long long)flips[i], cvk_result_name(r));
        char expected_damage[160];
        snprintf(expected_damage, sizeof expected_damage, "cvk_sim_load_snapshot: the snapshot "
                 "is damaged: its CRC-32 is %08x, its header says %08x", computed, crc);
        CHECK(strcmp(err.message, expected_damage) == 0 && computed != crc,
              "a bit flipped at byte %llu: message \"%s\"", (unsigned long long)flips[i],
              err.message);
    }
    /* A snapshot of format version 3 (no checksum) is refused by its version (as are 4's, 5's
       and 6's, whose contact state is shorter). */
    uint32_t version = 3, current;
    memcpy(&current, snap + 8, 4);
    memcpy(snap + 8, &version, 4);
    check_refusal(cvk_sim_load_snapshot(a, snap, size, &err), &err, CVK_ERROR_UNSUPPORTED,
                  "cvk_sim_load_snapshot: the snapshot has format version 3; this library reads "
                  "version 7", "a version-3 snapshot");
    memcpy(snap + 8, &current, 4);
    uint64_t hash_a, hash_b;
    memcpy(&hash_a, snap + 24, 8);
    memcpy(&hash_b, other_snap + 24, 8);
    snprintf(expected, sizeof expected, "cvk_sim_load_snapshot: the snapshot was taken of another "
             "scene (180 particles, build hash %016llx; this simulation: 192 particles, %016llx)",
             (unsigned long long)hash_b, (unsigned long long)hash_a);
    check_refusal(cvk_sim_load_snapshot(a, other_snap, other_size, &err), &err,
                  CVK_ERROR_INVALID_ARGUMENT, expected, "another scene's snapshot");
    snprintf(expected, sizeof expected, "cvk_sim_save_snapshot: the buffer holds %llu bytes; the "
             "snapshot is %llu (cvk_sim_snapshot_size)", (unsigned long long)(size + 8),
             (unsigned long long)size);
    unsigned char* big = calloc(1, size + 8);
    check_refusal(cvk_sim_save_snapshot(a, big, size + 8, &err), &err,
                  CVK_ERROR_INVALID_ARGUMENT, expected, "a save buffer of the wrong size");
    free(big);
    /* Nothing of the refused loads stuck: a's state is still what it was. */
    uint64_t again_size;
    unsigned char* again = save(a, &again_size);
    CHECK(again_size == size && memcmp(again, snap, size) == 0,
          "a refused load changed the simulation's state");
    printf("refusals: truncated, damaged (4 bit flips), version 3, not a snapshot, another scene, "
           "wrong save size\n");
    free(again);
    free(snap);
    free(other_snap);
    cvk_sim_destroy(a);
    cvk_sim_destroy(b);
}

/* Device solvers share their state's layout; gs-cpu keeps doubles on the host. */
/* Cloth contact's state (where detection saw each particle, the bounds, the lists of
   vertex–feature and edge–edge pairs, the positions a substep before) travels in a snapshot:
   a strip lying across another (only their edges meet, tests/contact/test_collide.c) saved
   while its edges are in contact and loaded into a second simulation of the scene steps on
   to the same bits as the first. */
static void edge_pairs(cvk_context* ctx)
{
    cvk_cloth_desc strips[2];
    harness_strips_across(strips, 0.5f, 0.515f);
    uint32_t pins[2][2] = {{0, 0}, {5, 1}};
    strips[0].pins = (const uint32_t(*)[2])pins;
    strips[0].pin_count = 2;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = strips;
    scene.cloth_count = 2;
    scene.collision.self = true;
    scene.collision.thickness = 0.01f;
    cvk_sim* first = make_sim(ctx, &scene);
    cvk_sim* second = make_sim(ctx, &scene);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(first, 10, &err), err);
    /* In contact at the snapshot: the upper strip's four particles beside the crossing (its
       rows at z = +-0.1, off the lower strip) rest on the lower strip's edges, under two
       thicknesses above the lower strip's four beside it (its columns at x = +-0.1); falling
       through, they would be below them. */
    float* x = harness_read_all(first);
    float upper = 0.0f, lower = 0.0f;
    for (uint32_t k = 0; k < 4; k++) {
        upper += 0.25f * x[3 * (12 + 4 + k) + 1];   /* strip 1 (2 x 6): rows 2 and 3 */
        lower += 0.25f * x[3 * (k < 2 ? 2 + k : 6 + k) + 1]; /* strip 0 (6 x 2): columns 2, 3 */
    }
    free(x);
    CHECK(upper > lower && upper - lower < 2.0f * scene.collision.thickness,
          "strips at the snapshot: the upper strip %.4f m above the lower one's edges (expected "
          "0 to 2 thicknesses: in contact)", (double)(upper - lower));
    printf("strips at the snapshot: the upper one %.4f m above the lower one's edges\n",
           (double)(upper - lower));
    uint64_t size;
    unsigned char* snap = save(first, &size);
    REQUIRE_OK(cvk_sim_load_snapshot(second, snap, size, &err), err);
    REQUIRE_OK(cvk_sim_step(first, 20, &err), err);
    REQUIRE_OK(cvk_sim_step(second, 20, &err), err);
    uint64_t size_a, size_b;
    unsigned char* a = save(first, &size_a);
    unsigned char* b = save(second, &size_b);
    CHECK(size_a == size_b && memcmp(a, b, size_a) == 0,
          "strips in contact: stepping on from a snapshot gave other bits than stepping on");
    printf("strips in contact: 20 frames from a snapshot give the same bits\n");
    free(a);
    free(b);
    free(snap);
    cvk_sim_destroy(first);
    cvk_sim_destroy(second);
}

static void across_solvers(cvk_context* ctx)
{
    swinging w, host;
    make_swinging(&w, 16, CVK_LINEAR_RBGS);
    make_swinging(&host, 16, CVK_LINEAR_GS_CPU);
    w.scene.solver.linear = CVK_LINEAR_JACOBI;
    cvk_sim* jacobi = make_sim(ctx, &w.scene);
    w.scene.solver.linear = CVK_LINEAR_RBGS;
    cvk_sim* rbgs = make_sim(ctx, &w.scene);
    cvk_sim* cpu = make_sim(ctx, &host.scene);
    cvk_error err;
    REQUIRE_OK(cvk_sim_step(jacobi, 3, &err), err);
    uint64_t size, cpu_size;
    void* snap = save(jacobi, &size);
    void* cpu_snap = save(cpu, &cpu_size);
    REQUIRE_OK(cvk_sim_load_snapshot(rbgs, snap, size, &err), err);
    float *xj = positions(jacobi), *xr = positions(rbgs);
    uint64_t n = cvk_sim_particle_count(rbgs);
    CHECK(memcmp(xj, xr, 3 * n * sizeof(float)) == 0,
          "a jacobi snapshot loaded into rbgs gives other positions (%g m off)",
          harness_max_diff(xj, xr, 3 * n));
    check_refusal(cvk_sim_load_snapshot(rbgs, cpu_snap, cpu_size, &err), &err,
                  CVK_ERROR_INVALID_ARGUMENT,
                  "cvk_sim_load_snapshot: the snapshot holds the gs-cpu solver's host state; "
                  "this simulation solves with rbgs: set that kind of solver first "
                  "(cvk_sim_set_solver)", "gs-cpu's snapshot into rbgs");
    printf("across solvers: jacobi -> rbgs loads; gs-cpu -> rbgs refused\n");
    free(snap);
    free(cpu_snap);
    free(xj);
    free(xr);
    cvk_sim_destroy(jacobi);
    cvk_sim_destroy(rbgs);
    cvk_sim_destroy(cpu);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    const cvk_linear_solver solvers[] = {CVK_LINEAR_RBGS, CVK_LINEAR_JACOBI,
                                         CVK_LINEAR_CHEBYSHEV, CVK_LINEAR_GS_CPU};
    for (size_t i = 0; i < sizeof solvers / sizeof solvers[0]; i++)
        resume_is_exact(ctx, solvers[i]);
    refusals(ctx);
    edge_pairs(ctx);
    across_solvers(ctx);
    return harness_finish(ctx);
}
