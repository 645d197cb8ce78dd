/* Determinism as a promise, in the manner of Box2D's determinism test: a grid cloth and an
   irregular mesh cloth are stepped for a fixed number of frames under several compute shapes
   (workgroup sizes × workgroups per dispatch × invocations per particle in the self-contact
   search) with each GPU solver, and one hash of the final
   positions (FNV-1a 64 over the float bytes of cvk_sim_read_positions) must be the same for
   every shape and again on a second run of the first shape. A scene of instances (three
   copies of a cloth with its colliders) gets the same test, its hash again under three
   lavapipe thread counts, and each copy is checked against the single cloth's run moved by its
   offset; so does a scene of three copies at one place with self-contact, each copy bit for
   bit the single cloth's self-contact run (copies never touch one another). A crowd of layers
   overflows the particles' side lists (check_crowd_scene).

   Why it should hold: every pass is a loop over particles in which each particle's result
   depends only on the data, never on which invocation or workgroup computes it; no pass
   reduces across invocations in floating point, so the dispatch shape cannot reorder a
   floating-point sum; and what depends on the order of atomics (a spatial hash cell's entries,
   the edges' buckets, the side lists) is read as a set: minima, and lists sorted by distance and
   index. A shape that changes the hash breaks that rule.

   rbgs runs twice: with solver.fuse off (one dispatch per colour and sweep) and on (every
   sweep of a substep in one dispatch of one workgroup, lib/solvers/solve_pd.h — for the
   instances without self-contact a workgroup a copy, striding over the copies where a shape
   allows fewer workgroups), and
   the fused hash must equal the unfused one: the same operations in the same order per
   particle, so the same bits, under every shape, and for the instances under every thread
   count too. */
#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"

#define FRAMES 6

typedef struct shape {
    uint32_t workgroup_size;
    uint32_t max_workgroups; /* 0: the library's choice */
    int fused_shared_memory; /* cvk_sim_desc's: 1 where it fits, -1 never */
} shape;

/* The first shape is the library's default; it also runs a second time. Every shape asks the
   fused sweeps to keep their iterate in shared memory (on lavapipe the library keeps it in
   global memory: check_fused_global). */
static const shape shapes[] = {
    {0, 0, 1},  {8, 1, 1},  {8, 3, 1},  {8, 0, 1},   {32, 1, 1},  {32, 3, 1},
    {32, 0, 1}, {64, 1, 1}, {64, 3, 1}, {256, 1, 1}, {256, 3, 1}, {256, 0, 1},
};
#define SHAPE_COUNT (sizeof shapes / sizeof shapes[0])
/* Under the sanitizers (tests/sanitize.sh sets CLOTHVK_SANITIZED=1) the default shape, one
   other and the second run, and no other lavapipe thread counts: that run looks for memory
   errors, whose code paths these reach; every shape's and thread count's bits are checked by the
   unsanitized run. The other is three workgroups of the default size: more than one workgroup
   a dispatch (what sizes the per-workgroup buffers and loops over groups), with the default
   shape's pipelines, which the context already holds; three workgroups of 32 compiled every
   pipeline again, most of the sanitized run (determinism-contact 139 s alone on the 2-core VM).
   (Five shapes there made the sanitized determinism tests over 13 minutes of CI's run.) */
static const shape sanitized_shapes[] = {{0, 3, 1}};
#define SANITIZED_COUNT (sizeof sanitized_shapes / sizeof sanitized_shapes[0])

typedef struct variant {
    cvk_linear_solver linear;
    cvk_fuse fuse;
    cvk_method method;
} variant;

/* The fused rbgs follows the unfused one, whose hash it must give. */
static const variant variants[] = {
    {CVK_LINEAR_RBGS, CVK_FUSE_OFF, CVK_METHOD_PD},
    {CVK_LINEAR_RBGS, CVK_FUSE_ON, CVK_METHOD_PD},
    {CVK_LINEAR_JACOBI, CVK_FUSE_AUTO, CVK_METHOD_PD},
    {CVK_LINEAR_CHEBYSHEV, CVK_FUSE_AUTO, CVK_METHOD_PD},
};

static uint64_t fnv1a64(const void* data, size_t bytes)
{
    const unsigned char* p = data;
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < bytes; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

/* ---- the two scenes ------------------------------------------------------------------------ */

/* 24 × 24, every spring kind, pinned at the two top corners: it falls and swings. */
static cvk_cloth_desc grid_cloth(void)
{
    static const uint32_t pins[2][2] = {{0, 0}, {23, 0}};
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.name = "grid";
    c.grid[0] = c.grid[1] = 24;
    c.size[0] = c.size[1] = 0.6f;
    c.stiffness.structural = 1e5f;
    c.stiffness.shear = 1e4f;
    c.stiffness.bend = 1e2f;
    c.pins = pins;
    c.pin_count = 2;
    return c;
}

#define MESH_SIDE 8 /* vertices along each side of the jittered lattice */

/* An irregular triangle mesh, 0.4 m square in the x-y plane: a jittered lattice whose cells
   are split along a random diagonal or, one in four, into a fan around an added centre vertex
   (valences from 3 to 8: the colouring is greedy, not a grid's). Written as OBJ to `path`;
   returns the number of vertices, or 0 when the file cannot be written. */
static uint32_t write_mesh(const char* path)
{
    FILE* f = fopen(path, "w");
    if (!f)
        return 0;
    harness_rng rng = {12345};
    const double d = 0.4 / (MESH_SIDE - 1);
    fprintf(f, "# irregular test cloth\n");
    for (int j = 0; j < MESH_SIDE; j++)
        for (int i = 0; i < MESH_SIDE; i++) {
            bool edge = i == 0 || j == 0 || i == MESH_SIDE - 1 || j == MESH_SIDE - 1;
            double jx = edge ? 0.0 : harness_uniform(&rng, -0.2, 0.2) * d;
            double jy = edge ? 0.0 : harness_uniform(&rng, -0.2, 0.2) * d;
            fprintf(f, "v %.6f %.6f 0\n", i * d + jx, 1.0 - j * d + jy);
        }
    int next = MESH_SIDE * MESH_SIDE + 1; /* OBJ numbers from 1 */
    for (int j = 0; j + 1 < MESH_SIDE; j++)
        for (int i = 0; i + 1 < MESH_SIDE; i++) {
            /* a b / c e: a = [i, j], b = [i+1, j], c = [i, j+1], e = [i+1, j+1]; counter-
               clockwise seen from +z, since j runs down. */
            int a = j * MESH_SIDE + i + 1, b = a + 1, c = a + MESH_SIDE, e = c + 1;
            uint32_t pick = harness_next(&rng) % 4;
            if (pick == 0) {
                fprintf(f, "v %.6f %.6f 0\n", (i + 0.5) * d, 1.0 - (j + 0.5) * d);
                int m = next++;
                fprintf(f, "f %d %d %d\nf %d %d %d\nf %d %d %d\nf %d %d %d\n", a, c, m, c, e, m, e,
                        b, m, b, a, m);
            } else if (pick == 1) {
                fprintf(f, "f %d %d %d\nf %d %d %d\n", a, c, b, b, c, e);
            } else {
                fprintf(f, "f %d %d %d\nf %d %d %d\n", a, c, e, a, e, b);
            }
        }
    return fclose(f) == 0 ? (uint32_t)next - 1 : 0;
}

static cvk_cloth_desc mesh_cloth(const char* path)
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.name = "mesh";
    c.mesh = path;
    c.stiffness.structural = 1e5f;
    c.stiffness.shear = 0.0f;
    c.stiffness.bend = 1e2f;
    /* Two vertices at the top-left corner (the edge is not jittered): the cloth swings down
       and sideways, so every solver moves it by centimetres. (Pinned along its whole top edge
       it hangs in its own plane and only stretches: a well-converged solve moves it by less
       than a millimetre.) A box says which vertices without relying on the particle order. */
    c.use_pin_box = true;
    c.pin_box = (cvk_box3){{-0.01f, 0.99f, -0.01f}, {0.07f, 1.01f, 0.01f}};
    return c;
}

