/* Benchmark (meson test --benchmark, or run directly): the GPU time of one linear sweep over
   a 100x100 cloth (hanging.json) for rbgs, jacobi and chebyshev, from timestamp queries, and a
   straightforward single-threaded C loop doing the same Gauss-Seidel sweep over the same data
   (colour order, padded slot-major adjacency, vec4 positions). Prints both and their ratio.
   Not a test: it asserts nothing about time. */
#include <time.h>

#include "topology/build.h"
#include "harness.h"

enum { SWEEPS = 200, FRAMES = 12 };

static double now_us(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e6 + t.tv_nsec * 1e-3;
}

static int compare_doubles(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

typedef struct timing {
    double sweep_us; /* median over frames of solve-pass GPU time / sweeps per frame */
    double frame_ms; /* median GPU time per frame */
} timing;

static timing measure(cvk_context* ctx, const cvk_scene_desc* scene, uint32_t sweeps_per_frame)
{
    cvk_error err;
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, scene, &sim, &err), err);
    REQUIRE_OK(cvk_sim_step(sim, 2, &err), err); /* warm-up, not timed */
    double sweep[FRAMES], frame[FRAMES];
    for (int f = 0; f < FRAMES; f++) {
        REQUIRE_OK(cvk_sim_step(sim, 1, &err), err);
        cvk_sim_stats st;
        cvk_sim_get_timing(sim, &st);
        sweep[f] = st.passes[1].gpu_ms * 1e3 / sweeps_per_frame;
        frame[f] = st.gpu_ms_per_frame;
    }
    cvk_sim_destroy(sim);
    qsort(sweep, FRAMES, sizeof sweep[0], compare_doubles);
    qsort(frame, FRAMES, sizeof frame[0], compare_doubles);
    return (timing){sweep[FRAMES / 2], frame[FRAMES / 2]};
}

/* The same Gauss-Seidel sweep as pd_gauss_seidel.comp (not the first sweep of an outer
   iteration), single-threaded: best of several runs, in µs per full sweep. */
static double c_loop_sweep_us(const cvk_build* b)
{
    uint32_t n = b->particle_count, nf = b->free_count;
    float* u = calloc(4 * (size_t)n, sizeof(float));
    float* rhs = malloc(4 * (size_t)nf * sizeof(float));
    for (uint32_t p = 0; p < nf; p++) {
        float diag = 2.5f;
        for (uint32_t s = 0; s < b->degree[p]; s++)
            diag += b->adj_k[(size_t)s * nf + p];
        rhs[4 * p] = 1e-3f, rhs[4 * p + 1] = -2e-3f, rhs[4 * p + 2] = 3e-3f, rhs[4 * p + 3] = 1.0f / diag;
    }
    double best = 1e30;
    for (int run = 0; run < 5; run++) {
        double t0 = now_us();
        for (int sweep = 0; sweep < SWEEPS; sweep++)
            for (uint32_t p = 0; p < nf; p++) {
                float ax = 0, ay = 0, az = 0;
                for (uint32_t s = 0; s < b->max_degree; s++) {
                    size_t e = (size_t)s * nf + p;
                    const float* un = &u[4 * (size_t)b->adj_index[e]];
                    float k = b->adj_k[e];
                    ax += k * un[0], ay += k * un[1], az += k * un[2];
                }
                const float* r = &rhs[4 * (size_t)p];
                u[4 * p] = (r[0] + ax) * r[3], u[4 * p + 1] = (r[1] + ay) * r[3],
                u[4 * p + 2] = (r[2] + az) * r[3];
            }
        double t = (now_us() - t0) / SWEEPS;
        if (t < best)
            best = t;
    }
    volatile float sink = u[4 * (nf / 2)]; /* keep the loop's result alive */
    (void)sink;
    free(u);
    free(rhs);
    return best;
}

int main(void)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    char path[1024];
    snprintf(path, sizeof path, "%s/assets/scenes/hanging.json", root ? root : ".");
    const char* one_long_solve[] = {"substeps=1", "solver.outer_iterations=1",
                                    "solver.inner_iterations=200"};
    cvk_error err;
    cvk_scene* file;
    REQUIRE_OK(cvk_scene_load(path, one_long_solve, 3, &file, &err), err);
    cvk_scene_desc scene = *cvk_scene_get_desc(file);

    cvk_context* ctx;
    /* Timing without the validation layer, whatever the environment says. */
    cvk_context_desc ctx_desc = cvk_default_context_desc();
    ctx_desc.validation = -1;
    REQUIRE_OK(cvk_context_create(&ctx_desc, &ctx, &err), err);
    const char* lp = getenv("LP_NUM_THREADS");
    printf("device: %s%s%s\n", cvk_context_get_info(ctx).device_name, lp ? ", LP_NUM_THREADS=" : "",
           lp ? lp : "");
    double us[3];
    const cvk_linear_solver solvers[3] = {CVK_LINEAR_RBGS, CVK_LINEAR_JACOBI, CVK_LINEAR_CHEBYSHEV};
    for (int i = 0; i < 3; i++) {
        scene.solver.linear = solvers[i];
        us[i] = measure(ctx, &scene, SWEEPS).sweep_us;
        printf("%-9s GPU %7.1f us per sweep of 100x100 (median of %d frames of %d sweeps)\n",
               cvk_linear_solver_name(solvers[i]), us[i], FRAMES, SWEEPS);
    }
    cvk_build b;
    REQUIRE_OK(cvk_build_create(&scene, &b, &err), err);
    double c = c_loop_sweep_us(&b);
    printf("C loop    CPU %7.1f us per Gauss-Seidel sweep, one thread\n", c);
    printf("ratio rbgs GPU / C loop: %.2f\n", us[0] / c);
    printf("sweeps in 1/2/4/8 ms:");
    for (int i = 0; i < 3; i++)
        printf(" %s %d/%d/%d/%d%s", cvk_linear_solver_name(solvers[i]), (int)(1e3 / us[i]),
               (int)(2e3 / us[i]), (int)(4e3 / us[i]), (int)(8e3 / us[i]), i < 2 ? "," : "\n");
    cvk_build_destroy(&b);

    cvk_scene_destroy(file);
    REQUIRE_OK(cvk_scene_load(path, NULL, 0, &file, &err), err);
    timing hanging = measure(ctx, cvk_scene_get_desc(file), 8 * 16);
    printf("hanging.json: %.2f ms GPU per frame (8 substeps, 4x4 rbgs), %.1f us per sweep\n",
           hanging.frame_ms, hanging.sweep_us);
    cvk_scene_destroy(file);
    cvk_context_destroy(ctx);
    return 0;
}
