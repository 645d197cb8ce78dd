/* Wedges: the variants (axes and explicit combinations), their checks, and running them one by
   one or several at a time. The table and the contact sheet are wedge_gather.c's. */
#include "wedge.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* A variant that is still running this long after its own limit has hung inside a frame (the
   limit is checked between frames): --jobs kills it. */
#define KILL_GRACE_S 30

bool app_wedge_requested(const app_wedge_options* o)
{
    return o->axis_count || o->file || o->limit || o->count || o->index_set || o->jobs_set ||
           o->time_limit_s || o->preview || o->bake;
}

int app_wedge_add_axis(app_wedge_options* o, const char* tool, const char* item)
{
    const char** grown = realloc(o->axes, (o->axis_count + 1) * sizeof *grown);
    if (!grown) {
        app_error(tool, "out of memory");
        return APP_EXIT_FAILURE;
    }
    grown[o->axis_count++] = item;
    o->axes = grown;
    return APP_EXIT_OK;
}

void app_wedge_options_free(app_wedge_options* o)
{
    free(o->axes);
    o->axes = NULL;
    o->axis_count = 0;
}

/* ---- reading the axes and the file ------------------------------------------------------ */

/* The values of "key=v1,v2,...": split at the commas outside brackets, braces and strings, so
   that a value may be any JSON ([8,8], {"a":1}, "a,b"). Appends json strings to `values`. */
static int split_values(const char* tool, const char* item, const char* text, json_t* values)
{
    if (!*text) {
        app_error(tool, "--wedge %s: no values (expected key.path=v1,v2,...)", item);
        return APP_EXIT_BAD_INPUT;
    }
    int depth = 0;
    bool in_string = false;
    const char* start = text;
    for (const char* c = text;; c++) {
        if (in_string && *c == '\\' && c[1]) {
            c++;
            continue;
        }
        if (*c == '"')
            in_string = !in_string;
        else if (!in_string && (*c == '[' || *c == '{'))
            depth++;
        else if (!in_string && (*c == ']' || *c == '}'))
            depth--;
        if (*c && (*c != ',' || depth > 0 || in_string))
            continue;
        if (c == start) {
            app_error(tool, "--wedge %s: value %zu is empty", item, json_array_size(values) + 1);
            return APP_EXIT_BAD_INPUT;
        }
        json_array_append_new(values, json_stringn(start, (size_t)(c - start)));
        if (!*c)
            return APP_EXIT_OK;
        start = c + 1;
    }
}

/* Whether `key` is in the array of strings. */
static bool has_key(const json_t* keys, const char* key)
{
    size_t i;
    json_t* k;
    json_array_foreach(keys, i, k)
        if (!strcmp(json_string_value(k), key))
            return true;
    return false;
}

/* One --wedge item into axes ([{"key": ..., "values": [...]}, ...]) and keys. */
static int read_axis(const char* tool, const char* item, json_t* axes, json_t* keys,
                     const json_t* file_keys, const char* file)
{
    const char* equals = strchr(item, '=');
    if (!equals || equals == item) {
        app_error(tool, "--wedge %s: expected key.path=v1,v2,...", item);
        return APP_EXIT_BAD_INPUT;
    }
    json_t* key = json_stringn(item, (size_t)(equals - item));
    if (has_key(file_keys, json_string_value(key))) {
        app_error(tool, "--wedge %s: %s is also varied in --wedges %s", item,
                  json_string_value(key), file);
        json_decref(key);
        return APP_EXIT_BAD_INPUT;
    }
    if (has_key(keys, json_string_value(key))) {
        app_error(tool, "--wedge %s: %s is varied twice", item, json_string_value(key));
        json_decref(key);
        return APP_EXIT_BAD_INPUT;
    }
    json_t* values = json_array();
    int status = split_values(tool, item, equals + 1, values);
    if (status == APP_EXIT_OK) {
        json_array_append(keys, key);
        json_array_append_new(axes, json_pack("{sOsO}", "key", key, "values", values));
    }
    json_decref(key);
    json_decref(values);
    return status;
}

/* A value of the file as --set takes it: compact JSON, a number with the fewest digits that
   read back to it (0.1, not 0.10000000000000001). */
