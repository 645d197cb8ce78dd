/* Baked caches (format in bake.h): cache.json, then one exact snapshot per K-th frame. */
#include "bake.h"

#include <dirent.h>
#include <errno.h>
#include <jansson.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

static uint64_t fnv1a(uint64_t h, const void* data, size_t size)
{
    const unsigned char* p = data;
    for (size_t i = 0; i < size; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

/* The run a bake holds: FNV-1a over the resolved scene, dt, substeps and K. Two runs with the
   same hash write the same frames. */
static void run_hash(const app_bake_desc* desc, const char* resolved, uint32_t every, char out[17])
{
    uint64_t h = fnv1a(0xcbf29ce484222325ull, resolved, strlen(resolved) + 1);
    h = fnv1a(h, &desc->scene->dt, sizeof desc->scene->dt);
    h = fnv1a(h, &desc->scene->substeps, sizeof desc->scene->substeps);
    h = fnv1a(h, &every, sizeof every);
    snprintf(out, 17, "%016llx", (unsigned long long)h);
}

static int write_cache(app_bake* b, const app_bake_desc* desc)
{
    char run[17];
    run_hash(desc, desc->resolved, b->every, run);
    json_t* overrides = json_array();
    for (uint32_t i = 0; i < desc->overrides->count; i++)
        json_array_append_new(overrides, json_string(desc->overrides->items[i]));
    json_t* root = json_pack(
        "{ss si ss ss ss so ss ss si si sf si si sI}", "format", APP_BAKE_FORMAT, "version",
        APP_BAKE_VERSION, "clothvk_version", CLOTHVK_VERSION_TEXT, "scene", b->scene_text,
        "scene_file", desc->scene_path, "overrides", overrides, "resolved", desc->resolved, "run",
        run, "frames", (int)b->frames, "every",
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

/* "frame_0007.snap", "frame_12345.snap": a name frame_path writes, exactly. */
static bool is_frame_name(const char* name)
{
    char* end;
    if (strncmp(name, "frame_", 6) != 0 || name[6] < '0' || name[6] > '9')
        return false;
    errno = 0;
    unsigned long number = strtoul(name + 6, &end, 10);
    if (errno || number > UINT32_MAX || strcmp(end, ".snap") != 0)
        return false;
    char again[32];
    snprintf(again, sizeof again, "frame_%04u.snap", (unsigned)number);
    return strcmp(again, name) == 0;
}

/* The names a bake writes in its folder (cache.json and frame files) must be regular files:
   anything else (a link, a folder) is refused before anything is written, naming the path.
   With `remove`, the frame files are then deleted: a new bake owns the folder, and a frame
   left by an earlier bake would be taken for one of this bake's by a resume. */
static int own_folder(app_bake* b, bool remove)
{
    DIR* dir = opendir(b->folder);
    if (!dir)
        return APP_EXIT_OK; /* no folder yet (app_make_output_folder names other problems) */
    size_t length = strlen(b->folder) + 2;
    int status = APP_EXIT_OK;
    for (int pass = 0; pass < (remove ? 2 : 1) && status == APP_EXIT_OK; pass++) {
        rewinddir(dir);
        struct dirent* entry;
        while (status == APP_EXIT_OK && (entry = readdir(dir))) {
            bool frame = is_frame_name(entry->d_name);
            if (!frame && strcmp(entry->d_name, "cache.json") != 0)
                continue;
            char* path = malloc(length + strlen(entry->d_name));
            if (!path) {
                app_error(b->tool, "out of memory");
                status = APP_EXIT_FAILURE;
                break;
            }
            sprintf(path, "%s/%s", b->folder, entry->d_name);
            char message[768];
            if (pass == 0 && !app_output_replaceable(path, message, sizeof message)) {
                app_error(b->tool, "%s", message);
                status = APP_EXIT_BAD_INPUT;
            } else if (pass == 1 && frame && unlink(path) != 0 && errno != ENOENT) {
                app_error(b->tool, "%s: cannot remove the earlier bake's frame: %s", path,
                          strerror(errno));
                status = APP_EXIT_FAILURE;
            }
            free(path);
        }
    }
    closedir(dir);
    return status;
}

int app_bake_start(app_bake* b, const char* tool, cvk_sim* sim, const char* folder,
                   const app_bake_desc* desc)
{
    int status = init(b, tool, sim, folder, desc);
    if (status != APP_EXIT_OK)
        return status;
    b->frames = desc->frames;
    b->every = desc->every ? desc->every : 1;
    status = own_folder(b, false);
    if (status != APP_EXIT_OK)
        return status;
    if (!app_make_output_folder(tool, folder))
        return APP_EXIT_BAD_INPUT;
    status = own_folder(b, true);
    return status == APP_EXIT_OK ? write_cache(b, desc) : status;
}

/* A JSON value for a message: numbers as the shortest decimal that reads back as them,
   cut at about 60 characters. */
static void show_value(const json_t* v, char* out, size_t size)
{
    if (!v) {
        snprintf(out, size, "not set");
        return;
    }
    if (json_is_number(v)) {
        double x = json_number_value(v);
        for (int digits = 1; digits <= 17; digits++) {
            snprintf(out, size, "%.*g", digits, x);
            if (strtod(out, NULL) == x)
                return;
        }
        return;
    }
    if (json_is_array(v) || json_is_object(v)) { /* elements shortest too, keys in order */
        size_t used = (size_t)snprintf(out, size, "%c", json_is_array(v) ? '[' : '{');
        size_t n = json_is_array(v) ? json_array_size(v) : json_object_size(v);
        void* it = json_is_object(v) ? json_object_iter((json_t*)v) : NULL;
        for (size_t i = 0; i < n && used + 4 < size; i++) {
            char item[96];
            show_value(json_is_array(v) ? json_array_get(v, i) : json_object_iter_value(it), item,
                       sizeof item);
            if (json_is_object(v))
                used += (size_t)snprintf(out + used, size - used, "%s\"%s\":%s", i ? "," : "",
                                         json_object_iter_key(it), item);
            else
                used += (size_t)snprintf(out + used, size - used, "%s%s", i ? "," : "", item);
            it = it ? json_object_iter_next((json_t*)v, it) : NULL;
        }
        if (used + 2 < size)
            snprintf(out + used, size - used, "%c", json_is_array(v) ? ']' : '}');
    } else {
        char* text = json_dumps(v, JSON_ENCODE_ANY);
        snprintf(out, size, "%s", text ? text : "?");
        free(text);
    }
    if (strlen(out) > 60)
        strcpy(out + 57, "...");
}

/* The differences between the bake's resolved scene and this run's. */
typedef struct scene_diff {
    char text[1024]; /* the first three, "path is A in the bake, B here; ..." */
    uint32_t count;
} scene_diff;

static void note_difference(scene_diff* d, const char* path, const json_t* baked,
                            const json_t* here)
{
    if (d->count++ >= 3)
        return;
    char a[80], b[80];
    show_value(baked, a, sizeof a);
    show_value(here, b, sizeof b);
    size_t used = strlen(d->text);
    snprintf(d->text + used, sizeof d->text - used, "%s%s is %s in the bake, %s here",
             used ? "; " : "", path, a, b);
}

/* Walks both trees; a key path is the one --set takes (cloths.0.grid). */
static void compare_values(scene_diff* d, const char* path, const json_t* baked,
                           const json_t* here)
{
    char sub[512];
    if (json_is_object(baked) && json_is_object(here)) {
        const char* key;
        json_t* value;
        json_object_foreach((json_t*)baked, key, value) {
            snprintf(sub, sizeof sub, "%s%s%s", path, *path ? "." : "", key);
            compare_values(d, sub, value, json_object_get(here, key));
        }
        json_object_foreach((json_t*)here, key, value) {
            snprintf(sub, sizeof sub, "%s%s%s", path, *path ? "." : "", key);
            if (!json_object_get(baked, key))
                note_difference(d, sub, NULL, value);
        }
    } else if (json_is_array(baked) && json_is_array(here)) {
        size_t n = json_array_size(baked) > json_array_size(here) ? json_array_size(baked)
                                                                 : json_array_size(here);
        for (size_t i = 0; i < n; i++) {
            snprintf(sub, sizeof sub, "%s.%zu", path, i);
            compare_values(d, sub, json_array_get(baked, i), json_array_get(here, i));
        }
    } else if (!baked || !here || !json_equal((json_t*)baked, (json_t*)here)) {
        note_difference(d, path, baked, here);
    }
}

/* The keys that change only how a scene is drawn, never its frames: the render block and
   the colours and materials of cloths and colliders. A bake is drawn with this run's. */
static void drop_render_keys(json_t* scene)
{
    json_object_del(scene, "render");
    const char* lists[] = {"cloths", "colliders"};
    for (size_t l = 0; l < sizeof lists / sizeof lists[0]; l++) {
        json_t* list = json_object_get(scene, lists[l]);
        for (size_t i = 0; i < json_array_size(list); i++) {
            json_t* item = json_array_get(list, i);
            if (json_is_object(item)) {
                json_object_del(item, "color");
                json_object_del(item, "material");
            }
        }
    }
}

/* The resolved scene in cache.json against this run's (cvk_scene_get_json), but for the keys
   that only draw it: false, with the differing key paths and both values printed, when they
   differ. */
static bool same_scene(app_bake* b, const char* baked, const char* here)
{
    if (strcmp(baked, here) == 0)
        return true;
    json_t* a = json_loads(baked, 0, NULL);
    json_t* c = json_loads(here, 0, NULL);
    scene_diff d = {.count = 0};
    if (json_is_object(a) && json_is_object(c)) {
        drop_render_keys(a);
        drop_render_keys(c);
        compare_values(&d, "", a, c);
        if (d.count == 0) {
            json_decref(a);
            json_decref(c);
            return true;
        }
    }
    json_decref(a);
    json_decref(c);
    if (!a || !c)
        app_error(b->tool, "%s: baked from another scene (its cache.json's \"resolved\" is not "
                  "JSON)", b->folder);
    else if (d.count > 3)
        app_error(b->tool, "%s: baked from another scene: %s; and %u more differences", b->folder,
                  d.text, d.count - 3);
    else
        app_error(b->tool, "%s: baked from another scene: %s", b->folder,
                  d.count ? d.text : "the same values written differently");
    return false;
}

/* cache.json's checks, in the order a user can act on. */
static int check_cache(app_bake* b, json_t* root, const app_bake_desc* desc)
{
    const char* format = json_string_value(json_object_get(root, "format"));
    json_int_t version = json_integer_value(json_object_get(root, "version"));
    const char* resolved = json_string_value(json_object_get(root, "resolved"));
    const char* run = json_string_value(json_object_get(root, "run"));
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
    if (!resolved || !run || !json_is_integer(json_object_get(root, "frames")) || frames < 0 ||
        frames > 100000000 || every < 1 || every > 100000000) {
        app_error(b->tool, "%s/cache.json: not a clothvk bake (\"resolved\", \"run\", \"frames\" "
                  "or \"every\" missing or out of range)", b->folder);
        return APP_EXIT_BAD_INPUT;
    }
    if (!same_scene(b, resolved, desc->resolved))
        return APP_EXIT_BAD_INPUT;
    if (desc->every && desc->every != (uint32_t)every) {
        app_error(b->tool, "--every %u: %s was baked with --every %lld", desc->every, b->folder,
                  (long long)every);
        return APP_EXIT_BAD_INPUT;
    }
    char here[17]; /* the bake's scene text (this run's may draw it otherwise) */
    run_hash(desc, resolved, (uint32_t)every, here);
    if (strcmp(run, here) != 0) { /* the same scene text: a default dt or substeps changed */
        app_error(b->tool, "%s: baked as run %s (dt %g s, %lld substeps); this clothvk makes run "
                  "%s of the scene (dt %g s, %u substeps)", b->folder, run,
                  json_number_value(json_object_get(root, "dt")),
                  json_integer_value(json_object_get(root, "substeps")), here,
                  shortest(desc->scene->dt), desc->scene->substeps);
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
   `frames` frames writes (i*every <= frames); -1 when frame_0000 is missing. */
static int64_t last_complete(app_bake* b, uint32_t frames)
{
    int64_t last = -1;
    struct stat st;
    for (uint64_t i = 0; i * b->every <= frames; i++) {
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
    if (status == APP_EXIT_OK)
        status = own_folder(b, false);
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
    b->first = (uint32_t)last * b->every;
    status = app_bake_load(b, b->first);
    if (status != APP_EXIT_OK)
        return status;
    cvk_sim_stats st;
    cvk_error err;
    if (cvk_sim_get_stats(sim, &st, &err) != CVK_SUCCESS) {
        app_error(tool, "%s", err.message);
        return APP_EXIT_FAILURE;
    }
    if (st.frames != b->first) { /* the file's header against its place in the bake */
        app_error(tool, "%s: holds the state after %llu frames, not %u: not a frame of this bake",
                  frame_path(b, (uint32_t)last), (unsigned long long)st.frames, b->first);
        return APP_EXIT_BAD_INPUT;
    }
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

uint32_t app_bake_last_frame(const app_bake* b)
{
    return b->frames / b->every * b->every;
}

static bool holds(const app_bake* b, uint32_t frame)
{
    if (frame % b->every == 0 && frame <= b->frames)
        return true;
    app_error(b->tool, "%s: frame %u is not in the bake (it holds frames 0 to %u, every %u)",
              b->folder, frame, app_bake_last_frame(b), b->every);
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
