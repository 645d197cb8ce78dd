/* Video out: the drawn frames piped as raw RGBA into ffmpeg, run as a separate process, which
   encodes them into a temporary file in the video's folder; the file is renamed into place
   when ffmpeg has finished it, and removed on any failure. */
#ifndef CVK_APP_VIDEO_H
#define CVK_APP_VIDEO_H

#include <stdbool.h>
#include <stdint.h>
#include <sys/types.h>

#include "clothvk.h"

typedef struct app_video {
    const char* tool;
    const char* path;       /* as given; its extension names the container (.mp4, .mkv, ...) */
    char* temp_path;        /* what ffmpeg writes; NULL once renamed into place */
    pid_t pid;              /* ffmpeg; 0 when not running */
    int fd;                 /* the write end of ffmpeg's stdin; -1 when closed */
    uint32_t width, height;
    uint8_t* row;           /* one row of tightly packed pixels */
    uint32_t frames;        /* written so far */
} app_video;

/* Before any work: true when ffmpeg is on PATH; otherwise one line saying how to get it. */
bool app_video_available(const char* tool);

/* Before any work: true when `path` names a video this tool can write (an extension of a
   container ffmpeg encodes, .mp4 .mkv .mov .webm .avi .gif; not a folder, a device or a link);
   otherwise one line. */
bool app_video_name_ok(const char* tool, const char* path);

/* Checks the name and makes the video's folder (APP_EXIT_BAD_INPUT, one line, on failure),
   then starts ffmpeg for frames of width × height pixels at `fps` frames per second
   (APP_EXIT_FAILURE when that fails). Call app_video_free in every case. */
int app_video_open(app_video* v, const char* tool, const char* path, uint32_t width,
                   uint32_t height, double fps);

/* Sends one frame to ffmpeg. False, with one line printed, when ffmpeg no longer takes it. */
bool app_video_write(app_video* v, const cvk_image* image);

/* Ends the stream, waits for ffmpeg and renames the video into place. APP_EXIT_OK, or
   APP_EXIT_FAILURE with one line printed and nothing left. */
int app_video_finish(app_video* v);

/* Stops ffmpeg if it still runs and removes an unfinished video. */
void app_video_free(app_video* v);

#endif