static char* value_text(const json_t* value)
{
    if (!json_is_real(value))
        return json_dumps(value, JSON_COMPACT | JSON_ENCODE_ANY);
    char text[64];
    double v = json_real_value(value);
    for (int digits = 1; digits <= 17; digits++) {
        snprintf(text, sizeof text, "%.*g", digits, v);
        if (strtod(text, NULL) == v)
            break;
    }
    if (!strpbrk(text, ".eEni"))
        strcat(text, ".0");
    return strdup(text);
}

/* --wedges FILE: a list of objects key.path -> value; each value kept as compact JSON text. */
static int read_file(const char* tool, const char* path, json_t* combos, json_t* keys)
{
    json_error_t jerr;
    json_t* root = json_load_file(path, JSON_REJECT_DUPLICATES, &jerr);
    if (!root) {
        if (jerr.line < 0)
            app_error(tool, "--wedges %s: %s", path, jerr.text);
        else
            app_error(tool, "--wedges %s: not JSON: %s (line %d)", path, jerr.text, jerr.line);
        return APP_EXIT_BAD_INPUT;
    }
    int status = APP_EXIT_OK;
    if (!json_is_array(root) || json_array_size(root) == 0) {
        app_error(tool, "--wedges %s: expected a list of one or more objects (key.path -> value)",
                  path);
        status = APP_EXIT_BAD_INPUT;
    }
    size_t i;
    json_t* entry;
    json_array_foreach(root, i, entry) {
        if (status != APP_EXIT_OK)
            break;
        if (!json_is_object(entry)) {
            app_error(tool, "--wedges %s: entry %zu: expected an object (key.path -> value)",
                      path, i);
            status = APP_EXIT_BAD_INPUT;
            break;
        }
        json_t* combo = json_object();
        const char* key;
        json_t* value;
        json_object_foreach(entry, key, value) {
            char* text = value_text(value);
            json_object_set_new(combo, key, json_string(text ? text : ""));
            free(text);
            if (!has_key(keys, key))
                json_array_append_new(keys, json_string(key));
        }
        json_array_append_new(combos, combo);
    }
    json_decref(root);
    return status;
}

/* ---- checking every variant as --set would ---------------------------------------------- */

/* The library's message for an override names it "(from --set)" or "--set ITEM"; here it came
   from `from`. */
static void print_load_error(const char* tool, const char* message, const char* from)
{
    char text[1024];
    const char* at = strstr(message, "(from --set)");
    size_t skip = strlen("(from --set)");
    if (!at) {
        at = strstr(message, "--set ");
        skip = strlen("--set ");
    }
    if (!at) {
        app_error(tool, "%s", message);
        return;
    }
    bool paren = at[1] == 'f';
    snprintf(text, sizeof text, "%.*s%s%s%s%s", (int)(at - message), message, paren ? "(from " : "",
             from, paren ? ")" : " ", at + skip);
    app_error(tool, "%s", text);
}

/* Loads the scene with `sets` then `items`; on failure one line naming `from`. */
static int try_load(const char* tool, const char* scene, const app_overrides* sets,
                    const json_t* items, const char* from)
{
    size_t n = sets->count + json_array_size(items);
    const char** all = malloc((n ? n : 1) * sizeof *all);
    if (!all) {
        app_error(tool, "out of memory");
        return APP_EXIT_FAILURE;
    }
    for (uint32_t i = 0; i < sets->count; i++)
        all[i] = sets->items[i];
    for (size_t i = 0; i < json_array_size(items); i++)
        all[sets->count + i] = json_string_value(json_array_get(items, i));
    cvk_scene* loaded = NULL;
    cvk_error err;
    cvk_result r = cvk_scene_load(scene, all, (uint32_t)n, &loaded, &err);
    free(all);
    cvk_scene_destroy(loaded);
    if (r == CVK_SUCCESS)
        return APP_EXIT_OK;
    if (from)
        print_load_error(tool, err.message, from);
    else
        app_error(tool, "%s", err.message);
    return r == CVK_ERROR_OUT_OF_MEMORY ? APP_EXIT_FAILURE : APP_EXIT_BAD_INPUT;
}

