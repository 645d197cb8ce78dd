/* libFuzzer harness for what clothvk-sim --resume and clothvk-render --from read from disk: a
   bake's cache.json and its frame files (snapshots). The first byte of an input picks the
   target:
   - even: the rest is DIR/cache.json of a bake of a small scene whose frame_0000.snap is valid,
     resumed as --resume does (apps/bake.c: app_bake_resume, which checks the cache, finds the
     last frame, loads it and rewrites the cache);
   - odd: the rest is a snapshot loaded into that scene's simulation (cvk_sim_load_snapshot);
     with bit 1 set its CRC-32 is made right first, so that mutations reach past the checksum
     into the header's other checks and the state's sections (solver family, contact, tearing).
   One Vulkan context and simulation (lavapipe, validation off) serve the whole run: a load
   that fails changes nothing, and one that succeeds replaces the whole state. Besides the
   sanitizers, each input checks those contracts (sim.h, bake.h), and a breach aborts with what
   it was:
   - a refused snapshot leaves the simulation's state as it was (its saved bytes the same), and
     its message is one line;
   - a refused resume leaves the bake's folder as it was: the same three files, frame 0 and
     the scene's text the same bytes, cache.json the input's.
   With CLOTHVK_FUZZ_SEEDS=DIR, writes the seeds (that cache.json, and the snapshot with and
   without the CRC bit) into DIR and exits. Built and run by scripts/fuzz.sh. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include <clothvk.h>

#include "bake.h"

/* Self-contact and tearing: a snapshot holds every section. */
static const char scene_text[] =
    "{\"name\": \"fuzz\", \"dt\": 0.002, \"substeps\": 2,"
    " \"collision\": {\"self\": true},"
    " \"cloths\": [{\"grid\": [6, 5], \"size\": [0.3, 0.25], \"pins\": [[0, 0], [5, 0]],"
    " \"tearing\": {\"max_stretch\": 1.5}}]}";

static cvk_context* context;
static cvk_scene* scene;
static cvk_sim* sim;
static char folder[] = "/tmp/clothvk-fuzz-bake-XXXXXX";
static char cache_path[sizeof folder + 16];
static char scene_path[sizeof folder + 16]; /* the scene's text, which a bake copies */
static app_overrides no_overrides;
static app_bake_desc desc;
static unsigned char* snapshot; /* a valid frame 0 */
static uint64_t snapshot_size;
static unsigned char* frame_file; /* frame_0000.snap as the bake wrote it */
static size_t frame_size;
static unsigned char* state;      /* the simulation's state as last saved */
static unsigned char* scratch;    /* and as saved after a load, to compare */

static void fail(const char* what, const char* message)
{
    fprintf(stderr, "fuzz_bake: %s: %s\n", what, message);
    exit(1);
}

static bool write_file(const char* path, const void* data, size_t size)
{
    FILE* f = fopen(path, "wb");
    if (!f)
        return false;
    bool ok = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && ok;
}

/* A breach of a contract: the input that found it is kept by libFuzzer as a crash. */
static void require(bool ok, const char* what, const char* detail)
{
    if (ok)
        return;
    fprintf(stderr, "fuzz_bake: %s: %s\n", what, detail);
    abort();
}

/* The whole file, or NULL; its size in *size. */
static unsigned char* read_bytes(const char* path, size_t* size)
{
    FILE* f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char* data = NULL;
    long end = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    if (end >= 0 && fseek(f, 0, SEEK_SET) == 0 && (data = malloc((size_t)end + 1)) &&
        fread(data, 1, (size_t)end, f) != (size_t)end) {
        free(data);
        data = NULL;
    }
    fclose(f);
    *size = end >= 0 ? (size_t)end : 0;
    return data;
}

static bool same_file(const char* path, const void* data, size_t size)
{
    size_t got;
    unsigned char* bytes = read_bytes(path, &got);
    bool same = bytes && got == size && memcmp(bytes, data, size) == 0;
    free(bytes);
    return same;
}

static void save_state(unsigned char* into)
{
    cvk_error err;
    if (cvk_sim_save_snapshot(sim, into, snapshot_size, &err) != CVK_SUCCESS)
        fail("cvk_sim_save_snapshot", err.message);
}

static char* read_text(const char* path)
{
    FILE* f = fopen(path, "rb");
    if (!f)
        return NULL;
    char* text = calloc(1, 1 << 20);
    if (text)
        fread(text, 1, (1 << 20) - 1, f);
    fclose(f);
    return text;
}

/* A seed: the target byte, then the payload. */
static void write_seed(const char* dir, const char* name, unsigned char target, const void* data,
                       size_t size)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    unsigned char* seed = malloc(size + 1);
    if (!seed)
        fail(path, "out of memory");
    seed[0] = target;
    memcpy(seed + 1, data, size);
    if (!write_file(path, seed, size + 1))
        fail(path, "cannot write");
    free(seed);
}

