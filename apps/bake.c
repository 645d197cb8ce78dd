/* Baked caches (format in bake.h): cache.json, then one exact snapshot per K-th frame. */
#include "bake.h"

#include <errno.h>
#include <jansson.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define STR2(x) #x
#define STR(x) STR2(x)
#define CLOTHVK_VERSION_TEXT                                                                  \
    STR(CLOTHVK_VERSION_MAJOR) "." STR(CLOTHVK_VERSION_MINOR) "." STR(CLOTHVK_VERSION_PATCH)

/* A whole file into memory (NUL-terminated for text); errno set on failure. */
static bool read_file(const char* path, unsigned char** data, uint64_t* size)
{
    *data = NULL;
    *size = 0;
    FILE* f = fopen(path, "rb");
    if (!f)
        return false;
    size_t capacity = 1 << 16, used = 0;
    unsigned char* buf = malloc(capacity + 1);
    while (buf) {
        used += fread(buf + used, 1, capacity - used, f);
        if (used < capacity)
            break;
        unsigned char* grown = realloc(buf, 2 * capacity + 1);
        if (!grown) {
            free(buf);
            buf = NULL;
            errno = ENOMEM;
            break;
        }
        buf = grown;
        capacity *= 2;
    }
    bool ok = buf && !ferror(f);
    if (buf && ferror(f))
        errno = EIO;
    fclose(f);
    if (!ok) {
        free(buf);
        return false;
    }
    buf[used] = '\0';
    *data = buf;
    *size = used;
    return true;
}

/* Prepares the buffers every path needs and reads the scene file's text. */
static int init(app_bake* b, const char* tool, cvk_sim* sim, const char* folder,
                const app_bake_desc* desc)
{
    memset(b, 0, sizeof *b);
    b->tool = tool;
    b->sim = sim;
    b->folder = folder;
    b->size = cvk_sim_snapshot_size(sim);
    b->data = malloc(b->size);
    b->path = malloc(strlen(folder) + 32);
    if (!b->data || !b->path) {
        app_error(tool, "out of memory for a %llu-byte snapshot", (unsigned long long)b->size);
        return APP_EXIT_FAILURE;
    }
    uint64_t length;
    if (!read_file(desc->scene_path, (unsigned char**)&b->scene_text, &length)) {
        app_error(tool, "%s: cannot read: %s", desc->scene_path, strerror(errno));
        return APP_EXIT_BAD_INPUT;
    }
    return APP_EXIT_OK;
}

static const char* frame_path(app_bake* b, uint32_t number)
{
    sprintf(b->path, "%s/frame_%04u.snap", b->folder, number);
    return b->path;
}

static bool write_json(FILE* file, void* user)
{
    return json_dumpf(user, file, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(9)) ==
               0 && fputc('\n', file) != EOF;
}

/* A float as the shortest decimal that reads back as it: 0.002, not 0.00200000009. */
static double shortest(float v)
{
    char text[32];
    for (int digits = 1; digits < 9; digits++) {
        snprintf(text, sizeof text, "%.*g", digits, (double)v);
        if ((float)strtod(text, NULL) == v)
            return strtod(text, NULL);
    }
    return v;
}

static int write_cache(app_bake* b, const app_bake_desc* desc)
{
    json_t* overrides = json_array();
    for (uint32_t i = 0; i < desc->overrides->count; i++)
        json_array_append_new(overrides, json_string(desc->overrides->items[i]));
    json_t* root = json_pack(
        "{ss si ss ss ss so si si sf si si sI}", "format", APP_BAKE_FORMAT, "version",
        APP_BAKE_VERSION, "clothvk_version", CLOTHVK_VERSION_TEXT, "scene", b->scene_text,
        "scene_file", desc->scene_path, "overrides", overrides, "frames", (int)b->frames, "every",
        (int)b->every, "dt", shortest(desc->scene->dt), "substeps", (int)desc->scene->substeps,
        "particles", (int)cvk_sim_particle_count(b->sim), "snapshot_bytes", (json_int_t)b->size);
    char message[512];
    snprintf(b->path, strlen(b->folder) + 32, "%s/cache.json", b->folder);
    bool ok = root && app_write_atomic(b->path, write_json, root, message, sizeof message);
    json_decref(root);
    if (!ok) {
        app_error(b->tool, "%s", root ? message : "out of memory for cache.json");
        return APP_EXIT_FAILURE;
    }
    return APP_EXIT_OK;
}