/* "key=value" items of one variant, in the manifest's key order. */
static json_t* variant_items(const json_t* variant)
{
    json_t* items = json_array();
    const char* key;
    json_t* value;
    json_object_foreach((json_t*)variant, key, value) {
        size_t len = strlen(key) + strlen(json_string_value(value)) + 2;
        char* item = malloc(len);
        if (!item)
            continue;
        snprintf(item, len, "%s=%s", key, json_string_value(value));
        json_array_append_new(items, json_string(item));
        free(item);
    }
    return items;
}

/* Each value alone (so that a bad one is named with its axis), then every variant whole. */
static int check_variants(const char* tool, const char* scene, const app_overrides* sets,
                          const json_t* axes, const json_t* combos, const char* file,
                          const json_t* variants)
{
    json_t* none = json_array();
    int status = try_load(tool, scene, sets, none, NULL);
    json_decref(none);
    size_t a, v, k;
    json_t *axis, *value, *combo;
    json_array_foreach(axes, a, axis) {
        const char* key = json_string_value(json_object_get(axis, "key"));
        json_array_foreach(json_object_get(axis, "values"), v, value) {
            if (status != APP_EXIT_OK)
                return status;
            json_t* one = json_object();
            json_object_set(one, key, value);
            json_t* items = variant_items(one);
            status = try_load(tool, scene, sets, items, "--wedge");
            json_decref(items);
            json_decref(one);
        }
    }
    char from[512];
    json_array_foreach(combos, k, combo) {
        if (status != APP_EXIT_OK)
            return status;
        snprintf(from, sizeof from, "--wedges %s, entry %zu", file, k);
        json_t* items = variant_items(combo);
        status = try_load(tool, scene, sets, items, from);
        json_decref(items);
    }
    json_array_foreach(variants, k, combo) {
        if (status != APP_EXIT_OK)
            return status;
        snprintf(from, sizeof from, "--wedge, variant %zu", k);
        json_t* items = variant_items(combo);
        status = try_load(tool, scene, sets, items, from);
        json_decref(items);
    }
    return status;
}

/* ---- the variants ---------------------------------------------------------------------- */

/* Variant k of the product: the combination (if any) varies slowest, then the axes in order. */
static json_t* make_variant(const json_t* axes, const json_t* combos, uint64_t k)
{
    json_t* variant = json_object();
    size_t n = json_array_size(axes);
    uint64_t rest = k;
    json_t** picked = calloc(n ? n : 1, sizeof *picked);
    if (!picked)
        return variant;
    for (size_t a = n; a-- > 0;) {
        json_t* values = json_object_get(json_array_get(axes, a), "values");
        size_t size = json_array_size(values);
        picked[a] = json_array_get(values, rest % size);
        rest /= size;
    }
    if (json_array_size(combos))
        json_object_update(variant, json_array_get(combos, rest));
    for (size_t a = 0; a < n; a++)
        json_object_set(variant, json_string_value(json_object_get(json_array_get(axes, a), "key")),
                        picked[a]);
    free(picked);
    return variant;
}

/* How many variants, or an error past the limit. */
static int count_variants(const char* tool, const json_t* axes, const json_t* combos,
                          uint32_t limit, uint32_t* out)
{
    uint64_t count = json_array_size(combos) ? json_array_size(combos) : 1;
    size_t a;
    json_t* axis;
    json_array_foreach(axes, a, axis) {
        count *= json_array_size(json_object_get(axis, "values"));
        if (count > limit)
            break;
    }
    if (count > limit) {
        app_error(tool, "--wedge: more than %u variants (the limit; raise it with --wedge-limit N)",
                  limit);
        return APP_EXIT_BAD_INPUT;
    }
    *out = (uint32_t)count;
    return APP_EXIT_OK;
}

