/* What the command-line tools share that needs no library: messages, whole numbers, --set
   collection and the command line read by a table of options. clothvk-ab, which opens builds
   of the library at run time and must not link one, uses it as the other tools do; common.h
   adds what a run needs of the library. */
#ifndef CVK_APP_CLI_H
#define CVK_APP_CLI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* Exit statuses of every tool. */
enum {
    APP_EXIT_OK = 0,
    APP_EXIT_FAILURE = 1,   /* the run failed (device error, NaN in the result, validation) */
    APP_EXIT_BAD_INPUT = 2, /* bad arguments or scene; nothing was written */
    APP_EXIT_DIVERGED = 3,  /* the simulation blew up (the library's divergence watch) */
};

/* Prints "tool: message" on stderr, one line: control characters in the message (from file
   names, keys or scene names a user wrote: an ESC sequence, a CR or LF forging a line) are
   written as \xNN. */
void app_error(const char* tool, const char* format, ...) __attribute__((format(printf, 2, 3)));

/* Writes text with control characters as \xNN, as app_error does. */
void app_put_escaped(FILE* out, const char* text);

/* An argument no option of the tool took: the scene file when it is the first such argument
 * and not an option; otherwise one line on stderr and APP_EXIT_BAD_INPUT. */
int app_take_scene_argument(const char* tool, const char* arg, const char** scene);

/* Parses a whole decimal number in [min, max]; false on anything else. */
bool app_parse_u32(const char* text, uint32_t min, uint32_t max, uint32_t* out);

/* Collected --set overrides. */
typedef struct app_overrides {
    const char** items;
    uint32_t count;
} app_overrides;

/* Appends item (not copied) to the growing list *items of *count; no memory for it prints one
 * line and returns APP_EXIT_FAILURE. */
int app_strings_add(const char*** items, uint32_t* count, const char* tool, const char* item);
/* Adds one --set item; an item without "key.path=" or no memory for it prints one line and
 * returns APP_EXIT_BAD_INPUT or APP_EXIT_FAILURE. */
int app_overrides_add(app_overrides* o, const char* tool, const char* item);
void app_overrides_free(app_overrides* o);

/* ---- the command line -------------------------------------------------------------------- */

/* What an option does with the argument after it. */
typedef enum app_option_kind {
    APP_OPTION_FLAG,  /* takes no value: sets *flag */
    APP_OPTION_U32,   /* a whole number in [min, max] into *number; sets *flag (if any) */
    APP_OPTION_PATH,  /* a file or folder name into *path */
    APP_OPTION_SET,   /* key.path=value, added to *overrides */
    APP_OPTION_OTHER, /* take() reads the value */
} app_option_kind;

/* One row of a tool's option table. A value is the next argument, whatever it looks like, or
   what follows the '=' of a long option written GNU style ("--frames=2"). */
typedef struct app_option {
    const char* name;
    const char* alias;        /* a second name ("-q" for "--quiet"), or NULL */
    app_option_kind kind;
    bool* flag;               /* FLAG: set; U32: set when given, or NULL */
    uint32_t* number;         /* U32 */
    uint32_t min, max;        /* U32: the range; max UINT32_MAX reads "of at least MIN" */
    const char** path;        /* PATH */
    const char* expected;     /* PATH: the message when it is missing, "a file name" */
    bool empty_ok;            /* PATH: an empty name is taken (writing it fails later) */
    app_overrides* overrides; /* SET */
    /* OTHER: value is NULL when the option is the last argument; returns an APP_EXIT status
       (after one line on stderr when not APP_EXIT_OK). */
    int (*take)(void* user, const char* option, const char* value);
} app_option;

/* A tool's command line: its options and what --help prints. */
typedef struct app_command_line {
    const char* tool;
    void (*usage)(FILE* out);
    const app_option* options;
    size_t option_count;
    void* user;               /* passed to the OTHER options' take() and take_argument() */
    /* The arguments no option takes, in order (an unknown option is refused before); NULL: the
       one scene file, which the line must have. Returns an APP_EXIT status as take() does. */
    int (*take_argument)(void* user, const char* arg);
} app_command_line;

/* A long option written "--name=value": the length of "--name" and the value after the first
   '='. Any other argument: its whole length and NULL. */
const char* app_option_split(const char* arg, size_t* name_length);

/* Reads argv by the table, left to right. --help or -h prints the usage on stdout, --version
 * the version; either sets *done and ends the reading. The one argument no option takes is the
 * scene file (unless the line has take_argument); without one the usage goes to stderr. Returns APP_EXIT_OK, or after one line on
 * stderr APP_EXIT_BAD_INPUT (APP_EXIT_FAILURE when memory runs out). */
int app_read_command_line(const app_command_line* line, int argc, char** argv, const char** scene,
                          bool* done);

/* --help or -h prints `usage` on stdout, --version "tool VERSION" (the project's version, that
   of the library built with the tools); true for those three. */
bool app_help_or_version(const char* tool, const char* arg, void (*usage)(FILE* out));

/* A whole-number option's value in [min, max] into *out; otherwise one line "tool: OPTION:
 * expected a whole number from MIN to MAX, got VALUE" ("of at least MIN" when max is
 * UINT32_MAX, VALUE "nothing" when NULL) and false. */
bool app_option_u32(const char* tool, const char* option, const char* value, uint32_t min,
                    uint32_t max, uint32_t* out);

#endif
