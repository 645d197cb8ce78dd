/* What the command-line tools share: messages, number parsing, --set collection, atomic
   file output and the validation-message hook. */
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

/* Log callback for cvk_context_desc: prints validation messages as "tool: validation: ...". */
void app_log_validation(void* tool_name, const char* message);

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