int app_wedge_build(app_wedge* w, const char* tool, const char* scene, const app_overrides* sets,
                    const app_wedge_options* o)
{
    *w = (app_wedge){.tool = tool};
    if (!o->axis_count && !o->file) {
        app_error(tool, "the wedge options need --wedge key.path=v1,v2,... or --wedges FILE");
        return APP_EXIT_BAD_INPUT;
    }
    json_t* keys = json_array();
    json_t* axes = json_array();
    json_t* combos = json_array();
    json_t* file_keys = json_array();
    int status = o->file ? read_file(tool, o->file, combos, file_keys) : APP_EXIT_OK;
    json_array_extend(keys, file_keys);
    for (uint32_t i = 0; i < o->axis_count && status == APP_EXIT_OK; i++)
        status = read_axis(tool, o->axes[i], axes, keys, file_keys, o->file);
    uint32_t count = 0;
    uint32_t limit = o->limit ? o->limit : APP_WEDGE_DEFAULT_LIMIT;
    if (status == APP_EXIT_OK)
        status = count_variants(tool, axes, combos, limit, &count);
    json_t* variants = json_array();
    for (uint32_t k = 0; k < count && status == APP_EXIT_OK; k++)
        json_array_append_new(variants, make_variant(axes, combos, k));
    if (status == APP_EXIT_OK)
        status = check_variants(tool, scene, sets, axes, combos, o->file, variants);
    json_t* set_items = json_array();
    for (uint32_t i = 0; i < sets->count; i++)
        json_array_append_new(set_items, json_string(sets->items[i]));
    if (status == APP_EXIT_OK) {
        w->manifest = json_pack("{sssisssOsOsOsbsbsi}", "format", APP_WEDGE_FORMAT, "version",
                                APP_WEDGE_VERSION, "scene", scene, "sets", set_items, "keys",
                                keys, "variants", variants, "preview", o->preview, "bake",
                                o->bake, "time_limit_s", (json_int_t)o->time_limit_s);
        w->count = count;
        if (!w->manifest) {
            app_error(tool, "out of memory");
            status = APP_EXIT_FAILURE;
        }
    }
    json_decref(set_items);
    json_decref(variants);
    json_decref(keys);
    json_decref(axes);
    json_decref(combos);
    json_decref(file_keys);
    return status;
}

void app_wedge_free(app_wedge* w)
{
    json_decref(w->manifest);
    w->manifest = NULL;
}

/* ---- one variant ------------------------------------------------------------------------ */

static bool write_json(FILE* file, void* user)
{
    return json_dumpf(user, file, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(9)) ==
               0 && fputc('\n', file) != EOF;
}

static bool write_text(FILE* file, void* user)
{
    return fputs(user, file) >= 0 && fputc('\n', file) != EOF;
}

static int write_json_file(const char* tool, const char* path, json_t* root)
{
    char message[600];
    if (app_write_atomic(path, write_json, root, message, sizeof message))
        return APP_EXIT_OK;
    app_error(tool, "%s", message);
    return APP_EXIT_FAILURE;
}

/* DIR/wedge.json: written when absent or the same; another wedge's is refused. */
static int write_manifest(const app_wedge* w, const char* folder)
{
    size_t len = strlen(folder) + 16;
    char* path = malloc(len);
    if (!path) {
        app_error(w->tool, "out of memory");
        return APP_EXIT_FAILURE;
    }
    snprintf(path, len, "%s/wedge.json", folder);
    json_t* old = json_load_file(path, 0, NULL);
    int status = APP_EXIT_OK;
    if (old && !json_equal(old, w->manifest)) {
        app_error(w->tool, "%s: holds another wedge (its scene, settings or variants differ); "
                  "give another -o folder or remove it", path);
        status = APP_EXIT_BAD_INPUT;
    } else if (!old) {
        status = write_json_file(w->tool, path, w->manifest);
    }
    json_decref(old);
    free(path);
    return status;
}

/* The names a variant's files go by. */
#define PATH_CHARS 4096

typedef struct variant_paths {
    char folder[PATH_CHARS - 16], status[PATH_CHARS], scene[PATH_CHARS], stats[PATH_CHARS],
        log[PATH_CHARS], preview[PATH_CHARS], bake[PATH_CHARS];
} variant_paths;

static bool make_paths(variant_paths* p, const char* out, uint32_t index)
{
    int n = snprintf(p->folder, sizeof p->folder, "%s/v%04u", out, index);
    if (n < 0 || (size_t)n >= sizeof p->folder)
        return false;
    snprintf(p->status, sizeof p->status, "%s/status.json", p->folder);
    snprintf(p->scene, sizeof p->scene, "%s/scene.json", p->folder);
    snprintf(p->stats, sizeof p->stats, "%s/stats.json", p->folder);
    snprintf(p->log, sizeof p->log, "%s/log.txt", p->folder);
    snprintf(p->preview, sizeof p->preview, "%s/last.png", p->folder);
    snprintf(p->bake, sizeof p->bake, "%s/bake", p->folder);
    return true;
}

