/* libFuzzer harness for the scene loader: JSON text, then optionally a line "#set" and one
   --set override per line, through cvk_scene_parse and, for a valid scene of grid cloths, the
   host side of simulation creation (the build with its size checks and the derived-quantity
   checks), where the counts the loader accepted become allocation sizes. No Vulkan: the device
   side multiplies the same checked counts. Built and run by scripts/fuzz.sh. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "topology/build.h"
#include "sim/sim_limits.h"

#define MAX_OVERRIDES 16
#define MAX_FUZZ_PARTICLES 20000u /* keeps one input to milliseconds */

static bool small_grids(const cvk_scene_desc* d)
{
    uint64_t total = 0;
    for (uint32_t c = 0; c < d->cloth_count; c++) {
        if (d->cloths[c].mesh)
            return false; /* a path the input names: not read here */
        total += (uint64_t)d->cloths[c].grid[0] * d->cloths[c].grid[1];
    }
    return total <= MAX_FUZZ_PARTICLES;
}

static void build_scene(const cvk_scene_desc* d)
{
    cvk_build build;
    cvk_error err;
    if (cvk_build_create_checked(d, NULL, NULL, &build, &err) != CVK_SUCCESS)
        return;
    cvk_check_derived(d, &build, d->dt, &err);
    cvk_build_destroy(&build);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    char* text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    const char* overrides[MAX_OVERRIDES];
    uint32_t count = 0;
    char* set = strstr(text, "\n#set\n");
    if (set) {
        *set = '\0';
        for (char* line = strtok(set + 6, "\n"); line && count < MAX_OVERRIDES;
             line = strtok(NULL, "\n"))
            overrides[count++] = line;
    }
    cvk_scene* scene = NULL;
    cvk_error err;
    if (cvk_scene_parse(text, "fuzz.json", overrides, count, &scene, &err) == CVK_SUCCESS) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        if (small_grids(d))
            build_scene(d);
        cvk_scene_destroy(scene);
    }
    free(text);
    return 0;
}
