/* The memory estimate (lib/sim/memory.c) against what the library really allocates, and the
   refusal of a scene that does not fit:
   - for PD with 4 and 12 springs per particle, self-contact and implicit Euler, the estimate
     of device memory is at least what the context holds after creating the simulation and at
     most twice that;
   - under an address-space limit (RLIMIT_AS) 256 MiB above the process's size, a 2000 x 2000
     grid is refused before anything is built: CVK_ERROR_OUT_OF_MEMORY and the sentence with the
     figure and the limit; a small grid under the same limit is created. */
#include <string.h>
#include <sys/resource.h>

#include "harness.h"
#include "sim/memory.h"

typedef struct config {
    const char* name;
    float shear, bend;
    bool self;
    cvk_method method;
    uint32_t degree;
} config;

static cvk_scene_desc grid_scene(cvk_cloth_desc* cloth, const config* c, uint32_t n)
{
    *cloth = cvk_default_cloth_desc();
    cloth->grid[0] = cloth->grid[1] = n;
    cloth->stiffness.shear = c->shear;
    cloth->stiffness.bend = c->bend;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloth;
    scene.cloth_count = 1;
    scene.collision.self = c->self;
    scene.solver.method = c->method;
    if (c->method == CVK_METHOD_IMPLICIT)
        scene.solver.linear = CVK_LINEAR_CG;
    return scene;
}

static void test_estimate(cvk_context* ctx, const config* c)
{
    cvk_cloth_desc cloth;
    cvk_scene_desc scene = grid_scene(&cloth, c, 100);
    uint64_t before = cvk_context_get_info(ctx).device_bytes;
    cvk_error err;
    cvk_sim* sim = NULL;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    uint64_t held = cvk_context_get_info(ctx).device_bytes - before;
    cvk_memory_estimate e = cvk_memory_estimate_for(&scene, 10000, c->degree);
    CHECK(e.device_bytes >= held && e.device_bytes <= 2 * held,
          "%s: estimated %llu device bytes for 10000 particles, the simulation holds %llu",
          c->name, (unsigned long long)e.device_bytes, (unsigned long long)held);
    cvk_sim_destroy(sim);
    uint64_t after = cvk_context_get_info(ctx).device_bytes;
    CHECK(after == before, "%s: %llu device bytes still counted after destroying",
          c->name, (unsigned long long)(after - before));
}

static uint64_t vm_size(void)
{
    FILE* f = fopen("/proc/self/status", "r");
    char line[256];
    unsigned long long kb = 0;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "VmSize: %llu", &kb) == 1)
            break;
    if (f)
        fclose(f);
    return (uint64_t)kb * 1024u;
}

static void test_refusal(cvk_context* ctx)
{
    struct rlimit saved;
    getrlimit(RLIMIT_AS, &saved);
    struct rlimit tight = saved;
    tight.rlim_cur = vm_size() + (256u << 20);
    if (setrlimit(RLIMIT_AS, &tight) != 0) {
        CHECK(false, "setrlimit(RLIMIT_AS) failed");
        return;
    }
    config c = {"struct", 0.0f, 0.0f, false, CVK_METHOD_PD, 4};
    cvk_cloth_desc cloth;
    cvk_scene_desc scene = grid_scene(&cloth, &c, 2000);
    cvk_error err = {.message = ""};
    cvk_sim* sim = NULL;
    cvk_result r = harness_sim_create(ctx, &scene, &sim, &err);
    /* The sentence: the estimate's figure (checked against real allocations above), the
       device's memory counted with the host's where the device is the CPU, and what is free
       under the limit: the 256 MiB above the process's size, less what it grew since. */
    cvk_memory_estimate need = cvk_memory_estimate_for(&scene, 4000000, c.degree);
    const double gib = (double)(1u << 30);
    char on_cpu[256], on_gpu[256];
    snprintf(on_cpu, sizeof on_cpu, "cloths.0.grid: 4000000 particles need about %.2f GiB of host "
             "memory (the device's memory included: it is the host's); ",
             (double)(need.host_bytes + need.device_bytes) / gib);
    snprintf(on_gpu, sizeof on_gpu, "cloths.0.grid: 4000000 particles need about %.2f GiB of host "
             "memory; ", (double)need.host_bytes / gib);
    const char* start = strncmp(err.message, on_cpu, strlen(on_cpu)) == 0 ? on_cpu : on_gpu;
    double free_gib = -1.0;
    char rest[160] = "";
    bool parsed = strncmp(err.message, start, strlen(start)) == 0 &&
                  sscanf(err.message + strlen(start), "%lf%159[^\n]", &free_gib, rest) == 2;
    CHECK(r == CVK_ERROR_OUT_OF_MEMORY && sim == NULL && parsed && free_gib > 0.0 &&
              free_gib <= 0.26 &&
              strcmp(rest, " GiB is free (bound by the address-space limit (RLIMIT_AS))") == 0,
          "a 2000 x 2000 grid under a tight RLIMIT_AS: %s, \"%s\", expected it to start \"%s\"",
          cvk_result_name(r), err.message, start);
    scene = grid_scene(&cloth, &c, 20);
    r = harness_sim_create(ctx, &scene, &sim, &err);
    CHECK(r == CVK_SUCCESS, "a 20 x 20 grid under the same limit: %s, %s", cvk_result_name(r),
          err.message);
    cvk_sim_destroy(sim);
    setrlimit(RLIMIT_AS, &saved);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    const config configs[] = {
        {"pd, structural springs", 0.0f, 0.0f, false, CVK_METHOD_PD, 4},
        {"pd, shear and bend", 1e5f, 100.0f, false, CVK_METHOD_PD, 12},
        {"pd, self-contact", 1e5f, 100.0f, true, CVK_METHOD_PD, 12},
        {"implicit", 1e5f, 100.0f, false, CVK_METHOD_IMPLICIT, 12},
    };
    for (size_t i = 0; i < sizeof configs / sizeof configs[0]; i++)
        test_estimate(ctx, &configs[i]);
    /* AddressSanitizer reserves terabytes of address space: an RLIMIT_AS test cannot run. */
    if (!getenv("ASAN_OPTIONS"))
        test_refusal(ctx);
    return harness_finish(ctx);
}