/* ---- runs ---------------------------------------------------------------------------------- */

typedef struct outcome {
    bool ok;
    uint64_t hash;
    float* xyz; /* final positions, for the size of a difference */
    uint64_t count;
    uint32_t iterations_last;    /* the solver's sweeps in the last frame (cvk_sim_stats) */
    uint64_t iterations_total;   /* and in all frames */
    bool one_group;              /* fused sweeps in one workgroup, not a workgroup a copy */
} outcome;

static outcome run(cvk_context* ctx, const cvk_scene_desc* scene, shape sh, cvk_error* err)
{
    outcome o = {0};
    cvk_sim* sim = NULL;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = scene;
    desc.workgroup_size = sh.workgroup_size;
    desc.max_workgroups = sh.max_workgroups;
    desc.fused_shared_memory = sh.fused_shared_memory;
    desc.timing = -1;
    if (cvk_sim_create(ctx, &desc, &sim, err) != CVK_SUCCESS)
        return o;
    /* The plan fuses the sweeps exactly when asked to (these scenes allow it), their iterate in
       shared memory unless told otherwise (these scenes fit lavapipe's). */
    if (scene->solver.linear == CVK_LINEAR_RBGS && scene->solver.fuse != CVK_FUSE_AUTO) {
        static char text[16384];
        cvk_sim_describe_plan(sim, text, sizeof text);
        const char* expected = scene->solver.fuse == CVK_FUSE_ON ? "sweeps fused"
                                                                 : "sweeps not fused";
        CHECK(strstr(text, expected) != NULL, "the plan does not say \"%s\":\n%s", expected, text);
        const char* memory = sh.fused_shared_memory < 0 ? "global memory" : "shared memory";
        CHECK(scene->solver.fuse == CVK_FUSE_OFF || strstr(text, memory) != NULL,
              "the plan does not say \"%s\":\n%s", memory, text);
        o.one_group = scene->solver.fuse == CVK_FUSE_ON && !strstr(text, "a workgroup a copy");
    }
    cvk_sim_stats st;
    if (cvk_sim_step(sim, FRAMES, err) == CVK_SUCCESS &&
        cvk_sim_get_stats(sim, &st, err) == CVK_SUCCESS) {
        o.count = cvk_sim_particle_count(sim);
        o.xyz = harness_read_all(sim);
        o.hash = fnv1a64(o.xyz, 3 * o.count * sizeof(float));
        o.iterations_last = st.solver_iterations;
        o.iterations_total = st.solver_iterations_total;
        o.ok = true;
    }
    cvk_sim_destroy(sim);
    return o;
}

static const char* shape_text(shape sh, char* text, size_t size)
{
    char wg[16], mw[16];
    snprintf(wg, sizeof wg, "%u", sh.workgroup_size);
    snprintf(mw, sizeof mw, "%u", sh.max_workgroups);
    snprintf(text, size, "workgroup size %s, max workgroups %s",
             sh.workgroup_size ? wg : "default", sh.max_workgroups ? mw : "default");
    return text;
}

/* Everything moved and stayed finite: a hash of a cloth at rest would prove little. */
static void check_moved(const char* what, const outcome* o, const float* start)
{
    uint64_t bad = 0;
    for (uint64_t i = 0; i < 3 * o->count; i++)
        bad += !isfinite(o->xyz[i]);
    CHECK(bad == 0, "%s: %llu coordinates are not finite", what, (unsigned long long)bad);
    double moved = harness_max_diff(o->xyz, start, 3 * o->count);
    CHECK(moved > 1e-3, "%s: the cloth moved only %g m in %d frames", what, moved, FRAMES);
}

/* One scene and solver under every shape, then the first shape again; returns the hash of
   the first shape (0 when it failed). */
static bool sanitized(void)
{
    const char* value = getenv("CLOTHVK_SANITIZED");
    return value != NULL && strcmp(value, "1") == 0;
}

/* Whether a shape before shapes[s] has its workgroup size: for fused sweeps in one
   workgroup (the plan does not say "a workgroup a copy", as for instances without
   self-contact, up to max_workgroups of them, which keep every shape), shapes that differ
   only in max_workgroups run the same fused dispatches (detection fused is one workgroup too,
   and the passes outside them are the unfused plan's, whose runs check them under every
   shape), so each size runs once (5 runs with the second instead of 12; on lavapipe a fused run of the default
   size, one workgroup of 1024, takes about 3 s of the 2-core VM, one of 8 a fraction). */
