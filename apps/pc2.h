/* Point caches for DCC tools: the whole run as one PC2 file (Blender's Mesh Cache modifier,
   3ds Max and Maya read it) beside a Wavefront OBJ of the rest mesh in the same vertex order.

   PC2, little endian: "POINTCACHE2\0" (12 bytes), int32 version 1, int32 numPoints,
   float32 startFrame, float32 sampleRate, int32 numSamples, then numSamples × numPoints ×
   (x, y, z) float32 in m. Points are every cloth's particles in the order of --dump and of the
   OBJ's v lines; sample i holds the state after i·sampleRate frames (startFrame 0). */
#ifndef CVK_APP_PC2_H
#define CVK_APP_PC2_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "clothvk.h"
#include "obj.h"

typedef struct app_pc2 {
    const char* tool;
    cvk_sim* sim;
    const char* path;       /* the cache, as given */
    char* folder;           /* the folder it goes into */
    char* obj_path;         /* the rest mesh: `path` with its extension replaced by .obj */
    char* temp_path;        /* the cache while it is written; NULL once renamed into place */
    FILE* file;
    uint64_t points;
    uint32_t every;         /* frames per sample */
    float* xyz;             /* one sample, m */
    unsigned char* bytes;   /* the same as little-endian float32 */
    uint32_t samples;       /* written so far */
    app_obj_frames rest;    /* the mesh before the first step */
} app_pc2;

/* Before the first step: checks the name (a name whose rest mesh would be itself, a folder),
   makes the folder, keeps the current mesh as the rest mesh and starts the cache in a
   temporary file in that folder. Returns APP_EXIT_OK, APP_EXIT_BAD_INPUT (a bad name or
   folder, one line printed, nothing left but folders made) or APP_EXIT_FAILURE. Call
   app_pc2_free in every case. */
int app_pc2_open(app_pc2* p, const char* tool, cvk_sim* sim, const char* path,
                 const cvk_scene_desc* scene, uint32_t every);

/* Appends the simulation's current positions as the next sample. False, with one line
   printed, when reading them or writing fails. */
bool app_pc2_write(app_pc2* p);

/* Completes the cache (its sample count, flushed to disk), writes the rest mesh OBJ, then
   renames the cache into place. With `summary`, prints one line on stdout saying what was
   written. Returns APP_EXIT_OK or APP_EXIT_FAILURE (one line printed). */
int app_pc2_finish(app_pc2* p, uint32_t frames, bool summary);

/* Frees everything; a cache not finished is removed. */
void app_pc2_free(app_pc2* p);

#endif