/* The scene as the variant reads it. */
static int write_resolved_scene(const char* tool, const char* scene, const app_overrides* all,
                                const char* path)
{
    cvk_scene* loaded = NULL;
    int status = app_load_scene(tool, scene, all, &loaded);
    if (status != APP_EXIT_OK)
        return status;
    char message[600];
    if (!app_write_atomic(path, write_text, (void*)cvk_scene_get_json(loaded), message,
                          sizeof message)) {
        app_error(tool, "%s", message);
        status = APP_EXIT_FAILURE;
    }
    cvk_scene_destroy(loaded);
    return status;
}

/* Runs with stderr going to the variant's log, then copies the log to stderr; `last` gets the
   log's last line (the error of a failed run). */
static int run_logged(const char* tool, const char* log_path, app_wedge_runner runner, void* user,
                      const app_overrides* all, app_wedge_run* run, char* last, size_t last_size)
{
    last[0] = '\0';
    fflush(stderr);
    int saved = dup(STDERR_FILENO);
    int fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (saved < 0 || fd < 0) {
        app_error(tool, "%s: cannot write: %s", log_path, strerror(errno));
        if (saved >= 0)
            close(saved);
        if (fd >= 0)
            close(fd);
        return APP_EXIT_FAILURE;
    }
    dup2(fd, STDERR_FILENO);
    close(fd);
    int status = runner(user, all, run);
    fflush(stderr);
    dup2(saved, STDERR_FILENO);
    close(saved);
    FILE* log = fopen(log_path, "r");
    char line[2048];
    while (log && fgets(line, sizeof line, log)) {
        fputs(line, stderr);
        line[strcspn(line, "\n")] = '\0';
        if (line[0])
            snprintf(last, last_size, "%s", line);
    }
    if (log)
        fclose(log);
    return status;
}

static json_t* start_status(uint32_t index)
{
    char host[256] = "";
    gethostname(host, sizeof host - 1);
    return json_pack("{sssisssisI}", "state", "running", "variant", (json_int_t)index, "host",
                     host, "pid", (json_int_t)getpid(), "started", (json_int_t)time(NULL));
}

/* The end: what happened, from the exit status and the run. */
static json_t* end_status(uint32_t index, int status, const app_wedge_run* run, const char* error,
                          const char* tool, double seconds)
{
    const char* state = status == APP_EXIT_OK ? "ok"
                        : run->diverged       ? "diverged"
                        : run->timed_out      ? "timed-out"
                                              : "failed";
    size_t prefix = strlen(tool) + 2;
    if (!strncmp(error, tool, prefix - 2) && !strncmp(error + prefix - 2, ": ", 2))
        error += prefix; /* the line without "clothvk-sim: " */
    json_t* root = json_pack("{sssisisisi}", "state", state, "variant", (json_int_t)index, "exit",
                             (json_int_t)status, "frames", (json_int_t)run->frames_done, "of",
                             (json_int_t)run->frames);
    if (run->diverged)
        json_object_set_new(root, "diverged_frame", json_integer((json_int_t)run->diverged_frame));
    json_object_set_new(root, "error", status == APP_EXIT_OK || !error[0] ? json_null()
                                                                          : json_string(error));
    json_object_set_new(root, "seconds", json_real(seconds));
    return root;
}

/* The variant's overrides: `sets`, then its own items (kept in `items`). */
static int variant_overrides(const app_wedge* w, const app_overrides* sets, uint32_t index,
                             json_t* items, app_overrides* all)
{
    json_t* own = variant_items(json_array_get(json_object_get(w->manifest, "variants"), index));
    json_array_extend(items, own);
    json_decref(own);
    int status = APP_EXIT_OK;
    for (uint32_t i = 0; i < sets->count && status == APP_EXIT_OK; i++)
        status = app_overrides_add(all, w->tool, sets->items[i]);
    for (size_t i = 0; i < json_array_size(items) && status == APP_EXIT_OK; i++)
        status = app_overrides_add(all, w->tool, json_string_value(json_array_get(items, i)));
    return status;
}

