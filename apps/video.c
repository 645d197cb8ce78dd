#include "video.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "common.h"

extern char** environ;

/* ---- ffmpeg on PATH --------------------------------------------------------------------- */

bool app_video_available(const char* tool)
{
    const char* path = getenv("PATH");
    char candidate[4096];
    while (path && *path) {
        const char* end = strchr(path, ':');
        size_t len = end ? (size_t)(end - path) : strlen(path);
        /* An empty entry is the current folder. */
        int n = len ? snprintf(candidate, sizeof candidate, "%.*s/ffmpeg", (int)len, path)
                    : snprintf(candidate, sizeof candidate, "./ffmpeg");
        struct stat st;
        if (n > 0 && (size_t)n < sizeof candidate && stat(candidate, &st) == 0 &&
            S_ISREG(st.st_mode) && access(candidate, X_OK) == 0)
            return true;
        path = end ? end + 1 : NULL;
    }
    app_error(tool, "--video needs ffmpeg: apt-get install ffmpeg");
    return false;
}

/* ---- names ------------------------------------------------------------------------------ */

/* Where the extension of the last path component starts, or NULL when it has none. */
static const char* extension(const char* path)
{
    const char* base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char* dot = strrchr(base, '.');
    return dot && dot > base && dot[1] ? dot : NULL;
}

/* "out/clip.mp4" → "out/clip.tmp-PID.mp4": ffmpeg picks the container by the extension. */
static char* temp_name(const char* path)
{
    const char* ext = extension(path);
    size_t stem = (size_t)(ext - path), len = strlen(path) + 32;
    char* out = malloc(len);
    if (out)
        snprintf(out, len, "%.*s.tmp-%ld%s", (int)stem, path, (long)getpid(), ext);
    return out;
}

/* The containers ffmpeg writes with the encoders it picks for them by default, each checked
   with yuv420p frames (tests/tools/test_video.py); ffmpeg would refuse another extension only
   once the frames are drawn. */
static const char* const containers[] = {".mp4", ".mkv", ".mov", ".webm", ".avi", ".gif"};

bool app_video_name_ok(const char* tool, const char* path)
{
    const char* ext = extension(path);
    if (!ext) {
        app_error(tool, "--video %s: expected a name whose extension names the format, such as "
                  "clip.mp4", path);
        return false;
    }
    bool known = false;
    for (size_t i = 0; i < sizeof containers / sizeof containers[0]; i++)
        known |= strcasecmp(ext, containers[i]) == 0;
    if (!known) {
        app_error(tool, "--video %s: unknown video format %s (expected .mp4, .mkv, .mov, .webm, "
                  ".avi or .gif)", path, ext);
        return false;
    }
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        app_error(tool, "--video %s: is a folder; expected a file name such as clip.mp4", path);
        return false;
    }
    return app_output_option_ok(tool, "--video", path);
}

static int make_folder(const char* tool, const char* path)
{
    char* folder = app_folder_of(path);
    if (!folder) {
        app_error(tool, "out of memory");
        return APP_EXIT_FAILURE;
    }
    bool ok = app_make_output_folder(tool, folder);
    free(folder);
    return ok ? APP_EXIT_OK : APP_EXIT_BAD_INPUT;
}

/* ---- ffmpeg ----------------------------------------------------------------------------- */

/* ffmpeg reads the frames from its stdin (the read end of `pipe_fds`); everything it is given
   is an argument of its own, never a shell command line, so no name is ever interpreted. */