static bool size_run_before(size_t s)
{
    for (size_t t = 0; t < s; t++)
        if (shapes[t].workgroup_size == shapes[s].workgroup_size)
            return true;
    return false;
}

/* The hash of the default shape's run, which every other shape and a second run must give;
   `counted` (or NULL) gets that run's solver sweeps. */
static uint64_t check_solver_counted(cvk_context* ctx, const char* name, cvk_scene_desc scene,
                                     variant v, const float* start, outcome* counted)
{
    scene.solver.linear = v.linear;
    scene.solver.fuse = v.fuse;
    scene.solver.method = v.method;
    char what[96], text[96];
    snprintf(what, sizeof what, "%s, %s%s%s", name,
             v.method == CVK_METHOD_IMPLICIT ? "implicit " : "", cvk_linear_solver_name(v.linear),
             v.linear != CVK_LINEAR_RBGS ? "" : v.fuse == CVK_FUSE_ON ? " fused" : " unfused");
    cvk_error err;
    outcome first = run(ctx, &scene, shapes[0], &err);
    CHECK(first.ok, "%s: %s", what, err.message);
    if (!first.ok)
        return 0;
    check_moved(what, &first, start);
    if (counted) {
        counted->iterations_last = first.iterations_last;
        counted->iterations_total = first.iterations_total;
    }
    uint32_t same = 0, runs = 0;
    bool few = sanitized();
    size_t count = few ? SANITIZED_COUNT : SHAPE_COUNT;
    /* shapes[0] is the first run's; the last is its second run */
    for (size_t s = few ? 0 : 1; s <= count; s++) {
        shape sh = s == count ? shapes[0] : few ? sanitized_shapes[s] : shapes[s];
        if (s < count && !few && first.one_group && size_run_before(s))
            continue;
        runs++;
        outcome o = run(ctx, &scene, sh, &err);
        shape_text(sh, text, sizeof text);
        CHECK(o.ok, "%s, %s: %s", what, text, err.message);
        if (o.ok) {
            CHECK(o.hash == first.hash,
                  "%s, %s%s: hash %016llx, the default shape gave %016llx; positions differ by "
                  "up to %g m", what, text, s == count ? " (second run)" : "",
                  (unsigned long long)o.hash, (unsigned long long)first.hash,
                  harness_max_diff(o.xyz, first.xyz, 3 * o.count));
            same += o.hash == first.hash;
        }
        free(o.xyz);
    }
    printf("%s: hash %016llx after %d frames, the same for %u of %u shapes and runs\n", what,
           (unsigned long long)first.hash, FRAMES, same, runs);
    free(first.xyz);
    return first.hash;
}

static uint64_t check_solver(cvk_context* ctx, const char* name, cvk_scene_desc scene,
                             variant v, const float* start)
{
    return check_solver_counted(ctx, name, scene, v, start, NULL);
}

/* Initial positions of a scene (a simulation that has not stepped), or NULL with the reason. */
static float* initial_positions(cvk_context* ctx, const cvk_scene_desc* scene, uint64_t* count,
                                cvk_error* err)
{
    cvk_sim* sim = NULL;
    cvk_sim_desc desc = cvk_default_sim_desc();
    desc.scene = scene;
    desc.timing = -1;
    if (cvk_sim_create(ctx, &desc, &sim, err) != CVK_SUCCESS)
        return NULL;
    *count = cvk_sim_particle_count(sim);
    float* xyz = harness_read_all(sim);
    cvk_sim_destroy(sim);
    return xyz;
}

/* The fused sweeps with their iterate in global memory (cvk_sim_desc.fused_shared_memory -1;
   every shape above keeps it in shared memory) give the unfused hash too: under the default
   shape and three workgroups of 32 (the first alone under the sanitizers). */
static void check_fused_global(cvk_context* ctx, const char* name, cvk_scene_desc scene,
                               uint64_t unfused)
{
    static const shape global[] = {{0, 0, -1}, {32, 3, -1}};
    scene.solver.linear = CVK_LINEAR_RBGS;
    scene.solver.fuse = CVK_FUSE_ON;
    size_t count = sanitized() ? 1 : sizeof global / sizeof global[0]; /* the host code is one */
    for (size_t s = 0; s < count; s++) {
        char text[96];
        shape_text(global[s], text, sizeof text);
        cvk_error err;
        outcome o = run(ctx, &scene, global[s], &err);
        CHECK(o.ok, "%s, rbgs fused in global memory, %s: %s", name, text, err.message);
        if (o.ok)
            CHECK(o.hash == unfused, "%s, rbgs fused in global memory, %s: hash %016llx, unfused "
                  "%016llx", name, text, (unsigned long long)o.hash,
                  (unsigned long long)unfused);
        printf("%s, rbgs fused in global memory, %s: hash %016llx\n", name, text,
               (unsigned long long)o.hash);
        free(o.xyz);
    }
}

/* `particles`: how many the scene must have (the mesh file's vertices); `variant_count`: the
   first so many of `variants`. */
static void check_variants(cvk_context* ctx, const char* name, const cvk_scene_desc* scene,
                           uint64_t particles, size_t variant_count)
{
    cvk_error err;
    uint64_t count = 0;
    float* start = initial_positions(ctx, scene, &count, &err);
    CHECK(start != NULL, "%s: %s", name, err.message);
    if (!start)
        return;
    CHECK(count == particles, "%s: %llu particles, expected %llu", name, (unsigned long long)count,
          (unsigned long long)particles);
    uint64_t unfused = 0;
    for (size_t k = 0; k < variant_count; k++) {
        uint64_t hash = check_solver(ctx, name, *scene, variants[k], start);
        if (variants[k].linear == CVK_LINEAR_RBGS && variants[k].fuse == CVK_FUSE_OFF)
            unfused = hash;
        if (variants[k].linear == CVK_LINEAR_RBGS && variants[k].fuse == CVK_FUSE_ON) {
            CHECK(hash == unfused, "%s: rbgs fused gave hash %016llx, unfused %016llx", name,
                  (unsigned long long)hash, (unsigned long long)unfused);
            check_fused_global(ctx, name, *scene, unfused);
        }
    }
    free(start);
}