/* The bake every cache.json input is read into: cache.json and a valid frame_0000.snap. */
static void make_bake(void)
{
    if (!mkdtemp(folder))
        fail(folder, "cannot make the folder");
    snprintf(cache_path, sizeof cache_path, "%s/cache.json", folder);
    snprintf(scene_path, sizeof scene_path, "%s/scene.json", folder);
    if (!write_file(scene_path, scene_text, strlen(scene_text)))
        fail(scene_path, "cannot write");
    desc = (app_bake_desc){.scene_path = scene_path, .overrides = &no_overrides,
                           .scene = cvk_scene_get_desc(scene),
                           .resolved = cvk_scene_get_json(scene), .frames = 4, .every = 1};
    app_bake bake;
    if (app_bake_start(&bake, "fuzz_bake", sim, folder, &desc) != 0 || !app_bake_frame(&bake, 0))
        fail(folder, "cannot bake frame 0");
    app_bake_free(&bake);
    desc.every = 0; /* as --resume without --every */
    desc.frames = 0;
    snapshot_size = cvk_sim_snapshot_size(sim);
    snapshot = malloc(snapshot_size);
    cvk_error err;
    if (!snapshot || cvk_sim_save_snapshot(sim, snapshot, snapshot_size, &err) != CVK_SUCCESS)
        fail("cvk_sim_save_snapshot", err.message);
    state = malloc(snapshot_size);
    scratch = malloc(snapshot_size);
    if (!state || !scratch)
        fail("the state's copies", "out of memory");
    memcpy(state, snapshot, snapshot_size);
    char path[sizeof folder + 32];
    snprintf(path, sizeof path, "%s/frame_0000.snap", folder);
    if (!(frame_file = read_bytes(path, &frame_size)))
        fail(path, "cannot read");
}

/* The folder holds scene.json, cache.json and frame_0000.snap, and no other file. */
static bool three_files(void)
{
    DIR* dir = opendir(folder);
    if (!dir)
        return false;
    int files = 0;
    bool known = true;
    struct dirent* entry;
    while ((entry = readdir(dir))) {
        if (strcmp(entry->d_name, ".") == 0 || strcmp(entry->d_name, "..") == 0)
            continue;
        files++;
        known = known && (strcmp(entry->d_name, "scene.json") == 0 ||
                          strcmp(entry->d_name, "cache.json") == 0 ||
                          strcmp(entry->d_name, "frame_0000.snap") == 0);
    }
    closedir(dir);
    return known && files == 3;
}

static void remove_bake(void)
{
    char path[sizeof folder + 32];
    snprintf(path, sizeof path, "%s/frame_0000.snap", folder);
    unlink(path);
    unlink(cache_path);
    unlink(scene_path);
    rmdir(folder);
}

int LLVMFuzzerInitialize(int* argc, char*** argv)
{
    (void)argc;
    (void)argv;
    cvk_error err;
    cvk_context_desc cd = cvk_default_context_desc();
    cd.validation = -1;
    if (cvk_context_create(&cd, &context, &err) != CVK_SUCCESS)
        fail("cvk_context_create", err.message);
    if (cvk_scene_parse(scene_text, "fuzz.json", NULL, 0, &scene, &err) != CVK_SUCCESS)
        fail("cvk_scene_parse", err.message);
    cvk_sim_desc sd = cvk_default_sim_desc();
    sd.scene = cvk_scene_get_desc(scene);
    sd.timing = -1;
    if (cvk_sim_create(context, &sd, &sim, &err) != CVK_SUCCESS)
        fail("cvk_sim_create", err.message);
    make_bake();
    atexit(remove_bake);
    const char* seeds = getenv("CLOTHVK_FUZZ_SEEDS");
    if (seeds) {
        char* cache = read_text(cache_path);
        if (!cache)
            fail(cache_path, "cannot read");
        write_seed(seeds, "cache.json", 0, cache, strlen(cache));
        write_seed(seeds, "snapshot", 1, snapshot, snapshot_size);
        write_seed(seeds, "snapshot-crc", 3, snapshot, snapshot_size);
        free(cache);
        exit(0);
    }
    return 0;
}

static void resume(const uint8_t* data, size_t size)
{
    if (!write_file(cache_path, data, size))
        fail(cache_path, "cannot write");
    app_bake bake;
    int status = app_bake_resume(&bake, "fuzz_bake", sim, folder, &desc);
    app_bake_free(&bake);
    char path[sizeof folder + 32];
    snprintf(path, sizeof path, "%s/frame_0000.snap", folder);
    require(same_file(path, frame_file, frame_size), "a resume", "changed frame_0000.snap");
    require(same_file(scene_path, scene_text, strlen(scene_text)), "a resume", "changed scene.json");
    require(three_files(), "a resume", "left other files than the bake's three");
    if (status != APP_EXIT_OK)
        require(same_file(cache_path, data, size), "a refused resume", "rewrote cache.json");
    save_state(state); /* a resume may have loaded frame 0, refused or not */
}

static void load(const uint8_t* data, size_t size, bool fix_crc)
{
    unsigned char* copy = malloc(size ? size : 1);
    if (!copy)
        return;
    memcpy(copy, data, size);
    if (fix_crc && size >= 72) { /* zlib's crc32 over every byte but 64-67 (snapshot.c) */
        uLong crc = crc32(0L, copy, 64);
        crc = crc32(crc, copy + 68, (uInt)(size - 68));
        uint32_t value = (uint32_t)crc;
        memcpy(copy + 64, &value, 4);
    }
    cvk_error err;
    cvk_result r = cvk_sim_load_snapshot(sim, copy, size, &err);
    free(copy);
    if (r == CVK_SUCCESS) {
        save_state(state);
        return;
    }
    const char* end = memchr(err.message, '\0', sizeof err.message);
    require(end && end > err.message && !memchr(err.message, '\n', (size_t)(end - err.message)),
            "a refused snapshot's message is not one line", err.message);
    require(err.result == r, "a refused snapshot", "error.result is not the result returned");
    save_state(scratch);
    require(memcmp(scratch, state, snapshot_size) == 0, "a refused snapshot changed the state",
            err.message);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size == 0)
        return 0;
    if (data[0] & 1)
        load(data + 1, size - 1, data[0] & 2);
    else
        resume(data + 1, size - 1);
    return 0;
}
