/* JSON scene text → cvk_scene_desc. Every message starts with the file name, then the key path
   (the same path --set takes), then the problem. */
#include "scene.h"

#include "error.h"

#include <errno.h>
#include <float.h>
#include <inttypes.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

struct cvk_scene {
    cvk_scene_desc desc;
    void** blocks;          /* every allocation desc points into, freed together */
    size_t block_count;
    size_t block_capacity;
};

/* ---- ownership: everything the description points to is a block of its scene ---- */

static void* scene_keep(cvk_scene* scene, void* block)
{
    if (!block)
        return NULL;
    if (scene->block_count == scene->block_capacity) {
        size_t capacity = scene->block_capacity ? 2 * scene->block_capacity : 16;
        void** blocks = realloc(scene->blocks, capacity * sizeof *blocks);
        if (!blocks) {
            free(block);
            return NULL;
        }
        scene->blocks = blocks;
        scene->block_capacity = capacity;
    }
    scene->blocks[scene->block_count++] = block;
    return block;
}

static void* scene_alloc(cvk_scene* scene, size_t count, size_t size)
{
    return scene_keep(scene, calloc(count, size));
}

void cvk_scene_destroy(cvk_scene* scene)
{
    if (!scene)
        return;
    for (size_t i = 0; i < scene->block_count; i++)
        free(scene->blocks[i]);
    free(scene->blocks);
    free(scene);
}

const cvk_scene_desc* cvk_scene_get_desc(const cvk_scene* scene)
{
    return scene ? &scene->desc : NULL;
}

/* ---- messages ---- */

/* State of one conversion: where messages go and which key paths the overrides wrote. */
typedef struct reader {
    cvk_scene* scene;
    const char* source;                  /* file name (or source_name) that starts every message */
    char (*set_paths)[CVK_KEY_PATH_MAX]; /* key paths the overrides wrote, indices normalised */
    uint32_t set_count;
    cvk_error* error;
} reader;

/* true when path is prefix or lies under it ("cloths.0.mass" under "cloths.0"). */
static bool path_within(const char* path, const char* prefix)
{
    size_t n = strlen(prefix);
    return n > 0 && strncmp(path, prefix, n) == 0 && (path[n] == '\0' || path[n] == '.');
}

/* A bad value under an overridden path, or one with an overridden part, came from --set. */
static bool from_override(const reader* rd, const char* path)
{
    for (uint32_t i = 0; i < rd->set_count; i++) {
        if (path_within(path, rd->set_paths[i]) || path_within(rd->set_paths[i], path))
            return true;
    }
    return false;
}