static bool spawn_ffmpeg(app_video* v, const int pipe_fds[2], double fps)
{
    char size[32], rate[32];
    snprintf(size, sizeof size, "%ux%u", v->width, v->height);
    snprintf(rate, sizeof rate, "%.9g", fps);
    /* yuv420p (what players expect) needs even sizes: an odd one is padded by a pixel. */
    char* argv[] = {"ffmpeg", "-nostdin", "-hide_banner", "-loglevel", "error", "-y",
                    "-f", "rawvideo", "-pix_fmt", "rgba", "-s", size, "-r", rate, "-i", "-",
                    "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p",
                    v->temp_path, NULL};
    posix_spawn_file_actions_t actions;
    if (posix_spawn_file_actions_init(&actions) != 0)
        return false;
    int err = posix_spawn_file_actions_adddup2(&actions, pipe_fds[0], STDIN_FILENO);
    if (!err)
        err = posix_spawn_file_actions_addclose(&actions, pipe_fds[1]);
    if (!err)
        err = posix_spawnp(&v->pid, "ffmpeg", &actions, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    if (err) {
        v->pid = 0;
        errno = err;
        return false;
    }
    return true;
}

int app_video_open(app_video* v, const char* tool, const char* path, uint32_t width,
                   uint32_t height, double fps)
{
    memset(v, 0, sizeof *v);
    v->tool = tool;
    v->path = path;
    v->fd = -1;
    v->width = width;
    v->height = height;
    int status = app_video_name_ok(tool, path) ? make_folder(tool, path) : APP_EXIT_BAD_INPUT;
    if (status != APP_EXIT_OK)
        return status;
    v->temp_path = temp_name(path);
    v->row = malloc((size_t)4 * width);
    if (!v->temp_path || !v->row) {
        app_error(tool, "out of memory");
        return APP_EXIT_FAILURE;
    }
    /* A write to a stopped ffmpeg must fail with EPIPE, not end this process. */
    signal(SIGPIPE, SIG_IGN);
    int fds[2];
    if (pipe(fds) != 0) {
        app_error(tool, "--video: cannot make a pipe to ffmpeg: %s", strerror(errno));
        return APP_EXIT_FAILURE;
    }
    fcntl(fds[1], F_SETFD, FD_CLOEXEC);
    bool started = spawn_ffmpeg(v, fds, fps);
    int saved = errno;
    close(fds[0]);
    v->fd = fds[1];
    if (!started) {
        app_error(tool, "--video: cannot start ffmpeg: %s", strerror(saved));
        return APP_EXIT_FAILURE;
    }
    return APP_EXIT_OK;
}

static bool write_all(int fd, const uint8_t* data, size_t size)
{
    while (size) {
        ssize_t n = write(fd, data, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;
        data += n;
        size -= (size_t)n;
    }
    return true;
}

bool app_video_write(app_video* v, const cvk_image* image)
{
    for (uint32_t y = 0; y < v->height; y++) {
        memcpy(v->row, image->pixels + (size_t)y * image->row_bytes, (size_t)4 * v->width);
        if (!write_all(v->fd, v->row, (size_t)4 * v->width)) {
            app_error(v->tool, "%s: ffmpeg stopped taking frames: %s", v->path, strerror(errno));
            return false;
        }
    }
    v->frames++;
    return true;
}

/* Closes ffmpeg's input and waits for it: its exit status, or -1. */
static int wait_ffmpeg(app_video* v)
{
    if (v->fd >= 0)
        close(v->fd);
    v->fd = -1;
    int status = 0;
    pid_t r;
    do
        r = waitpid(v->pid, &status, 0);
    while (r < 0 && errno == EINTR);
    v->pid = 0;
    return r < 0 || !WIFEXITED(status) ? -1 : WEXITSTATUS(status);
}

int app_video_finish(app_video* v)
{
    int code = wait_ffmpeg(v);
    if (code != 0) {
        app_error(v->tool, "%s: ffmpeg failed (exit status %d)", v->path, code);
        return APP_EXIT_FAILURE;
    }
    if (v->frames == 0) {
        app_error(v->tool, "%s: no frame to encode", v->path);
        return APP_EXIT_FAILURE;
    }
    if (rename(v->temp_path, v->path) != 0) {
        app_error(v->tool, "%s: cannot write: %s", v->path, strerror(errno));
        return APP_EXIT_FAILURE;
    }
    free(v->temp_path);
    v->temp_path = NULL;
    return APP_EXIT_OK;
}

void app_video_free(app_video* v)
{
    if (v->pid > 0) {
        kill(v->pid, SIGTERM);
        wait_ffmpeg(v);
    }
    if (v->fd >= 0)
        close(v->fd);
    if (v->temp_path)
        unlink(v->temp_path);
    free(v->temp_path);
    free(v->row);
    memset(v, 0, sizeof *v);
    v->fd = -1;
}
