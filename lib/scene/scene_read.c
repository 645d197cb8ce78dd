/* JSON values into C structs by field tables (see scene_read.h), and JSON text that may hold
   bare NaN and Infinity. */
#include "scene/scene_read.h"

#include "core/error.h"

#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- ownership ---- */

void* cvk_blocks_keep(cvk_blocks* blocks, void* block)
{
    if (!block)
        return NULL;
    if (blocks->count == blocks->capacity) {
        size_t capacity = blocks->capacity ? 2 * blocks->capacity : 16;
        void** items = realloc(blocks->items, capacity * sizeof *items);
        if (!items) {
            free(block);
            return NULL;
        }
        blocks->items = items;
        blocks->capacity = capacity;
    }
    blocks->items[blocks->count++] = block;
    return block;
}

void* cvk_blocks_alloc(cvk_blocks* blocks, size_t count, size_t size)
{
    return cvk_blocks_keep(blocks, calloc(count, size));
}

void cvk_blocks_free(cvk_blocks* blocks)
{
    for (size_t i = 0; i < blocks->count; i++)
        free(blocks->items[i]);
    free(blocks->items);
    *blocks = (cvk_blocks){0};
}

/* ---- messages ---- */

/* true when path is prefix or lies under it ("cloths.0.mass" under "cloths.0"). */
static bool path_within(const char* path, const char* prefix)
{
    size_t n = strlen(prefix);
    return n > 0 && strncmp(path, prefix, n) == 0 && (path[n] == '\0' || path[n] == '.');
}

/* A bad value under an overridden path, or one with an overridden part, came from --set. */
static bool from_override(const cvk_reader* rd, const char* path)
{
    for (uint32_t i = 0; i < rd->set_count; i++) {
        if (path_within(path, rd->set_paths[i]) || path_within(rd->set_paths[i], path))
            return true;
    }
    return false;
}

