/* Overrides: "key.path=value" (clothvk-sim --set) applied to the JSON tree before conversion,
   so that a value from the command line goes through the same readers and checks as the file's. */
#include "scene/scene_read.h"

#include "core/error.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* One --set being applied. */
typedef struct walk {
    cvk_reader* rd;
    const char* path;                  /* as written, for messages */
    char normalised[CVK_KEY_PATH_MAX]; /* keys passed so far, indices in plain decimal */
} walk;

__attribute__((format(printf, 2, 3)))
static cvk_result fail_walk(walk* w, const char* format, ...)
{
    char problem[384];
    va_list args;
    va_start(args, format);
    vsnprintf(problem, sizeof problem, format, args);
    va_end(args);
    return cvk_fail(w->rd->error, CVK_ERROR_INVALID_ARGUMENT, "%s: --set %s: %s", w->rd->source, w->path, problem);
}

static bool parse_index(const char* key, size_t* out)
{
    size_t v = 0;
    if (key[0] == '\0')
        return false;
    for (const char* c = key; *c; c++) {
        if (*c < '0' || *c > '9' || v > (SIZE_MAX - 9) / 10)
            return false;
        v = v * 10 + (size_t)(*c - '0');
    }
    *out = v;
    return true;
}

/* An index may name an element or the position one past the end (append). */
static cvk_result array_slot(walk* w, json_t* array, const char* key, size_t* out_index)
{
    size_t size = json_array_size(array);
    if (!parse_index(key, out_index))
        return fail_walk(w, "%s is an array, %s is not an index", w->normalised, key);
    if (*out_index > size)
        return fail_walk(w, "index %zu is out of range (%s has %zu element%s)", *out_index, w->normalised, size,
                         size == 1 ? "" : "s");
    return CVK_SUCCESS;
}

static void append_normalised(walk* w, const char* key)
{
    char joined[CVK_KEY_PATH_MAX];
    cvk_json_join_key(joined, w->normalised, key);
    memcpy(w->normalised, joined, sizeof joined);
}

static void append_index(walk* w, size_t index)
{
    char key[32];
    snprintf(key, sizeof key, "%zu", index);
    append_normalised(w, key);
}

/* The container a missing intermediate key gets: an array when the next key is an index, so
   that "cloths.0.pins.0=[0,0]" works on a cloth without pins. */
static json_t* new_container(const char* next_key)
{
    size_t index;
    return parse_index(next_key, &index) ? json_array() : json_object();
}

static cvk_result descend_object(walk* w, json_t* object, const char* key, const char* next_key,
                                 json_t** out_child)
{
    json_t* child = json_object_get(object, key);
    if (!child) {
        child = new_container(next_key);
        if (json_object_set_new(object, key, child) != 0)
            return cvk_reader_fail_memory(w->rd);
    }
    append_normalised(w, key);
    *out_child = child;
    return CVK_SUCCESS;
}

static cvk_result descend_array(walk* w, json_t* array, const char* key, const char* next_key,
                                json_t** out_child)
{
    size_t index = 0;
    cvk_result r = array_slot(w, array, key, &index);
    if (r != CVK_SUCCESS)
        return r;
    json_t* child = json_array_get(array, index);
    if (!child) {
        child = new_container(next_key);
        if (json_array_append_new(array, child) != 0)
            return cvk_reader_fail_memory(w->rd);
    }
    append_index(w, index);
    *out_child = child;
    return CVK_SUCCESS;
}

/* Steps from node into key, creating a container for next_key where key is missing. */
static cvk_result descend(walk* w, json_t* node, const char* key, const char* next_key, json_t** out_child)
{
    if (json_is_object(node))
        return descend_object(w, node, key, next_key, out_child);
    if (json_is_array(node))
        return descend_array(w, node, key, next_key, out_child);
    return fail_walk(w, "%s is not an object or array", w->normalised);
}

