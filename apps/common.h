/* What the command-line tools share: messages, the command line (a table of options), number
   parsing, --set collection, the scene and context every run starts with, atomic file output
   and the validation-message hook. */
#ifndef CVK_APP_COMMON_H
#define CVK_APP_COMMON_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "clothvk.h"

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

/* The exit status for a failed creation: scene problems found only when the scene is built
 * (a mesh file missing or malformed, too many particles for the device, a size above its
 * limit) are bad input, the rest a failure. */
int app_creation_status(cvk_result r);

/* Prints the simulation's notes (cvk_sim_note) on stderr, one line "tool: note: ..." each. */
void app_print_notes(const char* tool, const cvk_sim* sim);

/* Parses a whole decimal number in [min, max]; false on anything else. */
bool app_parse_u32(const char* text, uint32_t min, uint32_t max, uint32_t* out);

/* Collected --set overrides. */
typedef struct app_overrides {
    const char** items;
    uint32_t count;
} app_overrides;

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
    void* user;               /* passed to the OTHER options' take() */
} app_command_line;

/* A long option written "--name=value": the length of "--name" and the value after the first
   '='. Any other argument: its whole length and NULL. */
const char* app_option_split(const char* arg, size_t* name_length);

/* Reads argv by the table, left to right. --help or -h prints the usage on stdout, --version
 * the version; either sets *done and ends the reading. The one argument no option takes is the
 * scene file; without one the usage goes to stderr. Returns APP_EXIT_OK, or after one line on
 * stderr APP_EXIT_BAD_INPUT (APP_EXIT_FAILURE when memory runs out). */
int app_read_command_line(const app_command_line* line, int argc, char** argv, const char** scene,
                          bool* done);

/* --help or -h prints `usage` on stdout, --version "tool VERSION"; true for those three. */
bool app_help_or_version(const char* tool, const char* arg, void (*usage)(FILE* out));

/* A whole-number option's value in [min, max] into *out; otherwise one line "tool: OPTION:
 * expected a whole number from MIN to MAX, got VALUE" ("of at least MIN" when max is
 * UINT32_MAX, VALUE "nothing" when NULL) and false. */
bool app_option_u32(const char* tool, const char* option, const char* value, uint32_t min,
                    uint32_t max, uint32_t* out);

/* ---- the run ------------------------------------------------------------------------------- */

/* Loads a scene file with the --set overrides. On failure one line, and APP_EXIT_BAD_INPUT
 * (APP_EXIT_FAILURE when memory ran out). */
int app_load_scene(const char* tool, const char* path, const app_overrides* overrides,
                   cvk_scene** out);

/* Log callback for cvk_context_desc: prints validation messages as "tool: validation: ...". */
void app_log_validation(void* tool_name, const char* message);

/* A context whose validation messages go to stderr (app_log_validation; `tool` must outlive
 * it). On failure one line and APP_EXIT_FAILURE. */
int app_create_context(const char* tool, cvk_context** out);

/* `status`, or APP_EXIT_FAILURE after one line "tool: N validation messages" when the context
 * received any: a run the validation layer spoke about has failed. */
int app_validation_status(const char* tool, const cvk_context* ctx, int status);

/* What a simulating run starts with: the scene (app_load_scene), then the context
 * (app_create_context). On failure neither is left to destroy. */
int app_open(const char* tool, const char* path, const app_overrides* overrides, cvk_scene** scene,
             cvk_context** ctx);

/* What it ends with: the status after app_validation_status; the context and the scene are
 * destroyed. */
int app_close(const char* tool, cvk_context* ctx, cvk_scene* scene, int status);

/* From app_catch_interrupts on, Ctrl-C or SIGTERM only sets what app_interrupted returns: the
 * tools stop between frames, so every file they wrote is whole. */
void app_catch_interrupts(void);
bool app_interrupted(void);

/* Writes a file through a temporary name in the same folder and renames it into place, so
   a reader never sees a partial file. `write` returns false on failure (errno set). On
   failure nothing is left behind and the message says why. */
typedef bool (*app_writer)(FILE* file, void* user);
bool app_write_atomic(const char* path, app_writer write, void* user, char* message,
                      size_t message_size);

/* Makes `path` and its parents where missing, then checks that the folder takes new files
   (whoever runs the tool: a probe file is made and removed). On failure prints one line,
   "tool: PATH: why", and returns false; nothing is left behind but the folders made. */
bool app_make_output_folder(const char* tool, const char* path);

/* Output files are written to a temporary name and renamed over the target, which would
   replace a device node, a FIFO or a symbolic link with a plain file (as root, --dump /dev/full
   did). Such a target is refused instead: false when `path` exists and is not a regular file
   (not following links), with the reason in `message` ("PATH: exists and is not a regular
   file ..."). */
bool app_output_replaceable(const char* path, char* message, size_t message_size);

/* The same for an option's file, checked before any work: one line "tool: OPTION PATH: ..." and
   false when it is refused. */
bool app_output_option_ok(const char* tool, const char* option, const char* path);

/* The folder part of `path`, newly allocated: "." for a bare name, "/" for a name in the root;
   NULL when memory runs out. */
char* app_folder_of(const char* path);

/* Milliseconds on a monotonic clock. */
double app_now_ms(void);

/* The most resident memory the process has used so far, bytes (getrusage's ru_maxrss). */
uint64_t app_peak_rss(void);

#endif
