/* What the command-line tools share: cli.h (messages, the command line, number parsing, --set
   collection), and the scene and context every run starts with, atomic file output and the
   validation-message hook. */
#ifndef CVK_APP_COMMON_H
#define CVK_APP_COMMON_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "clothvk.h"

#include "cli.h"

/* The exit status for a failed creation: scene problems found only when the scene is built
 * (a mesh file missing or malformed, too many particles for the device, a size above its
 * limit) are bad input, the rest a failure. */
int app_creation_status(cvk_result r);

/* Prints the simulation's notes (cvk_sim_note) on stderr, one line "tool: note: ..." each. */
void app_print_notes(const char* tool, const cvk_sim* sim);

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