static void check_scene(cvk_context* ctx, const char* name, const cvk_scene_desc* scene,
                        uint64_t particles)
{
    check_variants(ctx, name, scene, particles, sizeof variants / sizeof variants[0]);
}

/* Contact: two cloths falling onto a sphere and onto each other while a keyframed box sweeps
   under them, with self-contact (the hash, the candidate search and the contact pass), with
   every pd solver and with implicit Euler's cg and jacobi. */
static void check_contact_scene(cvk_context* ctx, const cvk_scene_desc* base)
{
    cvk_cloth_desc cloths[2];
    for (int i = 0; i < 2; i++) {
        cloths[i] = cvk_default_cloth_desc();
        cloths[i].grid[0] = cloths[i].grid[1] = 16;
        cloths[i].size[0] = cloths[i].size[1] = 0.5f;
        cloths[i].origin[0] = -0.25f + 0.04f * i;
        cloths[i].origin[1] = 0.22f + 0.03f * i;
        cloths[i].origin[2] = -0.25f;
        cloths[i].stiffness.shear = 1e5f;
    }
    cvk_collider_desc colliders[2] = {cvk_default_collider_desc(), cvk_default_collider_desc()};
    colliders[0].type = CVK_COLLIDER_SPHERE;
    colliders[0].radius = 0.2f;
    colliders[1].type = CVK_COLLIDER_BOX;
    colliders[1].center[1] = 0.1f;
    colliders[1].half_extents[0] = colliders[1].half_extents[1] = colliders[1].half_extents[2] = 0.1f;
    static const cvk_keyframe keys[2] = {
        {.time = 0.0f, .translation = {-0.4f, 0.0f, 0.0f}, .rotation = {1, 0, 0, 0}},
        {.time = 0.1f, .translation = {0.4f, 0.0f, 0.0f}, .rotation = {0.7071068f, 0, 0.7071068f, 0}},
    };
    colliders[1].motion.keyframes = keys;
    colliders[1].motion.keyframe_count = 2;
    cvk_scene_desc scene = *base;
    scene.cloths = cloths;
    scene.cloth_count = 2;
    scene.colliders = colliders;
    scene.collider_count = 2;
    scene.collision.self = true;
    const char* name = "two cloths, sphere, moving box, self-contact";
    check_scene(ctx, name, &scene, 2 * 16 * 16);
    /* Detections held back to every third substep (collision.detection_interval): the
       decision, unfused and in the fused sweeps' one workgroup. */
    scene.collision.detection_interval = 3;
    check_variants(ctx, "the same, detection interval 3", &scene, 2 * 16 * 16, 2);
    scene.collision.detection_interval = 1;
    /* Implicit Euler's self-contact (implicit_integrate.comp, implicit_self.comp): block
       Jacobi under every shape; CG, whose dot products are summed over as many partial sums as
       the workgroup size makes (library.md, "Determinism"), from run to run. Jacobi at most
       16 sweeps a solve, not the default 100: its solves in contact reach neither 100 nor the
       tolerance, and 100 made its 14 runs most of this test's time (6 frames, 5-8 s a run on
       the 2-core VM). At 16 the solves of the first frames, before contact, stop at the
       tolerance and those of the last frame at 16: both ends of the device's loop run. */
    cvk_error err;
    uint64_t count = 0;
    float* start = initial_positions(ctx, &scene, &count, &err);
    CHECK(start != NULL, "%s: %s", name, err.message);
    enum { JACOBI_SWEEPS = 16 };
    scene.solver.max_iterations = JACOBI_SWEEPS;
    outcome counted = {0};
    if (start && check_solver_counted(ctx, name, scene, (variant){CVK_LINEAR_JACOBI,
                                      CVK_FUSE_AUTO, CVK_METHOD_IMPLICIT}, start, &counted)) {
        /* A solve a substep; at a cap of one sweep every solve runs one: so many a frame. */
        cvk_scene_desc one = scene;
        one.solver.method = CVK_METHOD_IMPLICIT;
        one.solver.linear = CVK_LINEAR_JACOBI;
        one.solver.max_iterations = 1;
        outcome solves = run(ctx, &one, shapes[0], &err);
        CHECK(solves.ok, "%s, implicit jacobi at one sweep: %s", name, err.message);
        uint64_t capped = (uint64_t)solves.iterations_last * JACOBI_SWEEPS;
        CHECK(solves.ok && solves.iterations_last > 0 &&
              counted.iterations_last == capped &&
              counted.iterations_total < capped * FRAMES,
              "%s, implicit jacobi: %u sweeps in the last frame of %u solves, %llu in %d "
              "frames: expected the last frame's solves all at the cap of %d sweeps and "
              "earlier ones stopped sooner by the tolerance", name, counted.iterations_last,
              solves.iterations_last, (unsigned long long)counted.iterations_total, FRAMES,
              JACOBI_SWEEPS);
        printf("%s, implicit jacobi: %u sweeps in the last frame (%u solves at the cap of "
               "%d), %llu in %d frames\n", name, counted.iterations_last,
               solves.iterations_last, JACOBI_SWEEPS,
               (unsigned long long)counted.iterations_total, FRAMES);
        free(solves.xyz);
    }
    scene.solver.max_iterations = 0;
    free(start);
    scene.solver.method = CVK_METHOD_IMPLICIT;
    scene.solver.linear = CVK_LINEAR_CG;
    outcome runs[2] = {run(ctx, &scene, shapes[0], &err), run(ctx, &scene, shapes[0], &err)};
    CHECK(runs[0].ok && runs[1].ok, "%s, implicit cg: %s", name, err.message);
    if (runs[0].ok && runs[1].ok) {
        CHECK(runs[0].hash == runs[1].hash, "%s, implicit cg: hash %016llx, then %016llx", name,
              (unsigned long long)runs[0].hash, (unsigned long long)runs[1].hash);
        printf("%s, implicit cg: hash %016llx after %d frames, the same in a second run\n", name,
               (unsigned long long)runs[0].hash, FRAMES);
    }
    free(runs[0].xyz);
    free(runs[1].xyz);
}

/* A cloth caught in a funnel's neck, its corners on the wall from the start: the funnel's
   edge test (pd_contact.glsl, edges_off_shells) reads the neighbours' iterate before, never the
   one being written. */
