/* libFuzzer harness for the scene loader: JSON text, then optionally a line "#set" and one
   --set override per line, through cvk_scene_parse and, for a valid scene of grid cloths, the
   host side of simulation creation (the build with its size checks and the derived-quantity
   checks), where the counts the loader accepted become allocation sizes. No Vulkan: the device
   side multiplies the same checked counts. Besides the sanitizers, each input checks the
   loader's contract (docs/library.md), and a breach aborts with what it was:
   - a refusal leaves no scene and one line that starts with the source name;
   - an accepted scene's canonical text (cvk_scene_get_json) is accepted again, without the
     overrides it already holds, and gives the same text;
   - the build's refusals are one line too.
   Built and run by scripts/fuzz.sh. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "topology/build.h"
#include "sim/sim_limits.h"

#define MAX_OVERRIDES 16
#define MAX_FUZZ_PARTICLES 20000u /* keeps one input to milliseconds */

/* A breach of the contract: the input that found it is kept by libFuzzer as a crash. */
static void require(bool ok, const char* what, const char* detail)
{
    if (ok)
        return;
    fprintf(stderr, "fuzz_scene: %s: %s\n", what, detail ? detail : "(none)");
    abort();
}

/* One line, ended within the message's buffer. */
static bool one_line(const cvk_error* err)
{
    const char* end = memchr(err->message, '\0', sizeof err->message);
    return end && end > err->message && !memchr(err->message, '\n', (size_t)(end - err->message));
}

static void require_refusal(cvk_result r, const cvk_error* err, const char* what)
{
    require(r != CVK_SUCCESS && err->result == r, what, "the result and error.result differ");
    require(one_line(err), what, "the message is not one line");
}

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
    cvk_result r = cvk_build_create_checked(d, NULL, NULL, &build, &err);
    if (r != CVK_SUCCESS) {
        require_refusal(r, &err, "cvk_build_create_checked");
        return;
    }
    r = cvk_check_derived(d, &build, d->dt, &err);
    if (r != CVK_SUCCESS)
        require_refusal(r, &err, "cvk_check_derived");
    cvk_build_destroy(&build);
}

/* The canonical text of an accepted scene is a scene, and its own canonical text. */
static void reparse(const cvk_scene* scene)
{
    const char* json = cvk_scene_get_json(scene);
    require(json != NULL, "cvk_scene_get_json", "NULL for a scene");
    cvk_scene* again = NULL;
    cvk_error err;
    if (cvk_scene_parse(json, "fuzz.json", NULL, 0, &again, &err) != CVK_SUCCESS)
        require(false, "the canonical text refused", err.message);
    require(strcmp(json, cvk_scene_get_json(again)) == 0, "the canonical text read again",
            cvk_scene_get_json(again));
    cvk_scene_destroy(again);
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
    cvk_result r = cvk_scene_parse(text, "fuzz.json", overrides, count, &scene, &err);
    if (r != CVK_SUCCESS) {
        require(scene == NULL, "cvk_scene_parse", "a refusal left a scene");
        require_refusal(r, &err, "cvk_scene_parse");
        require(strncmp(err.message, "fuzz.json", 9) == 0, "the message does not name the source",
                err.message);
    } else {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        reparse(scene);
        if (small_grids(d))
            build_scene(d);
        cvk_scene_destroy(scene);
    }
    free(text);
    return 0;
}
