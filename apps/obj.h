/* Frames out for other tools: an output folder, and one Wavefront OBJ file per frame with
   every cloth as one object (positions, vertex normals, the triangles that exist). */
#ifndef CVK_APP_OBJ_H
#define CVK_APP_OBJ_H

#include <stdbool.h>
#include <stdint.h>

#include "clothvk.h"

/* What the frames need, allocated once for the whole run. */
typedef struct app_obj_frames {
    const char* tool;
    cvk_sim* sim;
    const char* folder;
    const char* scene_name;
    double frame_seconds;        /* simulated time per frame, s */
    uint64_t vertex_count, triangle_count;
    float* xyz;
    float* normals;
    uint32_t* triangles;
    char* path;
    uint32_t written;            /* files written so far */
} app_obj_frames;

/* Prepares to write frames of `sim` into `folder` (made before the first frame is written).
   False, with one line printed, when memory runs out. */
bool app_obj_frames_init(app_obj_frames* f, const char* tool, cvk_sim* sim, const char* folder,
                         const cvk_scene_desc* scene);

/* Writes FOLDER/frame_NNNN.obj (NNNN = number, at least four digits) from the simulation's
   current state, `frame` frames after the start, through a temporary file renamed into place.
   False, with one line printed, when reading the mesh or writing the file fails. */
bool app_obj_frames_write(app_obj_frames* f, uint32_t number, uint32_t frame);

/* The two halves of app_obj_frames_write, for one file at a path of the caller's choosing
   (the rest mesh beside a point cache): reads the simulation's current mesh into `f`, then
   writes what was read to `path` through a temporary file renamed into place, its header
   naming `frame`. False, with one line printed, on failure. */
bool app_obj_frames_read(app_obj_frames* f);
bool app_obj_write_file(const app_obj_frames* f, const char* path, uint32_t frame);

void app_obj_frames_free(app_obj_frames* f);

#endif