static void check_funnel_scene(cvk_context* ctx, const cvk_scene_desc* base)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = 16;
    cloth.size[0] = cloth.size[1] = 0.5f;
    cloth.origin[0] = cloth.origin[2] = -0.25f;
    cloth.origin[1] = 0.1f; /* the funnel's radius there is e^-1 = 0.368 m, the corners' 0.354 */
    cvk_collider_desc funnel = cvk_default_collider_desc();
    funnel.type = CVK_COLLIDER_FUNNEL;
    funnel.apex[1] = 0.5f;
    funnel.funnel_a = 0.4f;
    funnel.height = 0.6f;
    cvk_scene_desc scene = *base;
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.colliders = &funnel;
    scene.collider_count = 1;
    check_scene(ctx, "a cloth in a funnel's neck", &scene, 16 * 16);
}

/* The passes between outer iterations: strain limiting, tethers and contact with a plane after
   every outer iteration, between the fused dispatches as between the unfused sweeps (rbgs
   only: the other solvers have no fused path). */
static void check_between_scene(cvk_context* ctx, const cvk_scene_desc* base)
{
    static const uint32_t pins[2][2] = {{0, 0}, {15, 0}};
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = 16;
    cloth.size[0] = cloth.size[1] = 0.5f;
    cloth.origin[1] = 0.3f;
    cloth.stiffness.shear = 1e4f;
    cloth.pins = pins;
    cloth.pin_count = 2;
    cloth.tethers = 1.0f;
    cvk_collider_desc ground = cvk_default_collider_desc();
    ground.type = CVK_COLLIDER_PLANE;
    ground.point[1] = 0.28f; /* 3 mm below the thickness (half a spring): hit in a few frames */
    cvk_scene_desc scene = *base;
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.colliders = &ground;
    scene.collider_count = 1;
    scene.solver.strain_limit = 0.05f;
    /* Three outer iterations, the tethers after the second and the last only: the fused
       dispatch's iterates swap roles an odd number of times, and its tethers skip the first. */
    scene.solver.outer_iterations = 3;
    scene.solver.tether_every = 2;
    check_variants(ctx, "strain limit, tethers every second outer iteration, a plane", &scene,
                   16 * 16, 2); /* rbgs */
}

/* The passes after the sweeps that the fused dispatch runs itself where no tether pass comes
   between (pd_fused.comp): the strain limit's rounds, contact between cloths and contact over
   every particle, the attached ones too, with the fused decision, measure and hash builds
   (contact_faces_fused.comp, contact_edges_fused.comp) — a cloth dragged by an attachment across the
   ground under another falling on it, with self-contact; rbgs unfused and fused. */
static void check_fused_after_scene(cvk_context* ctx, const cvk_scene_desc* base)
{
    static const uint32_t held[3][2] = {{0, 0}, {6, 0}, {11, 0}};
    cvk_cloth_desc cloths[2];
    for (int i = 0; i < 2; i++) {
        cloths[i] = cvk_default_cloth_desc();
        cloths[i].grid[0] = cloths[i].grid[1] = 12;
        cloths[i].size[0] = cloths[i].size[1] = 0.4f;
        cloths[i].origin[0] = -0.2f + 0.05f * i;
        cloths[i].origin[1] = 0.05f + 0.021f * i; /* within the radius: pairs at once */
        cloths[i].origin[2] = -0.2f;
        cloths[i].stiffness.shear = 1e4f;
    }
    static const cvk_keyframe drag[2] = {
        {.time = 0.0f, .rotation = {1, 0, 0, 0}},
        /* faster than a bound a substep: the contact pass holds the attached particles */
        {.time = 0.1f, .translation = {0.5f, 0.05f, 0.0f}, .rotation = {1, 0, 0, 0}},
    };
    cvk_attachment_desc hand = cvk_default_attachment_desc();
    hand.cloth = 0;
    hand.pins = held;
    hand.pin_count = 3;
    hand.motion.keyframes = drag;
    hand.motion.keyframe_count = 2;
    cvk_collider_desc ground = cvk_default_collider_desc();
    ground.type = CVK_COLLIDER_PLANE;
    ground.point[1] = 0.03f;
    cvk_scene_desc scene = *base;
    scene.cloths = cloths;
    scene.cloth_count = 2;
    scene.attachments = &hand;
    scene.attachment_count = 1;
    scene.colliders = &ground;
    scene.collider_count = 1;
    scene.collision.self = true;
    scene.solver.strain_limit = 0.05f;
    check_variants(ctx, "strain limit, an attachment, self-contact, a plane", &scene,
                   2 * 12 * 12, 2); /* rbgs unfused and fused */
}

/* ---- instances ----------------------------------------------------------------------------- */

/* Three copies of a 12 × 12 cloth falling onto a sphere while a box that turns as it slides
   sweeps under it (scene-format.md, "instances"), 1.5 m apart along x and 0.25 m along z; the
   same text without the block is the single cloth they copy. */
#define INSTANCE_SCENE                                                                          \
    "{\"substeps\": 4, \"solver\": {\"outer_iterations\": 2, \"inner_iterations\": 4},"      \
    " \"cloths\": [{\"grid\": [12, 12], \"size\": [0.5, 0.5], \"origin\": [-0.25, 0.3, -0.25],"\
    " \"stiffness\": {\"structural\": 1e5, \"shear\": 1e4}, \"pins\": [[0, 0]]}],"            \
    " \"colliders\": [{\"type\": \"sphere\", \"radius\": 0.2},"                               \
    " {\"type\": \"box\", \"center\": [0, 0.1, 0], \"half_extents\": [0.1, 0.1, 0.1],"          \
    "  \"keyframes\": [{\"time\": 0, \"translation\": [-0.4, 0, 0]},"                          \
    "   {\"time\": 0.1, \"translation\": [0.4, 0, 0], \"rotation\": [0.7071068, 0, 0.7071068, 0]}]}]"
#define INSTANCES 3
static const float instance_step[3] = {1.5f, 0.0f, 0.25f};

static cvk_scene* parse_scene(const char* text, const char* name)
{
    cvk_scene* scene = NULL;
    cvk_error err;
    CHECK(cvk_scene_parse(text, name, NULL, 0, &scene, &err) == CVK_SUCCESS, "%s: %s", name,
          err.message);
    return scene;
}