/* Puts value at key of node. Always takes value's reference, as jansson's *_new calls do. */
static cvk_result store(walk* w, json_t* node, const char* key, json_t* value)
{
    size_t index = 0;
    int failed = 0;
    if (json_is_object(node)) {
        failed = json_object_set_new(node, key, value);
        append_normalised(w, key);
    } else if (json_is_array(node)) {
        cvk_result r = array_slot(w, node, key, &index);
        if (r != CVK_SUCCESS) {
            json_decref(value);
            return r;
        }
        failed = index == json_array_size(node) ? json_array_append_new(node, value)
                                                : json_array_set_new(node, index, value);
        append_index(w, index);
    } else {
        json_decref(value);
        return fail_walk(w, "%s is not an object or array", w->normalised);
    }
    return failed ? cvk_reader_fail_memory(w->rd) : CVK_SUCCESS;
}

/* Copies the dotted part at *cursor into key and moves *cursor past it (NULL after the last). */
static void next_key(const char** cursor, char key[CVK_KEY_PATH_MAX])
{
    const char* dot = strchr(*cursor, '.');
    size_t length = dot ? (size_t)(dot - *cursor) : strlen(*cursor);
    cvk_key_path(key, "%.*s", (int)length, *cursor);
    *cursor = dot ? dot + 1 : NULL;
}

/* Walks w->path from root and stores value at its end. Always takes value's reference. */
static cvk_result set_path(walk* w, json_t* root, json_t* value)
{
    char key[CVK_KEY_PATH_MAX];
    char following[CVK_KEY_PATH_MAX];
    const char* cursor = w->path;
    json_t* node = root;
    next_key(&cursor, key);
    while (cursor) {
        next_key(&cursor, following);
        cvk_result r = descend(w, node, key, following, &node);
        if (r != CVK_SUCCESS) {
            json_decref(value);
            return r;
        }
        memcpy(key, following, sizeof key);
    }
    return store(w, node, key, value);
}

static bool has_empty_part(const char* path)
{
    size_t length = strlen(path);
    return length == 0 || path[0] == '.' || path[length - 1] == '.' || strstr(path, "..") != NULL;
}

/* JSON where it parses (bare NaN and Infinity included), else the raw text as a string, so that a
   shell-stripped `--set solver.linear=jacobi` works. NULL when neither works, or when the text
   is JSON but for a number past double's range (*too_large): not a string someone meant. */
static json_t* parse_override_value(const char* text, bool* out_of_memory, bool* too_large)
{
    json_error_t jerr;
    json_t* value = cvk_json_parse(text, strlen(text), &jerr, out_of_memory);
    if (value || *out_of_memory)
        return value;
    *too_large = json_error_code(&jerr) == json_error_numeric_overflow;
    return *too_large ? NULL : json_string(text);
}

cvk_result cvk_reader_apply_override(cvk_reader* rd, json_t* root, const char* text)
{
    const char* equals = strchr(text, '=');
    if (!equals || equals == text)
        return cvk_fail(rd->error, CVK_ERROR_INVALID_ARGUMENT, "%s: --set %s: expected key.path=value", rd->source,
                        text);
    if ((size_t)(equals - text) >= CVK_KEY_PATH_MAX)
        return cvk_fail(rd->error, CVK_ERROR_INVALID_ARGUMENT, "%s: --set %.*s: the key path is too long",
                        rd->source, (int)(equals - text), text);
    char path[CVK_KEY_PATH_MAX];
    cvk_key_path(path, "%.*s", (int)(equals - text), text);
    walk w = {.rd = rd, .path = path};
    if (has_empty_part(path))
        return fail_walk(&w, "the key path has an empty part");
    bool out_of_memory = false, too_large = false;
    json_t* value = parse_override_value(equals + 1, &out_of_memory, &too_large);
    if (too_large)
        return fail_walk(&w, "%s holds a number too large to read (beyond double precision)",
                         equals + 1);
    if (!value)
        return out_of_memory ? cvk_reader_fail_memory(rd)
                             : fail_walk(&w, "the value is neither JSON nor UTF-8 text");
    cvk_result r = set_path(&w, root, value);
    if (r == CVK_SUCCESS)
        memcpy(rd->set_paths[rd->set_count++], w.normalised, sizeof w.normalised);
    return r;
}