int app_bake_start(app_bake* b, const char* tool, cvk_sim* sim, const char* folder,
                   const app_bake_desc* desc)
{
    int status = init(b, tool, sim, folder, desc);
    if (status != APP_EXIT_OK)
        return status;
    b->frames = desc->frames;
    b->every = desc->every ? desc->every : 1;
    if (!app_make_output_folder(tool, folder))
        return APP_EXIT_BAD_INPUT;
    return write_cache(b, desc);
}

/* The --set items of cache.json against this run's. */
static bool same_overrides(json_t* list, const app_overrides* o)
{
    if (!json_is_array(list) || json_array_size(list) != o->count)
        return false;
    for (uint32_t i = 0; i < o->count; i++) {
        const char* item = json_string_value(json_array_get(list, i));
        if (!item || strcmp(item, o->items[i]) != 0)
            return false;
    }
    return true;
}

/* cache.json's checks, in the order a user can act on. */
static int check_cache(app_bake* b, json_t* root, const app_bake_desc* desc)
{
    const char* format = json_string_value(json_object_get(root, "format"));
    json_int_t version = json_integer_value(json_object_get(root, "version"));
    const char* scene = json_string_value(json_object_get(root, "scene"));
    json_int_t frames = json_integer_value(json_object_get(root, "frames"));
    json_int_t every = json_integer_value(json_object_get(root, "every"));
    if (!format || strcmp(format, APP_BAKE_FORMAT) != 0) {
        app_error(b->tool, "%s/cache.json: not a clothvk bake (no \"format\": \"%s\")", b->folder,
                  APP_BAKE_FORMAT);
        return APP_EXIT_BAD_INPUT;
    }
    if (version != APP_BAKE_VERSION) {
        app_error(b->tool, "%s/cache.json: bake format version %lld; this clothvk reads version %d",
                  b->folder, (long long)version, APP_BAKE_VERSION);
        return APP_EXIT_BAD_INPUT;
    }
    if (!scene || !json_is_integer(json_object_get(root, "frames")) || frames < 0 ||
        frames > 100000000 || every < 1 || every > 100000000) {
        app_error(b->tool, "%s/cache.json: not a clothvk bake (\"scene\", \"frames\" or \"every\" "
                  "missing or out of range)", b->folder);
        return APP_EXIT_BAD_INPUT;
    }
    if (strcmp(scene, b->scene_text) != 0) {
        app_error(b->tool, "%s: baked from another scene (the scene text in its cache.json differs "
                  "from %s)", b->folder, desc->scene_path);
        return APP_EXIT_BAD_INPUT;
    }
    if (!same_overrides(json_object_get(root, "overrides"), desc->overrides)) {
        app_error(b->tool, "%s: baked with other --set items than given here (see its cache.json)",
                  b->folder);
        return APP_EXIT_BAD_INPUT;
    }
    if (desc->every && desc->every != (uint32_t)every) {
        app_error(b->tool, "--every %u: %s was baked with --every %lld", desc->every, b->folder,
                  (long long)every);
        return APP_EXIT_BAD_INPUT;
    }
    b->frames = (uint32_t)frames;
    b->every = (uint32_t)every;
    return APP_EXIT_OK;
}

int app_bake_open(app_bake* b, const char* tool, cvk_sim* sim, const char* folder,
                  const app_bake_desc* desc)
{
    int status = init(b, tool, sim, folder, desc);
    if (status != APP_EXIT_OK)
        return status;
    json_error_t jerr;
    snprintf(b->path, strlen(folder) + 32, "%s/cache.json", folder);
    struct stat st;
    if (stat(b->path, &st) != 0) {
        app_error(tool, "%s: no bake here (%s: %s)", folder, b->path, strerror(errno));
        return APP_EXIT_BAD_INPUT;
    }
    json_t* root = json_load_file(b->path, 0, &jerr);
    if (!root) {
        app_error(tool, "%s: not a clothvk bake (line %d: %s)", b->path, jerr.line, jerr.text);
        return APP_EXIT_BAD_INPUT;
    }
    status = check_cache(b, root, desc);
    json_decref(root);
    return status;
}