/* lavapipe's worker threads in this process (named llvmpipe-N). */
static int lavapipe_threads(void)
{
    int count = 0;
    DIR* dir = opendir("/proc/self/task");
    if (!dir)
        return -1;
    for (struct dirent* e; (e = readdir(dir));) {
        char path[300], name[32];
        snprintf(path, sizeof path, "/proc/self/task/%s/comm", e->d_name);
        FILE* f = e->d_name[0] != '.' ? fopen(path, "r") : NULL;
        if (!f)
            continue;
        count += fgets(name, sizeof name, f) && !strncmp(name, "llvmpipe", 8);
        fclose(f);
    }
    closedir(dir);
    return count;
}

/* The default shape's hash again on fresh contexts with other lavapipe thread counts
   (LP_NUM_THREADS, read when a context opens the device), with rbgs's sweeps as the scene has
   them (solver.fuse auto: unfused on lavapipe) and fused. */
static void check_thread_counts(const cvk_scene_desc* scene, uint64_t hash)
{
    if (sanitized()) {
        printf("instances: other lavapipe thread counts not run under the sanitizers\n");
        return;
    }
    const char* before = getenv("LP_NUM_THREADS");
    char* saved = before ? strdup(before) : NULL;
    static const char* const threads[] = {"0", "1", "3"};
    for (size_t t = 0; t < sizeof threads / sizeof threads[0]; t++) {
        setenv("LP_NUM_THREADS", threads[t], 1);
        cvk_context* ctx = harness_context();
        for (int fused = 0; fused < 2; fused++) {
            cvk_scene_desc s = *scene;
            if (fused)
                s.solver.fuse = CVK_FUSE_ON;
            const char* how = fused ? ", fused" : "";
            cvk_error err;
            outcome o = run(ctx, &s, shapes[0], &err);
            CHECK(o.ok, "instances%s, LP_NUM_THREADS=%s: %s", how, threads[t], err.message);
            if (o.ok)
                CHECK(o.hash == hash, "instances%s, LP_NUM_THREADS=%s: hash %016llx, expected "
                      "%016llx", how, threads[t], (unsigned long long)o.hash,
                      (unsigned long long)hash);
            printf("instances%s, LP_NUM_THREADS=%s (%d lavapipe threads running): hash %016llx\n",
                   how, threads[t], lavapipe_threads(), (unsigned long long)o.hash);
            free(o.xyz);
        }
        CHECK(cvk_context_validation_message_count(ctx) == 0, "LP_NUM_THREADS=%s: %u validation "
              "messages", threads[t], cvk_context_validation_message_count(ctx));
        cvk_context_destroy(ctx);
    }
    if (saved)
        setenv("LP_NUM_THREADS", saved, 1);
    else
        unsetenv("LP_NUM_THREADS");
    free(saved);
}

/* Copy k after FRAMES frames is the single cloth's run moved by k × step. Copy 0 holds the
   same bits: its particles see the same numbers in the same order, and the other copies'
   colliders, 1.5 m away, never reach it. Copy k > 0 differs by rounding only: its positions
   are the single run's plus an offset of up to 3 m, so every stored coordinate rounds to
   2^-22 m (0.24 µm) at that magnitude instead of finer near the origin, and the solve
   propagates those differences (measured: 0.15 and 0.31 µm for copies 1 and 2); 1e-5 m is
   some forty of them. */
#define INSTANCE_BOUND 1e-5

static void check_instances(cvk_context* ctx)
{
    char text[2048];
    snprintf(text, sizeof text, "%s, \"instances\": {\"count\": %d, \"spacing\": [%g, %g, %g]}}",
             INSTANCE_SCENE, INSTANCES, instance_step[0], instance_step[1], instance_step[2]);
    cvk_scene* copies = parse_scene(text, "instances");
    cvk_scene* single = parse_scene(INSTANCE_SCENE "}", "single");
    if (!copies || !single) {
        cvk_scene_destroy(copies);
        cvk_scene_destroy(single);
        return;
    }
    const cvk_scene_desc* desc = cvk_scene_get_desc(copies);
    CHECK(desc->cloth_count == INSTANCES && desc->collider_count == 2 * INSTANCES,
          "instances: %u cloths and %u colliders, expected %d and %d", desc->cloth_count,
          desc->collider_count, INSTANCES, 2 * INSTANCES);
    check_scene(ctx, "instances: 3 copies of a cloth, sphere and moving box", desc,
                INSTANCES * 12 * 12);
    cvk_error err;
    outcome many = run(ctx, desc, shapes[0], &err);
    CHECK(many.ok, "instances: %s", err.message);
    outcome one = run(ctx, cvk_scene_get_desc(single), shapes[0], &err);
    CHECK(one.ok, "single: %s", err.message);
    CHECK(!many.ok || !one.ok || (one.count == 12 * 12 && many.count == INSTANCES * one.count),
          "instances: %llu particles, the single cloth %llu; expected %d and 144",
          (unsigned long long)many.count, (unsigned long long)one.count, INSTANCES * 12 * 12);
    if (many.ok && one.ok && many.count == INSTANCES * one.count) {
        for (int k = 0; k < INSTANCES; k++) {
            double worst = 0.0;
            for (uint64_t i = 0; i < 3 * one.count; i++) {
                double moved = (double)one.xyz[i] + k * (double)instance_step[i % 3];
                double d = fabs((double)many.xyz[3 * k * one.count + i] - moved);
                worst = d > worst ? d : worst;
            }
            if (k == 0)
                CHECK(worst == 0.0, "copy 0 is %g m from the single cloth's run", worst);
            else
                CHECK(worst <= INSTANCE_BOUND, "copy %d is %g m from the single cloth's run "
                      "moved by %d steps; the bound is %g m", k, worst, k, INSTANCE_BOUND);
            printf("instances: copy %d is %g m from the single cloth's run moved by its offset\n",
                   k, worst);
        }
        check_thread_counts(desc, many.hash);
    }
    free(many.xyz);
    free(one.xyz);
    cvk_scene_destroy(copies);
    cvk_scene_destroy(single);
}

