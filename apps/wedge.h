/* Wedges: many variants of one scene, each a set of --set overrides, run one by one (a Slurm
   array task each: --wedge-index K), several at a time on one machine (--jobs N), and gathered
   into one table and one contact sheet. docs/tools.md, Wedges, shows it end to end.

   The variants are the Cartesian product of the axes (--wedge key.path=v1,v2,...; the first
   axis varies slowest) and, when given, of a list of explicit combinations (--wedges FILE: a
   JSON list of objects key.path -> value), the list varying slowest of all. Every variant is
   checked as --set checks its items, before anything is written.

   An output folder DIR holds:
     DIR/wedge.json       the manifest: the scene, the --set items, the varied keys and every
                          variant's values (written by each run, atomically, always the same)
     DIR/vNNNN/           variant NNNN (four digits at least, from 0):
       status.json        {"state": "running", ...} at its start, replaced at its end by
                          {"state": "ok" | "diverged" | "timed-out" | "failed", "exit": N,
                          "frames": F, "error": "..."}: a folder whose status still says running
                          is a variant that crashed or was killed
       scene.json         the scene as this variant read it (cvk_scene_get_json)
       stats.json         clothvk-sim --json's object for its run
       log.txt            what the run printed on stderr
       last.png           the last frame drawn (--wedge-preview)
       bake/              its bake (--wedge-bake)
     DIR/states.tsv       how variants ended that did not end by themselves, one line each,
                          "K<TAB>STATE<TAB>DETAIL" (Slurm's job state, or a local signal)
     DIR/wedges.csv       one row per variant (--wedge-gather)
     DIR/contact-sheet.png each variant's last frame in a grid, labelled with its values */
#ifndef CVK_APP_WEDGE_H
#define CVK_APP_WEDGE_H

#include <jansson.h>
#include <stdbool.h>
#include <stdint.h>

#include "clothvk.h"
#include "common.h"

#define APP_WEDGE_FORMAT "clothvk-wedge"
#define APP_WEDGE_VERSION 1
#define APP_WEDGE_DEFAULT_LIMIT 1000

/* The wedge options of the command line. */
typedef struct app_wedge_options {
    const char** axes;        /* --wedge items, as given */
    uint32_t axis_count;
    const char* file;         /* --wedges FILE, or NULL */
    uint32_t limit;           /* --wedge-limit: the most variants (0: APP_WEDGE_DEFAULT_LIMIT) */
    bool count;               /* --wedge-count: print how many and stop */
    bool index_set;           /* --wedge-index K: run variant K only */
    uint32_t index;
    bool jobs_set;            /* --jobs N: N variants at a time on this machine */
    uint32_t jobs;
    uint32_t time_limit_s;    /* --wedge-time-limit S: a variant stops after S s (0: none) */
    bool preview;             /* --wedge-preview: draw each variant's last frame */
    bool bake;                /* --wedge-bake: bake each variant */
    const char* out;          /* -o DIR */
} app_wedge_options;

/* True when any wedge option was given. */
bool app_wedge_requested(const app_wedge_options* o);

/* Adds one --wedge item (checked later, by app_wedge_build). */
int app_wedge_add_axis(app_wedge_options* o, const char* tool, const char* item);
void app_wedge_options_free(app_wedge_options* o);

/* The variants, built and checked. */
typedef struct app_wedge {
    const char* tool;
    json_t* manifest;         /* what DIR/wedge.json holds */
    uint32_t count;
} app_wedge;

/* Reads the axes and the file, counts the variants against the limit and loads the scene with
   every variant's overrides (after `sets`), so that a key path or a value --set would refuse is
   refused here. Bad input: one line, APP_EXIT_BAD_INPUT; nothing is written. */
int app_wedge_build(app_wedge* w, const char* tool, const char* scene, const app_overrides* sets,
                    const app_wedge_options* o);
void app_wedge_free(app_wedge* w);

/* The "key=value" items of one variant (an object key -> value text of the manifest), in its
   key order: a new array of strings. */
json_t* app_wedge_variant_items(const json_t* variant);

/* What running one variant takes and gives back (filled by the tool's runner). */
typedef struct app_wedge_run {
    const char* stats_path;   /* write the --json object here */
    const char* preview_path; /* the last frame as a PNG, or NULL */
    const char* bake_path;    /* bake into this folder, or NULL */
    double deadline_ms;       /* app_now_ms() past which the run stops (0: none) */
    uint32_t time_limit_s;    /* for the message */
    /* results */
    bool timed_out;
    bool diverged;
    uint64_t diverged_frame;
    uint32_t frames_done;
    uint32_t frames;
} app_wedge_run;

/* Runs a scene with `overrides` as the run says; returns the tool's exit status. */
typedef int (*app_wedge_runner)(void* user, const app_overrides* overrides, app_wedge_run* run);

/* Runs variant `index` into its folder under o->out: the manifest, status.json at the start and
   the end, the resolved scene, the statistics, the log and what was asked for. Returns the
   run's exit status. */
int app_wedge_run_index(const app_wedge* w, const app_overrides* sets, const app_wedge_options* o,
                        uint32_t index, app_wedge_runner runner, void* user);

/* Runs every variant, o->jobs (at least 1) at a time, each in a process of its own, then
   gathers them. Returns APP_EXIT_OK when the table and the sheet were written. */
int app_wedge_run_all(const app_wedge* w, const app_overrides* sets, const app_wedge_options* o,
                      app_wedge_runner runner, void* user);

/* The last frame of `sim` drawn with the scene's render settings into a PNG at `path`, the
   camera where it is after `frames` frames. One line and APP_EXIT_FAILURE on failure. */
int app_wedge_preview(const char* tool, cvk_sim* sim, const cvk_scene_desc* scene,
                      uint32_t frames, const char* path);

/* --wedge-gather DIR: DIR/wedges.csv and DIR/contact-sheet.png from the manifest, the variant
   folders and DIR/states.tsv. Prints a one-line summary on stdout. */
int app_wedge_gather(const char* tool, const char* folder);

#endif
