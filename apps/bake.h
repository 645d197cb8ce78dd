/* Baked caches: the simulation's exact state at every K-th frame, in a folder, so that a run
   can be resumed bit for bit and frames can be drawn later without simulating.

   Format "clothvk-bake", version 3 (version 2 held frames 0 to N-1 of a bake of N frames; its
   last frame was simulated and thrown away). A folder DIR holds:

   DIR/cache.json, written first (and again when a resume extends the bake), atomically:
     {
       "format": "clothvk-bake",
       "version": 3,                       this format's version
       "clothvk_version": "0.1.0",         the library that baked it
       "scene": "...",                     the scene file's text, copied in full
       "scene_file": "scenes/hanging.json" the path it was read from (for people)
       "overrides": ["dt=0.001", ...],     the --set items, in order (for people)
       "resolved": "{\"cloths\":...}",       the scene as read (cvk_scene_get_json): what a resume
                                           and a render compare, key path by key path
       "run": "0123456789abcdef",          FNV-1a over resolved, dt, substeps and every
       "frames": 300,                      frames the whole bake simulates
       "every": 1,                         K: frame file i holds the state after i*K frames
       "dt": 0.002, "substeps": 8,         step (s) and substeps per frame, for readers
       "particles": 1600,                  particles over all cloths
       "snapshot_bytes": 51264             the size of every frame file
     }
   DIR/frame_0000.snap, frame_0001.snap, ...: file i holds the state after i*K frames, for every
     i*K <= frames (frame_0000: before the first step; with K dividing the frames, the last file
     is the state --dump writes), numbered as clothvk-sim --obj and
     clothvk-render number theirs (at least four digits). Each is one cvk_sim_save_snapshot
     (see clothvk.h: a 72-byte header with magic "CVKSNAP", format version, particle count,
     frame count, a hash of the built scene and a CRC-32, then the solver's state exactly as it
     holds it), written through a temporary file renamed into place: an interrupted bake leaves
     every finished frame whole. Mesh files the scene names are not copied; the hash in each
     frame refuses a frame whose scene has changed since.
   A new bake owns DIR: cache.json and the frame names must be regular files (checked before
   anything is written), and the frame files an earlier bake left are removed. */
#ifndef CVK_APP_BAKE_H
#define CVK_APP_BAKE_H

#include <stdbool.h>
#include <stdint.h>

#include "clothvk.h"
#include "common.h"

#define APP_BAKE_FORMAT "clothvk-bake"
#define APP_BAKE_VERSION 3

/* What a bake is of: cache.json says it, a resume and a render check it. */
typedef struct app_bake_desc {
    const char* scene_path;
    const app_overrides* overrides;
    const cvk_scene_desc* scene;
    const char* resolved; /* cvk_scene_get_json of the scene */
    uint32_t frames; /* of the whole bake */
    uint32_t every;  /* 0 where not given: 1 for a new bake, the cache's for a resume */
} app_bake_desc;

typedef struct app_bake {
    const char* tool;
    cvk_sim* sim;
    const char* folder;
    char* scene_text;
    uint32_t frames, every;
    uint32_t first;         /* frames simulated when this run starts (a resume: the last frame) */
    uint64_t size;          /* bytes of one snapshot */
    unsigned char* data;
    char* path;
    uint32_t written;       /* frame files this run wrote */
} app_bake;

/* A new bake of `sim` (at rest, frame 0) into `folder`: makes the folder and writes
   cache.json. Returns an APP_EXIT status, having printed one line on failure. */
int app_bake_start(app_bake* b, const char* tool, cvk_sim* sim, const char* folder,
                   const app_bake_desc* desc);

/* Continues the bake in `folder`: checks that its cache.json is of this scene (the resolved
   scene and the run hash), that `desc->every` (when given) is its K and that its frame names
   are regular files, loads the last complete frame (its header counting its place) into
   `sim`, and rewrites cache.json for `desc->frames` (0: the cache's). b->first, b->every and
   b->frames say where the run goes on. Bad input: one line, APP_EXIT_BAD_INPUT, nothing
   written. */
int app_bake_resume(app_bake* b, const char* tool, cvk_sim* sim, const char* folder,
                    const app_bake_desc* desc);

/* Opens a bake for reading frames into `sim` (clothvk-render --from): the same checks of
   cache.json as a resume. */
int app_bake_open(app_bake* b, const char* tool, cvk_sim* sim, const char* folder,
                  const app_bake_desc* desc);

/* With the state after `frame` frames (before frame `frame` is stepped, and after the last):
   writes its file when frame is a multiple of K and the file is not the one this run resumed
   from. False, with one line printed, when saving or writing fails. */
bool app_bake_frame(app_bake* b, uint32_t frame);

/* The last frame the bake holds: the largest multiple of K not above its frames. */
uint32_t app_bake_last_frame(const app_bake* b);

/* Checks, before any work, that the bake holds frames first, first + step, ..., last (each
   a multiple of K, not above its frames, its file present). Bad input: one line,
   APP_EXIT_BAD_INPUT. */
int app_bake_check_frames(app_bake* b, uint32_t first, uint32_t last, uint32_t step);

/* Loads the state after `frame` frames from the bake into its simulation. A frame the bake
   does not hold (not a multiple of K, beyond its frames, its file missing or not a
   snapshot of this scene): one line, APP_EXIT_BAD_INPUT. */
int app_bake_load(app_bake* b, uint32_t frame);

void app_bake_free(app_bake* b);

#endif