/* The same cloth, sphere and box with self-contact, three copies at one place (spacing 0):
   copies never touch one another (detection, the bounds and the colliders each copy meets are
   its own), so every copy must be the single cloth's self-contact run bit for bit, and the
   scene's hash the same under every dispatch shape and thread count. */
#define SELF_SCENE INSTANCE_SCENE ", \"collision\": {\"self\": true}"

static void check_instances_self(cvk_context* ctx)
{
    char text[2048];
    snprintf(text, sizeof text, "%s, \"instances\": {\"count\": %d, \"spacing\": [0, 0, 0]}}",
             SELF_SCENE, INSTANCES);
    cvk_scene* copies = parse_scene(text, "instances with self-contact");
    cvk_scene* single = parse_scene(SELF_SCENE "}", "single with self-contact");
    if (!copies || !single) {
        cvk_scene_destroy(copies);
        cvk_scene_destroy(single);
        return;
    }
    const cvk_scene_desc* desc = cvk_scene_get_desc(copies);
    check_scene(ctx, "instances: 3 copies at one place, self-contact, sphere and moving box",
                desc, INSTANCES * 12 * 12);
    cvk_error err;
    outcome many = run(ctx, desc, shapes[0], &err);
    CHECK(many.ok, "instances with self-contact: %s", err.message);
    outcome one = run(ctx, cvk_scene_get_desc(single), shapes[0], &err);
    CHECK(one.ok, "single with self-contact: %s", err.message);
    CHECK(!many.ok || !one.ok || (one.count == 12 * 12 && many.count == INSTANCES * one.count),
          "instances with self-contact: %llu particles, the single cloth %llu; expected %d and "
          "144", (unsigned long long)many.count, (unsigned long long)one.count,
          INSTANCES * 12 * 12);
    if (many.ok && one.ok && many.count == INSTANCES * one.count) {
        for (int k = 0; k < INSTANCES; k++) {
            uint64_t differ = 0;
            for (uint64_t i = 0; i < 3 * one.count; i++)
                differ += memcmp(&many.xyz[3 * k * one.count + i], &one.xyz[i], sizeof(float)) != 0;
            CHECK(differ == 0, "self-contact copy %d: %llu of %llu coordinates differ from the "
                  "single cloth's run", k, (unsigned long long)differ,
                  (unsigned long long)(3 * one.count));
            printf("instances with self-contact: copy %d has %llu coordinates unlike the single "
                   "cloth's run\n", k, (unsigned long long)differ);
        }
        check_thread_counts(desc, many.hash);
    }
    free(many.xyz);
    free(one.xyz);
    cvk_scene_destroy(copies);
    cvk_scene_destroy(single);
}

/* A crowd: sixteen 6 x 6 layers 1.2 mm apart, each shifted across the one below, falling onto a
   plane with self-contact. A particle is then a corner of more pairs than its side list holds
   (CVK_SIDES_PER_PARTICLE): which of them it kept was the order in which invocations reached
   the list, and this scene gave three hashes under four shapes; a crowded particle now keeps
   none (contact_bound.glsl), and contacts.crowded counts it, which must be above 0 here for the
   test to say anything. rbgs unfused only: fused, detection runs in one workgroup, and on
   lavapipe an invocation of it with this crowd's items passes the device's loop limit (a
   detection cut short: limits.md) under workgroups of 64 or fewer. */
#define CROWD_LAYERS 16

static void check_crowd_scene(cvk_context* ctx)
{
    char text[8192];
    int at = snprintf(text, sizeof text, "{\"name\": \"crowd\", \"dt\": 0.002, \"substeps\": 4, "
                      "\"solver\": {\"outer_iterations\": 2, \"inner_iterations\": 4}, "
                      "\"collision\": {\"self\": true}, \"colliders\": [{\"type\": \"plane\", "
                      "\"point\": [0, 0, 0], \"normal\": [0, 1, 0]}], \"cloths\": [");
    for (int i = 0; i < CROWD_LAYERS && at > 0 && (size_t)at < sizeof text; i++)
        at += snprintf(text + at, sizeof text - (size_t)at,
                       "%s{\"grid\": [6, 6], \"size\": [0.1, 0.1], \"mass\": 0.01, "
                       "\"origin\": [%g, %g, %g]}", i ? ", " : "", -0.05 + 0.0073 * (i % 3),
                       0.05 + 0.0012 * i, -0.05 + 0.0047 * (i % 4));
    CHECK(at > 0 && (size_t)at + 3 < sizeof text, "crowd: the scene text does not fit");
    if (at <= 0 || (size_t)at + 3 >= sizeof text)
        return;
    snprintf(text + at, sizeof text - (size_t)at, "]}");
    cvk_scene* crowd = parse_scene(text, "crowd");
    if (!crowd)
        return;
    const cvk_scene_desc* desc = cvk_scene_get_desc(crowd);
    cvk_sim* sim = NULL;
    cvk_sim_desc sd = cvk_default_sim_desc();
    sd.scene = desc;
    sd.timing = -1;
    cvk_error err;
    cvk_sim_stats st = {0};
    bool ok = cvk_sim_create(ctx, &sd, &sim, &err) == CVK_SUCCESS &&
              cvk_sim_step(sim, FRAMES, &err) == CVK_SUCCESS &&
              cvk_sim_get_stats(sim, &st, &err) == CVK_SUCCESS;
    CHECK(ok, "crowd: %s", err.message);
    cvk_sim_destroy(sim);
    if (ok) {
        CHECK(st.contact_crowded > 0, "crowd: no particle was crowded in %d frames (%llu "
              "detections): the scene no longer tests the side lists' overflow", FRAMES,
              (unsigned long long)st.contact_searches);
        CHECK(st.intersecting_pairs == 0, "crowd: %llu intersecting pairs",
              (unsigned long long)st.intersecting_pairs);
        printf("crowd: %llu crowded particles over %llu detections in %d frames\n",
               (unsigned long long)st.contact_crowded, (unsigned long long)st.contact_searches,
               FRAMES);
    }
    check_variants(ctx, "crowd of 16 layers, self-contact, a plane", desc, CROWD_LAYERS * 36, 1);
    cvk_scene_destroy(crowd);
}