/* Old outputs of this variant go before it runs: the folder then holds this run's only. */
static void remove_old(const variant_paths* p)
{
    unlink(p->stats);
    unlink(p->preview);
    unlink(p->log);
}

int app_wedge_run_index(const app_wedge* w, const app_overrides* sets, const app_wedge_options* o,
                        uint32_t index, app_wedge_runner runner, void* user)
{
    double start = app_now_ms();
    if (index >= w->count) {
        app_error(w->tool, "--wedge-index %u: the wedge has %u variant%s (0 to %u)", index,
                  w->count, w->count == 1 ? "" : "s", w->count - 1);
        return APP_EXIT_BAD_INPUT;
    }
    variant_paths p;
    if (!make_paths(&p, o->out, index)) {
        app_error(w->tool, "-o %s: the name is too long", o->out);
        return APP_EXIT_BAD_INPUT;
    }
    if (!app_make_output_folder(w->tool, o->out))
        return APP_EXIT_BAD_INPUT;
    int status = write_manifest(w, o->out);
    if (status != APP_EXIT_OK)
        return status;
    if (!app_make_output_folder(w->tool, p.folder))
        return APP_EXIT_FAILURE;
    remove_old(&p);
    json_t* started = start_status(index);
    status = write_json_file(w->tool, p.status, started);
    json_decref(started);
    json_t* items = json_array();
    app_overrides all = {0};
    if (status == APP_EXIT_OK)
        status = variant_overrides(w, sets, index, items, &all);
    if (status == APP_EXIT_OK)
        status = write_resolved_scene(w->tool, json_string_value(json_object_get(w->manifest,
                                      "scene")), &all, p.scene);
    app_wedge_run run = {.stats_path = p.stats, .preview_path = o->preview ? p.preview : NULL,
                         .bake_path = o->bake ? p.bake : NULL, .time_limit_s = o->time_limit_s,
                         .deadline_ms = o->time_limit_s ? start + 1e3 * o->time_limit_s : 0};
    char last[2048] = "";
    if (status == APP_EXIT_OK)
        status = run_logged(w->tool, p.log, runner, user, &all, &run, last, sizeof last);
    json_t* end = end_status(index, status, &run, last, w->tool, (app_now_ms() - start) / 1e3);
    int written = write_json_file(w->tool, p.status, end);
    json_decref(end);
    app_overrides_free(&all);
    json_decref(items);
    return status != APP_EXIT_OK ? status : written;
}

/* ---- every variant on this machine -------------------------------------------------------- */

typedef struct child {
    pid_t pid;
    uint32_t index;
    double started_ms;
    bool killed;
} child;

/* One line of DIR/states.tsv for a child that did not end by itself. */
static void note_state(json_t* states, const child* c, int wait_status, uint32_t limit_s)
{
    char detail[256];
    const char* state;
    if (c->killed) {
        state = "KILLED";
        snprintf(detail, sizeof detail, "still running %d s past its time limit of %u s; killed",
                 KILL_GRACE_S, limit_s);
    } else if (WIFSIGNALED(wait_status)) {
        state = "SIGNALED";
        snprintf(detail, sizeof detail, "ended by signal %d (%s)", WTERMSIG(wait_status),
                 strsignal(WTERMSIG(wait_status)));
    } else {
        return;
    }
    char line[400];
    snprintf(line, sizeof line, "%u\t%s\t%s\n", c->index, state, detail);
    json_array_append_new(states, json_string(line));
}

static bool write_lines(FILE* file, void* user)
{
    size_t i;
    json_t* line;
    json_array_foreach((json_t*)user, i, line)
        if (fputs(json_string_value(line), file) < 0)
            return false;
    return true;
}

/* Starts variant `index` in a child process. */
static int spawn(const app_wedge* w, const app_overrides* sets, const app_wedge_options* o,
                 uint32_t index, app_wedge_runner runner, void* user, child* c)
{
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) {
        app_error(w->tool, "cannot start a process for variant %u: %s", index, strerror(errno));
        return APP_EXIT_FAILURE;
    }
    if (pid == 0) {
        int status = app_wedge_run_index(w, sets, o, index, runner, user);
        fflush(stdout);
        fflush(stderr);
        _exit(status);
    }
    *c = (child){pid, index, app_now_ms(), false};
    return APP_EXIT_OK;
}