static cvk_result fail_problem(reader* rd, const char* path, const char* problem)
{
    if (path[0] == '\0')
        return cvk_fail(rd->error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s", rd->source, problem);
    const char* origin = from_override(rd, path) ? " (from --set)" : "";
    return cvk_fail(rd->error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s%s: %s", rd->source, path, origin, problem);
}

__attribute__((format(printf, 3, 4)))
static cvk_result fail_at(reader* rd, const char* path, const char* format, ...)
{
    char problem[384];
    va_list args;
    va_start(args, format);
    vsnprintf(problem, sizeof problem, format, args);
    va_end(args);
    return fail_problem(rd, path, problem);
}

static cvk_result fail_memory(reader* rd)
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

/* What the reader found where it expected something else: "a string", "an array of 2", "NaN". */
static const char* describe(const json_t* value, char* buffer, size_t size)
{
    switch (json_typeof(value)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY:
        snprintf(buffer, size, "an array of %zu", json_array_size(value));
        return buffer;
    case JSON_STRING:
        /* A quoted bare NaN or Infinity (see parse_json) is named as the user wrote it. */
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
        snprintf(buffer, size, "the number %g", json_number_value(value));
        return buffer;
    case JSON_TRUE: return "true";
    case JSON_FALSE: return "false";
    case JSON_NULL: return "null";
    }
    return "an unknown value";
}

static cvk_result fail_type(reader* rd, const char* path, const char* expected, const json_t* value)
{
    char buffer[48];
    return fail_at(rd, path, "expected %s, got %s", expected, describe(value, buffer, sizeof buffer));
}

static void join_key(char out[CVK_KEY_PATH_MAX], const char* path, const char* key)
{
    cvk_key_path(out, "%s%s%s", path, path[0] ? "." : "", key);
}

static void join_index(char out[CVK_KEY_PATH_MAX], const char* path, size_t index)
{
    cvk_key_path(out, "%s.%zu", path, index);
}

/* ---- value readers: one per kind of key, each writes where its table entry points ---- */

typedef struct field field;
typedef struct table table;
typedef cvk_result (*read_fn)(reader* rd, const field* f, json_t* value, const char* path, void* dest);

struct field {
    const char* key;
    read_fn read;
    size_t offset;        /* where the value goes in the destination struct */
    uint32_t count;       /* array readers: number of elements */
    uint32_t min;         /* whole-number readers: least valid value, named when a value is negative */
    const table* nested;  /* object readers: the nested object's keys */
    const char* required; /* set: the key must be present, and this says why */
};

struct table {
    const field* fields;
    size_t count;
};

static cvk_result read_string(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    if (!json_is_string(value))
        return fail_type(rd, path, "a string", value);
    char* text = scene_keep(rd->scene, strdup(json_string_value(value)));
    if (!text)
        return fail_memory(rd);
    *(const char**)dest = text;
    return CVK_SUCCESS;
}

static cvk_result read_bool(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    if (!json_is_boolean(value))
        return fail_type(rd, path, "true or false", value);
    *(bool*)dest = json_is_true(value);
    return CVK_SUCCESS;
}

/* Out of float range becomes ±inf, which validation reports as not finite. */
static float to_float(double v)
{
    if (v > FLT_MAX)
        return INFINITY;
    if (v < -FLT_MAX)
        return -INFINITY;
    return (float)v;
}

static cvk_result read_float(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    if (json_is_string(value) && is_nonfinite_word(json_string_value(value), json_string_length(value)))
        return fail_at(rd, path, "must be a finite number, got %s", json_string_value(value));
    if (!json_is_number(value))
        return fail_type(rd, path, "a number", value);
    *(float*)dest = to_float(json_number_value(value));
    return CVK_SUCCESS;
}

/* Integral reals (8.0) are accepted: some tools write every number as a real. */
static cvk_result read_uint(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    if (!json_is_number(value))
        return fail_type(rd, path, "a whole number", value);
    double v = json_number_value(value);
    if (v != floor(v))
        return fail_at(rd, path, "expected a whole number, got %g", v);
    if (v < 0)
        return fail_at(rd, path, "must be at least %" PRIu32 ", got %g", f->min, v);
    if (v > UINT32_MAX)
        return fail_at(rd, path, "must be at most %" PRIu32 ", got %g", UINT32_MAX, v);
    *(uint32_t*)dest = (uint32_t)v;
    return CVK_SUCCESS;
}

static cvk_result read_array(reader* rd, const field* f, json_t* value, const char* path, void* dest,
                             const char* noun, read_fn read_element, size_t element_size)
{
    if (!json_is_array(value) || json_array_size(value) != f->count) {
        char expected[64];
        snprintf(expected, sizeof expected, "an array of %" PRIu32 " %s", f->count, noun);
        return fail_type(rd, path, expected, value);
    }
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < f->count; i++) {
        join_index(element, path, i);
        cvk_result r = read_element(rd, f, json_array_get(value, i), element, (char*)dest + i * element_size);
        if (r != CVK_SUCCESS)
            return r;
    }
    return CVK_SUCCESS;
}

static cvk_result read_floats(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    return read_array(rd, f, value, path, dest, "numbers", read_float, sizeof(float));
}

static cvk_result read_uints(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    return read_array(rd, f, value, path, dest, "whole numbers", read_uint, sizeof(uint32_t));
}

/* "a, b, c or d" from an enum's name function, which returns NULL past the last value. */
static void list_names(const char* (*name_of)(int), char* out, size_t size)
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

static cvk_result read_enum(reader* rd, json_t* value, const char* path, const char* what,
                            const char* (*name_of)(int), int* out)
{
    if (!json_is_string(value))
        return fail_type(rd, path, "a string", value);
    const char* text = json_string_value(value);
    for (int v = 0; name_of(v); v++) {
        if (strcmp(text, name_of(v)) == 0) {
            *out = v;
            return CVK_SUCCESS;
        }
    }
    char names[256];
    list_names(name_of, names, sizeof names);
    return fail_at(rd, path, "unknown %s \"%s\" (expected %s)", what, text, names);
}

static const char* method_name(int v)
{
    return cvk_method_name((cvk_method)v);
}

static const char* linear_name(int v)
{
    return cvk_linear_solver_name((cvk_linear_solver)v);
}

static cvk_result read_method(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    int v = 0;
    cvk_result r = read_enum(rd, value, path, "method", method_name, &v);
    if (r == CVK_SUCCESS)
        *(cvk_method*)dest = (cvk_method)v;
    return r;
}

static cvk_result read_linear(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    int v = 0;
    cvk_result r = read_enum(rd, value, path, "linear solver", linear_name, &v);
    if (r == CVK_SUCCESS)
        *(cvk_linear_solver*)dest = (cvk_linear_solver)v;
    return r;
}

/* ---- objects: every key must be in the table; keys are read in the order the file has them ---- */

static const field* find_field(const table* t, const char* key)
{
    for (size_t i = 0; i < t->count; i++) {
        if (strcmp(t->fields[i].key, key) == 0)
            return &t->fields[i];
    }
    return NULL;
}

static void list_keys(const table* t, char* out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (size_t i = 0; i < t->count && used < size; i++)
        used += (size_t)snprintf(out + used, size - used, "%s%s", i ? ", " : "", t->fields[i].key);
}

static cvk_result check_required(reader* rd, const table* t, json_t* object, const char* path)
{
    char child[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < t->count; i++) {
        const field* f = &t->fields[i];
        if (!f->required || json_object_get(object, f->key))
            continue;
        join_key(child, path, f->key);
        return fail_at(rd, child, "missing; %s", f->required);
    }
    return CVK_SUCCESS;
}

static cvk_result read_object(reader* rd, const table* t, json_t* object, const char* path, void* dest)
{
    if (!json_is_object(object))
        return fail_type(rd, path, "an object", object);
    const char* key;
    json_t* value;
    json_object_foreach(object, key, value) {
        char child[CVK_KEY_PATH_MAX];
        join_key(child, path, key);
        const field* f = find_field(t, key);
        if (!f) {
            char keys[320];
            list_keys(t, keys, sizeof keys);
            return fail_at(rd, child, "unknown key (expected one of: %s)", keys);
        }
        cvk_result r = f->read(rd, f, value, child, (char*)dest + f->offset);
        if (r != CVK_SUCCESS)
            return r;
    }
    return check_required(rd, t, object, path);
}

static cvk_result read_nested(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    return read_object(rd, f->nested, value, path, dest);
}

static const field pin_field = {.key = "pins", .read = read_uints, .count = 2, .min = 0};

/* dest is the whole cloth: pins and pin_count go together. */
static cvk_result read_pins(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    cvk_cloth_desc* cloth = dest;
    if (!json_is_array(value))
        return fail_type(rd, path, "an array of [i, j] pairs", value);
    size_t count = json_array_size(value);
    cloth->pins = NULL;
    cloth->pin_count = 0;
    if (count == 0)
        return CVK_SUCCESS;
    if (count > UINT32_MAX)
        return fail_at(rd, path, "more than %" PRIu32 " pins", UINT32_MAX);
    uint32_t (*pins)[2] = scene_alloc(rd->scene, count, sizeof *pins);
    if (!pins)
        return fail_memory(rd);
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < count; i++) {
        join_index(element, path, i);
        cvk_result r = read_uints(rd, &pin_field, json_array_get(value, i), element, pins[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    cloth->pins = (const uint32_t(*)[2])pins;
    cloth->pin_count = (uint32_t)count;
    return CVK_SUCCESS;
}

#define FIELDS(array) {array, sizeof array / sizeof array[0]}

static const field stiffness_fields[] = {
    {.key = "structural", .read = read_float, .offset = offsetof(cvk_stiffness, structural)},
    {.key = "shear", .read = read_float, .offset = offsetof(cvk_stiffness, shear)},
    {.key = "bend", .read = read_float, .offset = offsetof(cvk_stiffness, bend)},
};
static const table stiffness_table = FIELDS(stiffness_fields);

static const field cloth_fields[] = {
    {.key = "name", .read = read_string, .offset = offsetof(cvk_cloth_desc, name)},
    {.key = "grid", .read = read_uints, .offset = offsetof(cvk_cloth_desc, grid), .count = 2, .min = 1},
    {.key = "size", .read = read_floats, .offset = offsetof(cvk_cloth_desc, size), .count = 2},
    {.key = "origin", .read = read_floats, .offset = offsetof(cvk_cloth_desc, origin), .count = 3},
    {.key = "u_axis", .read = read_floats, .offset = offsetof(cvk_cloth_desc, u_axis), .count = 3},
    {.key = "v_axis", .read = read_floats, .offset = offsetof(cvk_cloth_desc, v_axis), .count = 3},
    {.key = "rest_scale", .read = read_float, .offset = offsetof(cvk_cloth_desc, rest_scale)},
    {.key = "mass", .read = read_float, .offset = offsetof(cvk_cloth_desc, mass)},
    {.key = "stiffness", .read = read_nested, .offset = offsetof(cvk_cloth_desc, stiffness),
     .nested = &stiffness_table},
    {.key = "pins", .read = read_pins, .offset = 0},
    {.key = "color", .read = read_floats, .offset = offsetof(cvk_cloth_desc, color), .count = 3},
};
static const table cloth_table = FIELDS(cloth_fields);

/* dest is the whole scene: cloths and cloth_count go together. */
static cvk_result read_cloths(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    (void)f;
    cvk_scene_desc* desc = dest;
    if (!json_is_array(value))
        return fail_type(rd, path, "an array of cloth objects", value);
    size_t count = json_array_size(value);
    if (count == 0)
        return CVK_SUCCESS; /* validation says that a scene needs a cloth */
    if (count > UINT32_MAX)
        return fail_at(rd, path, "more than %" PRIu32 " cloths", UINT32_MAX);
    cvk_cloth_desc* cloths = scene_alloc(rd->scene, count, sizeof *cloths);
    if (!cloths)
        return fail_memory(rd);
    char element[CVK_KEY_PATH_MAX];
    for (size_t i = 0; i < count; i++) {
        join_index(element, path, i);
        cloths[i] = cvk_default_cloth_desc();
        cvk_result r = read_object(rd, &cloth_table, json_array_get(value, i), element, &cloths[i]);
        if (r != CVK_SUCCESS)
            return r;
    }
    desc->cloths = cloths;
    desc->cloth_count = (uint32_t)count;
    return CVK_SUCCESS;
}

static const field solver_fields[] = {
    {.key = "method", .read = read_method, .offset = offsetof(cvk_solver_desc, method)},
    {.key = "linear", .read = read_linear, .offset = offsetof(cvk_solver_desc, linear)},
    {.key = "outer_iterations", .read = read_uint, .offset = offsetof(cvk_solver_desc, outer_iterations), .min = 1},
    {.key = "inner_iterations", .read = read_uint, .offset = offsetof(cvk_solver_desc, inner_iterations), .min = 1},
    {.key = "omega", .read = read_float, .offset = offsetof(cvk_solver_desc, omega)},
    {.key = "chebyshev_rho", .read = read_float, .offset = offsetof(cvk_solver_desc, chebyshev_rho)},
    {.key = "chebyshev_delay", .read = read_uint, .offset = offsetof(cvk_solver_desc, chebyshev_delay)},
};
static const table solver_table = FIELDS(solver_fields);

/* dest is the whole render description: an explicit eye, target or ground height replaces the
   automatic one. */
static cvk_result read_eye(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    cvk_render_desc* render = dest;
    render->auto_eye = false;
    return read_floats(rd, f, value, path, render->eye);
}

static cvk_result read_target(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    cvk_render_desc* render = dest;
    render->auto_target = false;
    return read_floats(rd, f, value, path, render->target);
}

static cvk_result read_ground_height(reader* rd, const field* f, json_t* value, const char* path, void* dest)
{
    cvk_render_desc* render = dest;
    render->auto_ground_height = false;
    return read_float(rd, f, value, path, &render->ground_height);
}

static const field light_fields[] = {
    {.key = "direction", .read = read_floats, .offset = offsetof(cvk_light, direction), .count = 3},
    {.key = "color", .read = read_floats, .offset = offsetof(cvk_light, color), .count = 3},
};
static const table light_table = FIELDS(light_fields);

static const field render_fields[] = {
    {.key = "size", .read = read_uints, .offset = offsetof(cvk_render_desc, size), .count = 2, .min = 1},
    {.key = "eye", .read = read_eye, .offset = 0, .count = 3},
    {.key = "target", .read = read_target, .offset = 0, .count = 3},
    {.key = "up", .read = read_floats, .offset = offsetof(cvk_render_desc, up), .count = 3},
    {.key = "fov_y", .read = read_float, .offset = offsetof(cvk_render_desc, fov_y)},
    {.key = "key", .read = read_nested, .offset = offsetof(cvk_render_desc, key), .nested = &light_table},
    {.key = "fill", .read = read_nested, .offset = offsetof(cvk_render_desc, fill), .nested = &light_table},
    {.key = "ambient", .read = read_floats, .offset = offsetof(cvk_render_desc, ambient), .count = 3},
    {.key = "background", .read = read_floats, .offset = offsetof(cvk_render_desc, background), .count = 3},
    {.key = "ground", .read = read_bool, .offset = offsetof(cvk_render_desc, ground)},
    {.key = "ground_height", .read = read_ground_height, .offset = 0},
    {.key = "ground_color", .read = read_floats, .offset = offsetof(cvk_render_desc, ground_color), .count = 3},
    {.key = "shadow_map_size", .read = read_uint, .offset = offsetof(cvk_render_desc, shadow_map_size), .min = 16},
    {.key = "samples", .read = read_uint, .offset = offsetof(cvk_render_desc, samples), .min = 1},
};
static const table render_table = FIELDS(render_fields);

static const field scene_fields[] = {
    {.key = "name", .read = read_string, .offset = offsetof(cvk_scene_desc, name)},
    {.key = "dt", .read = read_float, .offset = offsetof(cvk_scene_desc, dt)},
    {.key = "substeps", .read = read_uint, .offset = offsetof(cvk_scene_desc, substeps), .min = 1},
    {.key = "frames", .read = read_uint, .offset = offsetof(cvk_scene_desc, frames), .min = 1},
    {.key = "integrate", .read = read_bool, .offset = offsetof(cvk_scene_desc, integrate)},
    {.key = "gravity", .read = read_floats, .offset = offsetof(cvk_scene_desc, gravity), .count = 3},
    {.key = "damping", .read = read_float, .offset = offsetof(cvk_scene_desc, damping)},
    {.key = "solver", .read = read_nested, .offset = offsetof(cvk_scene_desc, solver), .nested = &solver_table},
    {.key = "cloths", .read = read_cloths, .offset = 0, .required = "a scene needs at least one cloth"},
    {.key = "render", .read = read_nested, .offset = offsetof(cvk_scene_desc, render), .nested = &render_table},
};
static const table scene_table = FIELDS(scene_fields);

/* ---- JSON text, with bare NaN and Infinity accepted as strings ---- */

enum { json_flags = JSON_REJECT_DUPLICATES | JSON_DECODE_ANY };

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
static json_t* parse_json(const char* text, size_t size, json_error_t* jerr, bool* out_of_memory)
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

static cvk_result load_root(reader* rd, const char* text, size_t size, json_t** out_root)
{
    json_error_t jerr;
    bool out_of_memory = false;
    json_t* root = parse_json(text, size, &jerr, &out_of_memory);
    if (out_of_memory)
        return fail_memory(rd);
    if (!root)
        return cvk_fail(rd->error, CVK_ERROR_PARSE, "%s:%d:%d: malformed JSON: %s", rd->source, jerr.line,
                        jerr.column, jerr.text);
    if (!json_is_object(root)) {
        char buffer[48];
        cvk_result r = fail_at(rd, "", "the top level must be an object, got %s",
                               describe(root, buffer, sizeof buffer));
        json_decref(root);
        return r;
    }
    *out_root = root;
    return CVK_SUCCESS;
}

/* ---- overrides: "key.path=value" applied to the tree before conversion ---- */

/* One --set being applied. */
typedef struct walk {
    reader* rd;
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
    join_key(joined, w->normalised, key);
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
            return fail_memory(w->rd);
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
            return fail_memory(w->rd);
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
    return failed ? fail_memory(w->rd) : CVK_SUCCESS;
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
   shell-stripped `--set solver.linear=jacobi` works. NULL when neither works. */
static json_t* parse_override_value(const char* text, bool* out_of_memory)
{
    json_error_t jerr;
    json_t* value = parse_json(text, strlen(text), &jerr, out_of_memory);
    if (value || *out_of_memory)
        return value;
    return json_string(text);
}

static cvk_result apply_override(reader* rd, json_t* root, const char* text)
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
    bool out_of_memory = false;
    json_t* value = parse_override_value(equals + 1, &out_of_memory);
    if (!value)
        return out_of_memory ? fail_memory(rd) : fail_walk(&w, "the value is neither JSON nor UTF-8 text");
    cvk_result r = set_path(&w, root, value);
    if (r == CVK_SUCCESS)
        memcpy(rd->set_paths[rd->set_count++], w.normalised, sizeof w.normalised);
    return r;
}

/* ---- the whole conversion ---- */

/* "scenes/hanging.json" → "hanging": a scene without a name takes its file's. */
static cvk_result set_default_name(reader* rd)
{
    const char* base = strrchr(rd->source, '/');
    base = base ? base + 1 : rd->source;
    const char* dot = strrchr(base, '.');
    size_t length = dot && dot != base ? (size_t)(dot - base) : strlen(base);
    char* name = scene_keep(rd->scene, strndup(base, length));
    if (!name)
        return fail_memory(rd);
    rd->scene->desc.name = name;
    return CVK_SUCCESS;
}

static cvk_result convert(reader* rd, json_t* root, bool name_from_source, const char* const* overrides,
                          uint32_t override_count)
{
    cvk_result r = CVK_SUCCESS;
    for (uint32_t i = 0; i < override_count && r == CVK_SUCCESS; i++)
        r = apply_override(rd, root, overrides[i]);
    if (r == CVK_SUCCESS && name_from_source)
        r = set_default_name(rd);
    if (r == CVK_SUCCESS)
        r = read_object(rd, &scene_table, root, "", &rd->scene->desc);
    if (r != CVK_SUCCESS)
        return r;
    cvk_scene_issue issue;
    if (!cvk_scene_desc_check(&rd->scene->desc, &issue))
        return fail_problem(rd, issue.path, issue.problem);
    return CVK_SUCCESS;
}

static cvk_result build_scene(reader* rd, const char* text, size_t size, bool name_from_source,
                              const char* const* overrides, uint32_t override_count)
{
    json_t* root = NULL;
    cvk_result r = load_root(rd, text, size, &root);
    if (r != CVK_SUCCESS)
        return r;
    r = convert(rd, root, name_from_source, overrides, override_count);
    json_decref(root);
    return r;
}

static cvk_result parse_scene(const char* text, size_t size, const char* source, bool name_from_source,
                              const char* const* overrides, uint32_t override_count, cvk_scene** out_scene,
                              cvk_error* error)
{
    cvk_scene* scene = calloc(1, sizeof *scene);
    char (*set_paths)[CVK_KEY_PATH_MAX] = calloc(override_count ? override_count : 1, sizeof *set_paths);
    reader rd = {.scene = scene, .source = source, .set_paths = set_paths, .error = error};
    cvk_result r = CVK_ERROR_OUT_OF_MEMORY;
    if (!scene || !set_paths) {
        cvk_fail(error, r, "%s: out of memory", source);
    } else {
        scene->desc = cvk_default_scene_desc();
        r = build_scene(&rd, text, size, name_from_source, overrides, override_count);
    }
    free(set_paths);
    if (r != CVK_SUCCESS) {
        cvk_scene_destroy(scene);
        return r;
    }
    *out_scene = scene;
    return CVK_SUCCESS;
}

static cvk_result check_arguments(const char* call, const void* input, const char* input_name,
                                  const char* const* overrides, uint32_t override_count, cvk_scene** out_scene,
                                  cvk_error* error)
{
    if (!out_scene)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: out_scene is NULL", call);
    *out_scene = NULL;
    if (!input)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s is NULL", call, input_name);
    if (override_count > 0 && !overrides)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: overrides is NULL but override_count is %" PRIu32,
                        call, override_count);
    for (uint32_t i = 0; i < override_count; i++) {
        if (!overrides[i])
            return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: overrides[%" PRIu32 "] is NULL", call, i);
    }
    return CVK_SUCCESS;
}

/* ---- files ---- */

/* Reads to the end rather than trusting a size from fseek, so pipes and /dev/stdin work. */
static cvk_result read_stream(FILE* file, const char* path, char** out_text, size_t* out_size, cvk_error* error)
{
    char* text = NULL;
    size_t size = 0;
    size_t capacity = 0;
    for (;;) {
        if (size == capacity) {
            capacity = capacity ? 2 * capacity : 65536;
            char* grown = realloc(text, capacity);
            if (!grown) {
                free(text);
                return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
            }
            text = grown;
        }
        size_t got = fread(text + size, 1, capacity - size, file);
        size += got;
        if (got > 0)
            continue;
        if (!ferror(file))
            break;
        int code = errno;
        free(text);
        return cvk_fail_errno(error, path, "cannot read", code);
    }
    *out_text = text;
    *out_size = size;
    return CVK_SUCCESS;
}

cvk_result cvk_scene_load(const char* path, const char* const* overrides, uint32_t override_count,
                          cvk_scene** out_scene, cvk_error* error)
{
    cvk_result r = check_arguments("cvk_scene_load", path, "path", overrides, override_count, out_scene, error);
    if (r != CVK_SUCCESS)
        return r;
    FILE* file = fopen(path, "rb");
    if (!file)
        return cvk_fail_errno(error, path, "cannot open", errno);
    char* text = NULL;
    size_t size = 0;
    r = read_stream(file, path, &text, &size, error);
    fclose(file);
    if (r != CVK_SUCCESS)
        return r;
    r = parse_scene(text, size, path, true, overrides, override_count, out_scene, error);
    free(text);
    return r;
}

cvk_result cvk_scene_parse(const char* json_text, const char* source_name, const char* const* overrides,
                           uint32_t override_count, cvk_scene** out_scene, cvk_error* error)
{
    cvk_result r =
        check_arguments("cvk_scene_parse", json_text, "json_text", overrides, override_count, out_scene, error);
    if (r != CVK_SUCCESS)
        return r;
    const char* source = source_name ? source_name : "<string>";
    return parse_scene(json_text, strlen(json_text), source, source_name != NULL, overrides, override_count,
                       out_scene, error);
}