/* Every GPU solver on a grid cloth and on an irregular mesh cloth (written to a file first). */
static void check_solver_scenes(cvk_context* ctx, cvk_scene_desc scene)
{
    cvk_cloth_desc grid = grid_cloth();
    scene.cloths = &grid;
    scene.cloth_count = 1;
    check_scene(ctx, "grid 24 x 24", &scene, 24 * 24);

    char dir[] = "/tmp/clothvk-determinism-XXXXXX";
    char path[64] = "";
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp worked", "cannot make a folder under /tmp for the mesh file");
        return;
    }
    snprintf(path, sizeof path, "%s/irregular.obj", dir);
    uint32_t vertices = write_mesh(path);
    CHECK(vertices > 0, "cannot write %s", path);
    cvk_cloth_desc mesh = mesh_cloth(path);
    scene.cloths = &mesh;
    if (vertices > 0)
        check_scene(ctx, "irregular mesh", &scene, vertices);
    unlink(path);
    rmdir(dir);
}

/* The fused sweeps in a workgroup of 8, the iterate in shared memory and in global memory,
   against the unfused: a 40 x 40 cloth with shear springs (four colours, two quads of springs
   a particle) at 3 outer x 4 inner iterations, one substep a frame. Each invocation then sweeps
   50 particles a colour, and each neighbour read in shared memory once ran a loop over the
   colours (pd_fused.comp's slot_of), past llvmpipe's silent end of a loop after 65,535 steps an
   invocation: 1,631 coordinates up to 2.1e-5 m off after one substep (docs/limits.md). */
static void check_small_workgroup(cvk_context* ctx, cvk_scene_desc scene)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = 40;
    cloth.size[0] = cloth.size[1] = 1.2f;
    cloth.origin[0] = cloth.origin[2] = -0.6f;
    cloth.origin[1] = 0.8f;
    cloth.mass = 0.144f;
    cloth.stiffness.structural = cloth.stiffness.shear = 1e6f;
    cloth.stiffness.bend = 0.0f;
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.dt = 1.0f / 480.0f;
    scene.substeps = 1;
    scene.solver.outer_iterations = 3;
    scene.solver.inner_iterations = 4;
    scene.solver.omega = 1.5f;
    scene.solver.linear = CVK_LINEAR_RBGS;
    scene.solver.fuse = CVK_FUSE_OFF;
    cvk_error err;
    outcome unfused = run(ctx, &scene, shapes[0], &err);
    CHECK(unfused.ok, "40 x 40 in workgroups of 8, unfused: %s", err.message);
    scene.solver.fuse = CVK_FUSE_ON;
    static const shape small[] = {{8, 1, 1}, {8, 1, -1}};
    for (size_t k = 0; unfused.ok && k < sizeof small / sizeof small[0]; k++) {
        outcome fused = run(ctx, &scene, small[k], &err);
        const char* memory = small[k].fused_shared_memory > 0 ? "shared" : "global";
        CHECK(fused.ok, "40 x 40 fused in a workgroup of 8, %s memory: %s", memory, err.message);
        if (fused.ok)
            CHECK(fused.hash == unfused.hash, "40 x 40 fused in a workgroup of 8, %s memory: "
                  "hash %016llx, unfused %016llx; positions differ by up to %g m", memory,
                  (unsigned long long)fused.hash, (unsigned long long)unfused.hash,
                  harness_max_diff(fused.xyz, unfused.xyz, 3 * fused.count));
        printf("40 x 40, 3 x 4 iterations, fused in a workgroup of 8, %s memory: hash %016llx, "
               "unfused %016llx\n", memory, (unsigned long long)fused.hash,
               (unsigned long long)unfused.hash);
        free(fused.xyz);
    }
    free(unfused.xyz);
    /* 32 x 16 iterations: 102,400 steps of the sweeps' loop an invocation in a substep. On
       lavapipe that passes the limit, and the step (FRAMES frames in one call) must say so; a
       device without such a limit runs it whole. */
    scene.solver.outer_iterations = 32;
    scene.solver.inner_iterations = 16;
    bool lavapipe = strstr(cvk_context_get_info(ctx).device_name, "llvmpipe") != NULL;
    outcome many = run(ctx, &scene, small[1], &err);
    if (lavapipe) {
        char want[64];
        snprintf(want, sizeof want, "the fused sweeps were cut short by frame %d: ", FRAMES);
        CHECK(!many.ok && err.result == CVK_ERROR_DEVICE_LIMIT &&
              strncmp(err.message, want, strlen(want)) == 0,
              "40 x 40 fused in a workgroup of 8 at 32 x 16: expected \"%s...\" "
              "(CVK_ERROR_DEVICE_LIMIT), got %s", want, many.ok ? "success" : err.message);
        printf("40 x 40, 32 x 16 iterations, fused in a workgroup of 8: %s\n",
               many.ok ? "ran" : err.message);
    } else {
        CHECK(many.ok, "40 x 40 fused in a workgroup of 8 at 32 x 16: %s", err.message);
    }
    free(many.xyz);
}

/* The test in three parts, each its own meson test so they run side by side (argv[1]: solvers,
   contact or instances; none: all three): the sanitized run of the whole took over the 600 s
   limit alone on a 2-core VM. */
int main(int argc, char** argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0); /* each line as it comes: where a long run is, in a pipe */
    const char* part = argc > 1 ? argv[1] : "all";
    bool all = strcmp(part, "all") == 0;
    if (!all && strcmp(part, "solvers") != 0 && strcmp(part, "contact") != 0 && strcmp(part, "instances") != 0) {
        fprintf(stderr, "test_determinism: unknown part '%s' (expected solvers, contact or instances)\n", part);
        return 2;
    }
    cvk_context* ctx = harness_context();
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.substeps = 4;
    scene.solver.outer_iterations = 2;
    scene.solver.inner_iterations = 4;
    if (all || strcmp(part, "solvers") == 0) {
        check_solver_scenes(ctx, scene);
        check_small_workgroup(ctx, scene);
    }
    if (all || strcmp(part, "contact") == 0) {
        check_contact_scene(ctx, &scene);
        check_funnel_scene(ctx, &scene);
        check_between_scene(ctx, &scene);
        check_fused_after_scene(ctx, &scene);
        check_crowd_scene(ctx);
    }
    if (all || strcmp(part, "instances") == 0) {
        check_instances(ctx);
        check_instances_self(ctx);
    }
    return harness_finish(ctx);
}