/* Waits for one child to end (killing one past its limit and grace); returns its slot. */
static size_t reap(child* running, size_t count, uint32_t limit_s, json_t* states)
{
    for (;;) {
        int wait_status = 0;
        pid_t pid = waitpid(-1, &wait_status, WNOHANG);
        for (size_t i = 0; pid > 0 && i < count; i++) {
            if (running[i].pid != pid)
                continue;
            note_state(states, &running[i], wait_status, limit_s);
            return i;
        }
        if (pid < 0 && errno != EINTR)
            return count; /* no children left: cannot happen while count > 0 */
        double now = app_now_ms();
        for (size_t i = 0; i < count && limit_s; i++) {
            if (!running[i].killed && now - running[i].started_ms > 1e3 * (limit_s + KILL_GRACE_S)) {
                kill(running[i].pid, SIGKILL);
                running[i].killed = true;
            }
        }
        struct timespec nap = {0, 20 * 1000 * 1000};
        nanosleep(&nap, NULL);
    }
}

int app_wedge_run_all(const app_wedge* w, const app_overrides* sets, const app_wedge_options* o,
                      app_wedge_runner runner, void* user)
{
    if (!app_make_output_folder(w->tool, o->out))
        return APP_EXIT_BAD_INPUT;
    int status = write_manifest(w, o->out);
    if (status != APP_EXIT_OK)
        return status;
    size_t len = strlen(o->out) + 16;
    char* states_path = malloc(len);
    child* running = calloc(o->jobs ? o->jobs : 1, sizeof *running);
    json_t* states = json_array();
    if (!states_path || !running) {
        free(states_path);
        free(running);
        json_decref(states);
        app_error(w->tool, "out of memory");
        return APP_EXIT_FAILURE;
    }
    snprintf(states_path, len, "%s/states.tsv", o->out);
    unlink(states_path);
    uint32_t jobs = o->jobs ? o->jobs : 1;
    size_t active = 0;
    for (uint32_t next = 0; (next < w->count && !app_interrupted()) || active > 0;) {
        if (next < w->count && active < jobs && !app_interrupted() && status == APP_EXIT_OK) {
            status = spawn(w, sets, o, next, runner, user, &running[active]);
            active += status == APP_EXIT_OK;
            next++;
            continue;
        }
        if (active == 0)
            break;
        size_t done = reap(running, active, o->time_limit_s, states);
        if (done >= active)
            break;
        running[done] = running[--active];
    }
    char message[600];
    if (json_array_size(states) && !app_write_atomic(states_path, write_lines, states, message,
                                                     sizeof message)) {
        app_error(w->tool, "%s", message);
        status = APP_EXIT_FAILURE;
    }
    free(states_path);
    free(running);
    json_decref(states);
    if (status != APP_EXIT_OK)
        return status;
    status = app_wedge_gather(w->tool, o->out);
    if (status == APP_EXIT_OK && app_interrupted()) {
        app_error(w->tool, "interrupted: the table holds the variants run so far");
        status = APP_EXIT_FAILURE;
    }
    return status;
}

/* ---- the preview -------------------------------------------------------------------------- */

int app_wedge_preview(const char* tool, cvk_sim* sim, const cvk_scene_desc* scene,
                      uint32_t frames, const char* path)
{
    cvk_mesh* mesh = NULL;
    cvk_renderer* renderer = NULL;
    cvk_error err;
    cvk_result r = cvk_mesh_create(sim, NULL, &mesh, &err);
    if (r == CVK_SUCCESS)
        r = cvk_renderer_create(mesh, &scene->render, &renderer, &err);
    if (r == CVK_SUCCESS) {
        cvk_renderer_set_time(renderer, (double)frames * scene->dt * scene->substeps);
        r = cvk_renderer_draw(renderer, &err);
    }
    if (r == CVK_SUCCESS) {
        cvk_image image = cvk_renderer_get_image(renderer);
        r = cvk_image_write_png(&image, path, &err);
    }
    cvk_renderer_destroy(renderer);
    cvk_mesh_destroy(mesh);
    if (r == CVK_SUCCESS)
        return APP_EXIT_OK;
    app_error(tool, "preview %s: %s", path, err.message);
    return APP_EXIT_FAILURE;
}