/* The number of the last frame file of an unbroken run from frame_0000 among those a bake of
   `frames` frames writes; -1 when frame_0000 is missing. */
static int64_t last_complete(app_bake* b, uint32_t frames)
{
    int64_t last = -1;
    struct stat st;
    for (uint64_t i = 0; i * b->every < frames || i == 0; i++) {
        if (stat(frame_path(b, (uint32_t)i), &st) != 0)
            break;
        last = (int64_t)i;
    }
    return last;
}

int app_bake_resume(app_bake* b, const char* tool, cvk_sim* sim, const char* folder,
                    const app_bake_desc* desc)
{
    int status = app_bake_open(b, tool, sim, folder, desc);
    if (status != APP_EXIT_OK)
        return status;
    if (desc->frames)
        b->frames = desc->frames;
    int64_t last = last_complete(b, b->frames);
    if (last < 0) {
        app_error(tool, "%s: no complete frame to resume from (%s missing)", folder,
                  frame_path(b, 0));
        return APP_EXIT_BAD_INPUT;
    }
    status = app_bake_load(b, (uint32_t)last * b->every);
    if (status != APP_EXIT_OK)
        return status;
    b->first = (uint32_t)last * b->every;
    return write_cache(b, desc);
}

static bool write_bytes(FILE* file, void* user)
{
    const app_bake* b = user;
    return fwrite(b->data, 1, b->size, file) == b->size;
}

bool app_bake_frame(app_bake* b, uint32_t frame)
{
    if (frame % b->every != 0 || (frame == b->first && b->first > 0))
        return true;
    cvk_error err;
    if (cvk_sim_save_snapshot(b->sim, b->data, b->size, &err) != CVK_SUCCESS) {
        app_error(b->tool, "%s", err.message);
        return false;
    }
    char message[512];
    if (!app_write_atomic(frame_path(b, frame / b->every), write_bytes, b, message,
                          sizeof message)) {
        app_error(b->tool, "%s", message);
        return false;
    }
    b->written++;
    return true;
}

static bool holds(const app_bake* b, uint32_t frame)
{
    if (frame % b->every == 0 && frame < b->frames)
        return true;
    if (b->frames == 0)
        app_error(b->tool, "%s: frame %u is not in the bake (it holds none)", b->folder, frame);
    else
        app_error(b->tool, "%s: frame %u is not in the bake (it holds frames 0 to %u, every %u)",
                  b->folder, frame, (b->frames - 1) / b->every * b->every, b->every);
    return false;
}

int app_bake_check_frames(app_bake* b, uint32_t first, uint32_t last, uint32_t step)
{
    struct stat st;
    for (uint64_t f = first; f <= last; f += step) {
        if (!holds(b, (uint32_t)f))
            return APP_EXIT_BAD_INPUT;
        const char* path = frame_path(b, (uint32_t)f / b->every);
        if (stat(path, &st) != 0) {
            app_error(b->tool, "%s: frame %llu is missing (%s: %s)", b->folder,
                      (unsigned long long)f, path, strerror(errno));
            return APP_EXIT_BAD_INPUT;
        }
    }
    return APP_EXIT_OK;
}

int app_bake_load(app_bake* b, uint32_t frame)
{
    if (!holds(b, frame))
        return APP_EXIT_BAD_INPUT;
    unsigned char* data;
    uint64_t size;
    const char* path = frame_path(b, frame / b->every);
    if (!read_file(path, &data, &size)) {
        app_error(b->tool, "%s: cannot read: %s", path, strerror(errno));
        return APP_EXIT_BAD_INPUT;
    }
    cvk_error err;
    cvk_result r = cvk_sim_load_snapshot(b->sim, data, size, &err);
    free(data);
    if (r != CVK_SUCCESS) {
        app_error(b->tool, "%s: %s", path, err.message);
        return r == CVK_ERROR_OUT_OF_MEMORY || r == CVK_ERROR_VULKAN ? APP_EXIT_FAILURE
                                                                    : APP_EXIT_BAD_INPUT;
    }
    return APP_EXIT_OK;
}

void app_bake_free(app_bake* b)
{
    free(b->scene_text);
    free(b->data);
    free(b->path);
    memset(b, 0, sizeof *b);
}
