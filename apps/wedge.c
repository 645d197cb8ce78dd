/* Wedges: the variants (axes and explicit combinations) and their checks. Running them is
   wedge_run.c's; the table and the contact sheet are wedge_gather.c's. */
#include "wedge.h"

#include <stdlib.h>
#include <string.h>

bool app_wedge_requested(const app_wedge_options* o)
{
    return o->axis_count || o->file || o->limit || o->count || o->index_set || o->jobs_set ||
           o->time_limit_s || o->preview || o->bake;
}

int app_wedge_add_axis(app_wedge_options* o, const char* tool, const char* item)
{
    return app_strings_add(&o->axes, &o->axis_count, tool, item);
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

json_t* app_wedge_variant_items(const json_t* variant)
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
            json_t* items = app_wedge_variant_items(one);
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
        json_t* items = app_wedge_variant_items(combo);
        status = try_load(tool, scene, sets, items, from);
        json_decref(items);
    }
    json_array_foreach(variants, k, combo) {
        if (status != APP_EXIT_OK)
            return status;
        snprintf(from, sizeof from, "--wedge, variant %zu", k);
        json_t* items = app_wedge_variant_items(combo);
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
