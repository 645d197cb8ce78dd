/* The tools' messages, numbers, --set collection and command line (cli.h). */
#include "cli.h"

#ifndef CVK_TOOLS_VERSION
#error "the build gives the project's version as CVK_TOOLS_VERSION (apps/meson.build)"
#endif

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

void app_put_escaped(FILE* out, const char* text)
{
    for (const unsigned char* c = (const unsigned char*)text; *c; c++) {
        if (*c < 0x20 || *c == 0x7f)
            fprintf(out, "\\x%02x", *c);
        else
            fputc(*c, out);
    }
}

void app_error(const char* tool, const char* format, ...)
{
    char line[2048];
    va_list args;
    va_start(args, format);
    vsnprintf(line, sizeof line, format, args);
    va_end(args);
    fprintf(stderr, "%s: ", tool);
    app_put_escaped(stderr, line);
    fputc('\n', stderr);
}

/* An argument that looks like an option but is none of the tool's: one line, and true. */
static bool unknown_option(const char* tool, const char* arg)
{
    if (arg[0] != '-' || !arg[1])
        return false;
    app_error(tool, "unknown option %s (see --help)", arg);
    return true;
}

int app_take_scene_argument(const char* tool, const char* arg, const char** scene)
{
    if (unknown_option(tool, arg))
        return APP_EXIT_BAD_INPUT;
    if (*scene) {
        app_error(tool, "one scene file expected, got %s and %s", *scene, arg);
        return APP_EXIT_BAD_INPUT;
    }
    *scene = arg;
    return APP_EXIT_OK;
}

bool app_parse_u32(const char* text, uint32_t min, uint32_t max, uint32_t* out)
{
    if (!text || !*text || *text == '-' || *text == '+')
        return false;
    errno = 0;
    char* end = NULL;
    unsigned long long v = strtoull(text, &end, 10);
    if (errno || *end || v < min || v > max)
        return false;
    *out = (uint32_t)v;
    return true;
}

bool app_option_u32(const char* tool, const char* option, const char* value, uint32_t min,
                    uint32_t max, uint32_t* out)
{
    if (app_parse_u32(value, min, max, out))
        return true;
    const char* got = value ? value : "nothing";
    if (max == UINT32_MAX)
        app_error(tool, "%s: expected a whole number of at least %u, got %s", option, min, got);
    else
        app_error(tool, "%s: expected a whole number from %u to %u, got %s", option, min, max, got);
    return false;
}

bool app_help_or_version(const char* tool, const char* arg, void (*usage)(FILE* out))
{
    if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
        usage(stdout);
        return true;
    }
    if (!strcmp(arg, "--version")) {
        printf("%s %s\n", tool, CVK_TOOLS_VERSION);
        return true;
    }
    return false;
}

const char* app_option_split(const char* arg, size_t* name_length)
{
    const char* equals = strncmp(arg, "--", 2) == 0 ? strchr(arg, '=') : NULL;
    *name_length = equals ? (size_t)(equals - arg) : strlen(arg);
    return equals ? equals + 1 : NULL;
}

/* The row whose name or alias is the first `length` characters of arg; *name is set to that
   name or alias. */
static const app_option* find_option(const app_command_line* line, const char* arg, size_t length,
                                     const char** name)
{
    for (size_t i = 0; i < line->option_count; i++) {
        const app_option* o = &line->options[i];
        const char* names[2] = {o->name, o->alias};
        for (int k = 0; k < 2; k++) {
            if (names[k] && strlen(names[k]) == length && !strncmp(arg, names[k], length)) {
                *name = names[k];
                return o;
            }
        }
    }
    return NULL;
}

/* One option with `value`, given after '=' (inline) or the argument after it (NULL when it was
   the last); *used is set when the argument after it was taken. */
static int take_option(const app_command_line* line, const app_option* o, const char* arg,
                       const char* value, bool inline_value, bool* used)
{
    *used = value != NULL && !inline_value && o->kind != APP_OPTION_FLAG;
    switch (o->kind) {
    case APP_OPTION_FLAG:
        if (inline_value) {
            app_error(line->tool, "%s takes no value, got %s=%s", arg, arg, value);
            return APP_EXIT_BAD_INPUT;
        }
        *o->flag = true;
        return APP_EXIT_OK;
    case APP_OPTION_U32:
        if (!app_option_u32(line->tool, arg, value, o->min, o->max, o->number))
            return APP_EXIT_BAD_INPUT;
        if (o->flag)
            *o->flag = true;
        return APP_EXIT_OK;
    case APP_OPTION_PATH:
        if (!value || (!value[0] && !o->empty_ok)) {
            app_error(line->tool, "%s: expected %s", arg, o->expected);
            return APP_EXIT_BAD_INPUT;
        }
        *o->path = value;
        return APP_EXIT_OK;
    case APP_OPTION_SET:
        return app_overrides_add(o->overrides, line->tool, value ? value : "");
    case APP_OPTION_OTHER:
        return o->take(line->user, arg, value);
    }
    return APP_EXIT_BAD_INPUT;
}

/* An argument no option took: the tool's take_argument's, or else the scene file. */
static int take_argument(const app_command_line* line, const char* arg, const char** scene)
{
    if (!line->take_argument)
        return app_take_scene_argument(line->tool, arg, scene);
    return unknown_option(line->tool, arg) ? APP_EXIT_BAD_INPUT
                                           : line->take_argument(line->user, arg);
}

int app_read_command_line(const app_command_line* line, int argc, char** argv, const char** scene,
                          bool* done)
{
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
        if (app_help_or_version(line->tool, a, line->usage)) {
            *done = true;
            return APP_EXIT_OK;
        }
        size_t length = 0;
        const char* inline_value = app_option_split(a, &length);
        const char* name = NULL;
        const app_option* o = find_option(line, a, length, &name);
        const char* value = inline_value ? inline_value : i + 1 < argc ? argv[i + 1] : NULL;
        bool used = false;
        int status = o ? take_option(line, o, name, value, inline_value != NULL, &used)
                       : take_argument(line, a, scene);
        if (status != APP_EXIT_OK)
            return status;
        i += used;
    }
    if (!line->take_argument && !*scene) {
        app_error(line->tool, "no scene file given");
        line->usage(stderr);
        return APP_EXIT_BAD_INPUT;
    }
    return APP_EXIT_OK;
}

int app_strings_add(const char*** items, uint32_t* count, const char* tool, const char* item)
{
    const char** grown = realloc(*items, (*count + 1) * sizeof *grown);
    if (!grown) {
        app_error(tool, "out of memory");
        return APP_EXIT_FAILURE;
    }
    grown[(*count)++] = item;
    *items = grown;
    return APP_EXIT_OK;
}

int app_overrides_add(app_overrides* o, const char* tool, const char* item)
{
    if (!strchr(item, '=') || item[0] == '=') {
        app_error(tool, "--set %s: expected key.path=value", item);
        return APP_EXIT_BAD_INPUT;
    }
    return app_strings_add(&o->items, &o->count, tool, item);
}

void app_overrides_free(app_overrides* o)
{
    free(o->items);
    o->items = NULL;
    o->count = 0;
}
