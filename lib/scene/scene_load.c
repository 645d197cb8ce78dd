/* JSON scene text → cvk_scene: the text parsed, the overrides applied, the tables of
   scene_json.c read and the result checked; from a file or from text in memory. Every message
   starts with the file name, then the key path (the same path --set takes), then the problem. */
#include "scene/scene_read.h"

#include "core/error.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

struct cvk_scene {
    cvk_scene_desc desc;
    const char* json;  /* the text with the overrides applied, canonical (cvk_scene_get_json) */
    cvk_blocks blocks; /* everything desc and json point to */
};

void cvk_scene_destroy(cvk_scene* scene)
{
    if (!scene)
        return;
    cvk_blocks_free(&scene->blocks);
    free(scene);
}

const cvk_scene_desc* cvk_scene_get_desc(const cvk_scene* scene)
{
    return scene ? &scene->desc : NULL;
}

const char* cvk_scene_get_json(const cvk_scene* scene)
{
    return scene ? scene->json : NULL;
}

/* ---- the text ---- */

static cvk_result load_root(cvk_reader* rd, const char* text, size_t size, json_t** out_root)
{
    json_error_t jerr;
    bool out_of_memory = false;
    json_t* root = cvk_json_parse(text, size, &jerr, &out_of_memory);
    if (out_of_memory)
        return cvk_reader_fail_memory(rd);
    if (!root)
        return cvk_fail(rd->error, CVK_ERROR_PARSE, "%s:%d:%d: malformed JSON: %s", rd->source, jerr.line,
                        jerr.column, jerr.text);
    if (!json_is_object(root)) {
        char buffer[48];
        cvk_result r = cvk_reader_fail_at(rd, "", "the top level must be an object, got %s",
                                          cvk_json_describe(root, buffer, sizeof buffer));
        json_decref(root);
        return r;
    }
    *out_root = root;
    return CVK_SUCCESS;
}

/* ---- the whole conversion ---- */

/* "scenes/hanging.json" → "hanging": a scene without a name takes its file's. */
static cvk_result set_default_name(cvk_reader* rd, cvk_scene_desc* desc)
{
    const char* base = strrchr(rd->source, '/');
    base = base ? base + 1 : rd->source;
    const char* dot = strrchr(base, '.');
    size_t length = dot && dot != base ? (size_t)(dot - base) : strlen(base);
    char* name = cvk_blocks_keep(rd->blocks, strndup(base, length));
    if (!name)
        return cvk_reader_fail_memory(rd);
    desc->name = name;
    return CVK_SUCCESS;
}

static cvk_result convert(cvk_reader* rd, json_t* root, cvk_scene_desc* desc, bool name_from_source,
                          const char* const* overrides, uint32_t override_count)
{
    cvk_result r = CVK_SUCCESS;
    for (uint32_t i = 0; i < override_count && r == CVK_SUCCESS; i++)
        r = cvk_reader_apply_override(rd, root, overrides[i]);
    if (r == CVK_SUCCESS && name_from_source)
        r = set_default_name(rd, desc);
    if (r == CVK_SUCCESS)
        r = cvk_read_object(rd, &cvk_scene_table, root, "", desc);
    json_t* instances = json_object_get(root, "instances");
    if (r == CVK_SUCCESS && instances)
        r = cvk_reader_expand_instances(rd, instances, desc);
    if (r != CVK_SUCCESS)
        return r;
    cvk_scene_issue issue;
    if (!cvk_scene_desc_check(desc, &issue))
        return cvk_reader_fail_problem(rd, issue.path, issue.problem);
    return CVK_SUCCESS;
}

/* Keys sorted, no spaces, every real with the 17 digits that read back as it: two trees that
   hold the same values give the same text. */