cvk_result cvk_reader_fail_problem(cvk_reader* rd, const char* path, const char* problem)
{
    if (path[0] == '\0')
        return cvk_fail(rd->error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s", rd->source, problem);
    const char* origin = from_override(rd, path) ? " (from --set)" : "";
    return cvk_fail(rd->error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s%s: %s", rd->source, path, origin, problem);
}

__attribute__((format(printf, 3, 4)))
cvk_result cvk_reader_fail_at(cvk_reader* rd, const char* path, const char* format, ...)
{
    char problem[384];
    va_list args;
    va_start(args, format);
    vsnprintf(problem, sizeof problem, format, args);
    va_end(args);
    return cvk_reader_fail_problem(rd, path, problem);
}

cvk_result cvk_reader_fail_memory(cvk_reader* rd)
{
    return cvk_fail(rd->error, CVK_ERROR_OUT_OF_MEMORY, "%s: out of memory", rd->source);
}

static bool is_letter(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}

/* "nan", "inf" or "infinity" in any case, with an optional minus: what people write and JSON lacks. */
static bool is_nonfinite_word(const char* text, size_t length)
{
    static const char* const words[] = {"nan", "inf", "infinity"};
    if (length > 0 && text[0] == '-') {
        text++;
        length--;
    }
    for (size_t i = 0; i < sizeof words / sizeof words[0]; i++) {
        if (strlen(words[i]) == length && strncasecmp(text, words[i], length) == 0)
            return true;
    }
    return false;
}

/* What a reader found where it expected something else: "a string", "an array of 2", "NaN". */
const char* cvk_json_describe(const json_t* value, char* buffer, size_t size)
{
    switch (json_typeof(value)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY:
        snprintf(buffer, size, "an array of %zu", json_array_size(value));
        return buffer;
    case JSON_STRING:
        /* A quoted bare NaN or Infinity (see cvk_json_parse) is named as the user wrote it. */
        if (is_nonfinite_word(json_string_value(value), json_string_length(value)))
            return json_string_value(value);
        /* The value itself helps find the mistake; a long one is cut. */
        if (json_string_length(value) > 24)
            snprintf(buffer, size, "the string \"%.21s...\"", json_string_value(value));
        else
            snprintf(buffer, size, "the string \"%s\"", json_string_value(value));
        return buffer;
    case JSON_INTEGER:
    case JSON_REAL:
        snprintf(buffer, size, "the number %s", cvk_double_text(json_number_value(value)).text);
        return buffer;
    case JSON_TRUE: return "true";
    case JSON_FALSE: return "false";
    case JSON_NULL: return "null";
    }
    return "an unknown value";
}

bool cvk_json_is_nonfinite(const json_t* value)
{
    return json_is_string(value) && is_nonfinite_word(json_string_value(value), json_string_length(value));
}

cvk_result cvk_reader_fail_type(cvk_reader* rd, const char* path, const char* expected, const json_t* value)
{
    char buffer[48];
    return cvk_reader_fail_at(rd, path, "expected %s, got %s", expected,
                              cvk_json_describe(value, buffer, sizeof buffer));
}

void cvk_json_join_key(char out[CVK_KEY_PATH_MAX], const char* path, const char* key)
{
    cvk_key_path(out, "%s%s%s", path, path[0] ? "." : "", key);
}

void cvk_json_join_index(char out[CVK_KEY_PATH_MAX], const char* path, size_t index)
{
    cvk_key_path(out, "%s.%zu", path, index);
}

/* ---- value readers: one per kind of key, each writes where its table entry points ---- */

cvk_result cvk_read_string(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    if (!json_is_string(value))
        return cvk_reader_fail_type(rd, path, "a string", value);
    char* text = cvk_blocks_keep(rd->blocks, strdup(json_string_value(value)));
    if (!text)
        return cvk_reader_fail_memory(rd);
    *(const char**)dest = text;
    return CVK_SUCCESS;
}

cvk_result cvk_read_path(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    if (!json_is_string(value))
        return cvk_reader_fail_type(rd, path, "a string", value);
    const char* text = json_string_value(value);
    /* An empty path stays empty, for validation to name it. */
    if (rd->folder_length == 0 || text[0] == '/' || text[0] == '\0')
        return cvk_read_string(rd, f, value, path, dest);
    size_t length = strlen(text);
    char* joined = cvk_blocks_keep(rd->blocks, malloc(rd->folder_length + length + 1));
    if (!joined)
        return cvk_reader_fail_memory(rd);
    memcpy(joined, rd->source, rd->folder_length);
    memcpy(joined + rd->folder_length, text, length + 1);
    *(const char**)dest = joined;
    return CVK_SUCCESS;
}

cvk_result cvk_read_bool(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    if (!json_is_boolean(value))
        return cvk_reader_fail_type(rd, path, "true or false", value);
    *(bool*)dest = json_is_true(value);
    return CVK_SUCCESS;
}

/* A number that would not read as itself in single precision is refused as written: past
   float's range it would become infinite, and so near 0 that it rounds to 0 it would be
   refused (or taken) as the 0 nobody wrote (keyframe times 0 and 1e-300: "got 0"). */
cvk_result cvk_read_float(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    if (json_is_string(value) && is_nonfinite_word(json_string_value(value), json_string_length(value)))
        return cvk_reader_fail_at(rd, path, "must be a finite number, got %s", json_string_value(value));
    if (!json_is_number(value))
        return cvk_reader_fail_type(rd, path, "a number", value);
    double v = json_number_value(value);
    if (fabs(v) > FLT_MAX)
        return cvk_reader_fail_at(rd, path, "is too large for single precision (at most %s in "
                                  "magnitude), got %s", cvk_float_text(FLT_MAX).text,
                                  cvk_double_text(v).text);
    if (v != 0.0 && (float)v == 0.0f)
        return cvk_reader_fail_at(rd, path, "is too near 0 for single precision, which reads it as "
                                  "0 (the least magnitude is %s), got %s",
                                  cvk_float_text(FLT_TRUE_MIN).text, cvk_double_text(v).text);
    *(float*)dest = (float)v;
    return CVK_SUCCESS;
}

/* Integral reals (8.0) are accepted: some tools write every number as a real. */
cvk_result cvk_read_uint(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    if (!json_is_number(value))
        return cvk_reader_fail_type(rd, path, "a whole number", value);
    double v = json_number_value(value);
    cvk_number_text text = cvk_double_text(v);
    if (v != floor(v))
        return cvk_reader_fail_at(rd, path, "expected a whole number, got %s", text.text);
    if (v < 0)
        return cvk_reader_fail_at(rd, path, "must be at least %" PRIu32 ", got %s", f->min, text.text);
    if (v > UINT32_MAX)
        return cvk_reader_fail_at(rd, path, "must be at most %" PRIu32 ", got %s", UINT32_MAX,
                                  text.text);
    *(uint32_t*)dest = (uint32_t)v;
    return CVK_SUCCESS;
}

static cvk_result read_array(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path,
                             void* dest, const char* noun, cvk_read_fn read_element, size_t element_size)
{
    if (!json_is_array(value) || json_array_size(value) != f->count) {
        char expected[64];
        snprintf(expected, sizeof expected, "an array of %" PRIu32 " %s", f->count, noun);
        return cvk_reader_fail_type(rd, path, expected, value);
    }
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < f->count; i++) {
        cvk_json_join_index(element, path, i);
        cvk_result r = read_element(rd, f, json_array_get(value, i), element, (char*)dest + i * element_size);
        if (r != CVK_SUCCESS)
            return r;
    }
    return CVK_SUCCESS;
}

cvk_result cvk_read_floats(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    return read_array(rd, f, value, path, dest, "numbers", cvk_read_float, sizeof(float));
}

cvk_result cvk_read_uints(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    return read_array(rd, f, value, path, dest, "whole numbers", cvk_read_uint, sizeof(uint32_t));
}

/* "a, b, c or d" from an enum's name function, which returns NULL past the last value. */
void cvk_list_names(const char* (*name_of)(int), char* out, size_t size)
{
    int count = 0;
    while (name_of(count))
        count++;
    size_t used = 0;
    out[0] = '\0';
    for (int v = 0; v < count && used < size; v++) {
        const char* separator = v == 0 ? "" : v == count - 1 ? " or " : ", ";
        used += (size_t)snprintf(out + used, size - used, "%s%s", separator, name_of(v));
    }
}

cvk_result cvk_read_enum(cvk_reader* rd, json_t* value, const char* path, const char* what,
                         const char* (*name_of)(int), int* out)
{
    if (!json_is_string(value))
        return cvk_reader_fail_type(rd, path, "a string", value);
    const char* text = json_string_value(value);
    for (int v = 0; name_of(v); v++) {
        if (strcmp(text, name_of(v)) == 0) {
            *out = v;
            return CVK_SUCCESS;
        }
    }
    char names[256];
    cvk_list_names(name_of, names, sizeof names);
    return cvk_reader_fail_at(rd, path, "unknown %s \"%s\" (expected %s)", what, text, names);
}

/* ---- objects: every key must be in the table; keys are read in the order the file has them ---- */

static const cvk_field* find_field(const cvk_table* t, const char* key)
{
    for (size_t i = 0; i < t->count; i++) {
        if (strcmp(t->fields[i].key, key) == 0)
            return &t->fields[i];
    }
    return t->shared ? find_field(t->shared, key) : NULL;
}

/* The shared table's keys, then the table's own. */
static size_t list_keys(const cvk_table* t, char* out, size_t size)
{
    size_t used = t->shared ? list_keys(t->shared, out, size) : 0;
    if (used == 0)
        out[0] = '\0';
    for (size_t i = 0; i < t->count && used < size; i++)
        used += (size_t)snprintf(out + used, size - used, "%s%s", used ? ", " : "", t->fields[i].key);
    return used;
}

static cvk_result check_required(cvk_reader* rd, const cvk_table* t, json_t* object, const char* path)
{
    char child[CVK_KEY_PATH_MAX];
    if (t->shared) {
        cvk_result r = check_required(rd, t->shared, object, path);
        if (r != CVK_SUCCESS)
            return r;
    }
    for (size_t i = 0; i < t->count; i++) {
        const cvk_field* f = &t->fields[i];
        if (!f->required || json_object_get(object, f->key))
            continue;
        cvk_json_join_key(child, path, f->key);
        return cvk_reader_fail_at(rd, child, "missing; %s", f->required);
    }
    return CVK_SUCCESS;
}

cvk_result cvk_read_object(cvk_reader* rd, const cvk_table* t, json_t* object, const char* path, void* dest)
{
    if (!json_is_object(object))
        return cvk_reader_fail_type(rd, path, "an object", object);
    const char* key;
    json_t* value;
    json_object_foreach(object, key, value) {
        char child[CVK_KEY_PATH_MAX];
        cvk_json_join_key(child, path, key);
        const cvk_field* f = find_field(t, key);
        if (!f) {
            char keys[320];
            list_keys(t, keys, sizeof keys);
            if (t->owner)
                return cvk_reader_fail_at(rd, child, "unknown key for %s (expected one of: %s)", t->owner, keys);
            return cvk_reader_fail_at(rd, child, "unknown key (expected one of: %s)", keys);
        }
        cvk_result r = f->read(rd, f, value, child, (char*)dest + f->offset);
        if (r != CVK_SUCCESS)
            return r;
    }
    return check_required(rd, t, object, path);
}

cvk_result cvk_read_nested(cvk_reader* rd, const cvk_field* f, json_t* value, const char* path, void* dest)
{
    return cvk_read_object(rd, f->nested, value, path, dest);
}

/* ---- JSON text, with bare NaN and Infinity accepted as strings ---- */

/* Integers are read as doubles: every reader takes numbers as doubles, and an integer too long
   for jansson's 64 bits (99999999999999999999) is then a number past its key's bound, not a
   syntax error or, through --set, a string. */
enum { json_flags = JSON_REJECT_DUPLICATES | JSON_DECODE_ANY | JSON_DECODE_INT_AS_REAL };

/* Text with the bare NaN/Infinity words found so far wrapped in quotes. */
typedef struct quoted_text {
    const char* text;
    size_t size;
    char* owned;  /* the rewritten copy, once there is one */
    size_t* ends; /* offset just past each added closing quote, increasing */
    size_t count;
} quoted_text;

static size_t error_offset(const json_error_t* jerr, size_t size)
{
    size_t position = jerr->position > 0 ? (size_t)jerr->position : 0;
    return position < size ? position : size;
}

/* jansson stops just past a bare word, or just past the '-' of "-Infinity". */
static bool find_nonfinite_word(const char* text, size_t size, const json_error_t* jerr, size_t* out_start,
                                size_t* out_end)
{
    if (json_error_code(jerr) != json_error_invalid_syntax || strncmp(jerr->text, "invalid token", 13) != 0)
        return false;
    size_t start = error_offset(jerr, size);
    while (start > 0 && is_letter(text[start - 1]))
        start--;
    if (start > 0 && text[start - 1] == '-')
        start--;
    size_t end = start < size && text[start] == '-' ? start + 1 : start;
    while (end < size && is_letter(text[end]))
        end++;
    if (end < size && text[end] >= '0' && text[end] <= '9')
        return false;
    *out_start = start;
    *out_end = end;
    return is_nonfinite_word(text + start, end - start);
}

static bool quote_word(quoted_text* q, size_t start, size_t end)
{
    size_t* ends = realloc(q->ends, (q->count + 1) * sizeof *ends);
    if (!ends)
        return false;
    q->ends = ends;
    char* text = malloc(q->size + 2);
    if (!text)
        return false;
    memcpy(text, q->text, start);
    text[start] = '"';
    memcpy(text + start + 1, q->text + start, end - start);
    text[end + 1] = '"';
    memcpy(text + end + 2, q->text + end, q->size - end);
    free(q->owned);
    q->owned = text;
    q->text = text;
    q->size += 2;
    q->ends[q->count++] = end + 2;
    return true;
}

/* jansson counted columns in the rewritten text; quotes we added earlier on the line are not the user's. */
static int original_column(const quoted_text* q, const json_error_t* jerr)
{
    size_t position = error_offset(jerr, q->size);
    int column = jerr->column;
    for (size_t i = 0; i < q->count; i++) {
        size_t end = q->ends[i];
        if (end <= position && !memchr(q->text + end, '\n', position - end))
            column -= 2;
    }
    return column;
}

/* JSON has no NaN or Infinity. Quoting such a bare word and parsing again lets the number reader
   report it with its key path ("dt: must be a finite number, got NaN") instead of a syntax error. */
json_t* cvk_json_parse(const char* text, size_t size, json_error_t* jerr, bool* out_of_memory)
{
    quoted_text q = {.text = text, .size = size};
    json_t* root = NULL;
    size_t start = 0;
    size_t end = 0;
    *out_of_memory = false;
    for (;;) {
        root = json_loadb(q.text, q.size, json_flags, jerr);
        if (root || !find_nonfinite_word(q.text, q.size, jerr, &start, &end))
            break;
        if (!quote_word(&q, start, end)) {
            *out_of_memory = true;
            break;
        }
    }
    /* jansson leaves the error blank (line -1, no text) when one of its own allocations fails. */
    bool blank = jerr->line < 0 && jerr->text[0] == '\0';
    if (!root && (json_error_code(jerr) == json_error_out_of_memory || blank))
        *out_of_memory = true;
    if (!root)
        jerr->column = original_column(&q, jerr);
    free(q.owned);
    free(q.ends);
    return root;
}
