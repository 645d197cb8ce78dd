/* Checks shared by the scene tests (test_scene.c, test_scene_mesh.c): CHECK_* print the fact
   that failed with the actual and expected values; JSON helpers parse text written with ' for "
   and compare error messages exactly. Header-only, included by one file per test program. */
#ifndef CVK_TEST_SCENE_CHECKS_H
#define CVK_TEST_SCENE_CHECKS_H

#include "clothvk.h"

#include <stdbool.h>
#include <stdio.h>
#include <string.h>

/* ---- checking ---- */

typedef struct tally {
    int checks;
    int failures;
} tally;

static tally T;

static inline void check_true(bool ok, const char* fact, const char* file, int line)
{
    T.checks++;
    if (ok)
        return;
    T.failures++;
    printf("%s:%d: FAILED: %s\n", file, line, fact);
}

static inline void check_str(const char* actual, const char* expected, const char* fact, const char* file, int line)
{
    bool same = actual && expected ? strcmp(actual, expected) == 0 : actual == expected;
    check_true(same, fact, file, line);
    if (!same)
        printf("    actual:   %s%s%s\n    expected: %s%s%s\n", actual ? "\"" : "", actual ? actual : "NULL",
               actual ? "\"" : "", expected ? "\"" : "", expected ? expected : "NULL", expected ? "\"" : "");
}

static inline void check_int(long long actual, long long expected, const char* fact, const char* file, int line)
{
    check_true(actual == expected, fact, file, line);
    if (actual != expected)
        printf("    actual:   %lld\n    expected: %lld\n", actual, expected);
}

static inline void check_float(double actual, double expected, const char* fact, const char* file, int line)
{
    check_true(actual == expected, fact, file, line);
    if (actual != expected)
        printf("    actual:   %.9g\n    expected: %.9g\n", actual, expected);
}

#define CHECK(cond) check_true((cond), #cond, __FILE__, __LINE__)
#define CHECK_STR(actual, expected) check_str((actual), (expected), #actual, __FILE__, __LINE__)
#define CHECK_INT(actual, expected) check_int((long long)(actual), (long long)(expected), #actual, __FILE__, __LINE__)
#define CHECK_FLOAT(actual, expected) check_float((actual), (expected), #actual, __FILE__, __LINE__)

/* ---- helpers: JSON inputs are written with ' for " so they stay readable ---- */

typedef struct text {
    char data[8192];
} text;

static inline text json(const char* single_quoted)
{
    text t;
    snprintf(t.data, sizeof t.data, "%s", single_quoted);
    for (char* c = t.data; *c; c++) {
        if (*c == '\'')
            *c = '"';
    }
    return t;
}

/* Parses as "t.json"; on failure reports the message and returns NULL. */
static inline cvk_scene* parse_ok_at(const char* file, int line, const char* single_quoted, const char* const* sets,
                              uint32_t set_count)
{
    text t = json(single_quoted);
    cvk_scene* scene = NULL;
    cvk_error err = {0};
    cvk_result r = cvk_scene_parse(t.data, "t.json", sets, set_count, &scene, &err);
    check_true(r == CVK_SUCCESS && scene, single_quoted, file, line);
    if (r != CVK_SUCCESS)
        printf("    %s: %s\n", cvk_result_name(r), err.message);
    return scene;
}

static inline void expect_error_at(const char* file, int line, const char* single_quoted, const char* const* sets,
                            uint32_t set_count, cvk_result result, const char* message)
{
    text t = json(single_quoted);
    cvk_scene* scene = (cvk_scene*)&t; /* must be reset to NULL on failure */
    cvk_error err = {0};
    cvk_result r = cvk_scene_parse(t.data, "t.json", sets, set_count, &scene, &err);
    check_int(r, result, single_quoted, file, line);
    check_int(err.result, result, "error.result", file, line);
    check_str(err.message, message, single_quoted, file, line);
    check_true(scene == NULL, "out_scene is NULL after a failure", file, line);
    if (r == CVK_SUCCESS && scene != (cvk_scene*)&t)
        cvk_scene_destroy(scene);
}

#define PARSE_OK(json_text) parse_ok_at(__FILE__, __LINE__, json_text, NULL, 0)
#define PARSE_OK_SET(json_text, sets) parse_ok_at(__FILE__, __LINE__, json_text, sets, sizeof sets / sizeof sets[0])
#define EXPECT_ERROR(json_text, result, message) \
    expect_error_at(__FILE__, __LINE__, json_text, NULL, 0, result, message)
#define EXPECT_SET_ERROR(json_text, set, message)                                                          \
    expect_error_at(__FILE__, __LINE__, json_text, (const char* const[]){set}, 1, CVK_ERROR_INVALID_ARGUMENT, \
                    message)
#define EXPECT_INVALID(json_text, message) EXPECT_ERROR(json_text, CVK_ERROR_INVALID_ARGUMENT, message)

/* A scene with one cloth, both from the defaults. */
typedef struct fixture {
    cvk_scene_desc scene;
    cvk_cloth_desc cloths[3];
} fixture;

static inline void fixture_init(fixture* f)
{
    f->scene = cvk_default_scene_desc();
    for (int i = 0; i < 3; i++)
        f->cloths[i] = cvk_default_cloth_desc();
    f->scene.cloths = f->cloths;
    f->scene.cloth_count = 1;
}

static inline void expect_invalid_at(const char* file, int line, const cvk_scene_desc* desc, const char* message)
{
    cvk_error err = {0};
    cvk_result r = cvk_scene_desc_validate(desc, &err);
    check_int(r, CVK_ERROR_INVALID_ARGUMENT, message, file, line);
    check_str(err.message, message, "validation message", file, line);
}

static inline void expect_valid_at(const char* file, int line, const cvk_scene_desc* desc)
{
    cvk_error err = {0};
    cvk_result r = cvk_scene_desc_validate(desc, &err);
    check_true(r == CVK_SUCCESS, "description is valid", file, line);
    if (r != CVK_SUCCESS)
        printf("    %s\n", err.message);
}

#define EXPECT_DESC_INVALID(desc, message) expect_invalid_at(__FILE__, __LINE__, desc, message)
#define EXPECT_DESC_VALID(desc) expect_valid_at(__FILE__, __LINE__, desc)

/* ---- files ---- */

static inline bool write_file(const char* path, const char* contents)
{
    FILE* f = fopen(path, "wb");
    if (!f)
        return false;
    bool ok = fputs(contents, f) >= 0;
    return fclose(f) == 0 && ok;
}

#endif