static cvk_result keep_canonical(cvk_reader* rd, const json_t* root, const char** out_json)
{
    char* text = json_dumps(root, JSON_COMPACT | JSON_SORT_KEYS | JSON_REAL_PRECISION(17));
    *out_json = cvk_blocks_keep(rd->blocks, text);
    return *out_json ? CVK_SUCCESS : cvk_reader_fail_memory(rd);
}

static cvk_result build_scene(cvk_reader* rd, const char* text, size_t size, cvk_scene* scene,
                              bool name_from_source, const char* const* overrides, uint32_t override_count)
{
    json_t* root = NULL;
    cvk_result r = load_root(rd, text, size, &root);
    if (r != CVK_SUCCESS)
        return r;
    r = convert(rd, root, &scene->desc, name_from_source, overrides, override_count);
    if (r == CVK_SUCCESS)
        r = keep_canonical(rd, root, &scene->json);
    json_decref(root);
    return r;
}

/* What the text came from, and so what its source name means. */
typedef enum source_kind {
    SOURCE_TEXT,  /* text in memory without a name ("<string>" in messages) */
    SOURCE_NAMED, /* text in memory with a name: a scene without a name takes it */
    SOURCE_FILE,  /* a file: the same, and relative paths in it are relative to its folder */
} source_kind;

/* "scenes/hanging.json" → 7, the length of "scenes/"; 0 for "hanging.json". */
static size_t folder_length(const char* path)
{
    const char* slash = strrchr(path, '/');
    return slash ? (size_t)(slash - path) + 1 : 0;
}

static cvk_result parse_scene(const char* text, size_t size, const char* source, source_kind kind,
                              const char* const* overrides, uint32_t override_count, cvk_scene** out_scene,
                              cvk_error* error)
{
    cvk_scene* scene = calloc(1, sizeof *scene);
    char (*set_paths)[CVK_KEY_PATH_MAX] = calloc(override_count ? override_count : 1, sizeof *set_paths);
    cvk_reader rd = {.source = source, .folder_length = kind == SOURCE_FILE ? folder_length(source) : 0,
                     .set_paths = set_paths, .error = error};
    bool name_from_source = kind != SOURCE_TEXT;
    cvk_result r = CVK_ERROR_OUT_OF_MEMORY;
    if (!scene || !set_paths) {
        cvk_fail(error, r, "%s: out of memory", source);
    } else {
        scene->desc = cvk_default_scene_desc();
        rd.blocks = &scene->blocks;
        r = build_scene(&rd, text, size, scene, name_from_source, overrides, override_count);
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
    /* A device or a FIFO would be read forever or block (clothvk-sim /dev/zero); a scene is a
       file, and no scene needs more than CVK_MAX_SCENE_BYTES. */
    struct stat st;
    if (stat(path, &st) != 0)
        return cvk_fail_errno(error, path, "cannot open", errno);
    if (S_ISDIR(st.st_mode))
        return cvk_fail_errno(error, path, "cannot read", EISDIR);
    if (!S_ISREG(st.st_mode))
        return cvk_fail(error, CVK_ERROR_IO, "%s: cannot read: it is not a regular file", path);
    if ((uint64_t)st.st_size > CVK_MAX_SCENE_BYTES)
        return cvk_fail(error, CVK_ERROR_IO, "%s: %llu bytes; a scene file is at most %u", path,
                        (unsigned long long)st.st_size, CVK_MAX_SCENE_BYTES);
    FILE* file = fopen(path, "rb");
    if (!file)
        return cvk_fail_errno(error, path, "cannot open", errno);
    char* text = NULL;
    size_t size = 0;
    r = read_stream(file, path, &text, &size, error);
    fclose(file);
    if (r != CVK_SUCCESS)
        return r;
    r = parse_scene(text, size, path, SOURCE_FILE, overrides, override_count, out_scene, error);
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
    return parse_scene(json_text, strlen(json_text), source, source_name ? SOURCE_NAMED : SOURCE_TEXT, overrides,
                       override_count, out_scene, error);
}
