#include "common.h"

#include <errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

void app_log_validation(void* tool_name, const char* message)
{
    fprintf(stderr, "%s: validation: %s\n", (const char*)tool_name, message);
}

int app_load_scene(const char* tool, const char* path, const app_overrides* overrides,
                   cvk_scene** out)
{
    cvk_error err;
    if (cvk_scene_load(path, overrides->items, overrides->count, out, &err) == CVK_SUCCESS)
        return APP_EXIT_OK;
    app_error(tool, "%s", err.message);
    return err.result == CVK_ERROR_OUT_OF_MEMORY ? APP_EXIT_FAILURE : APP_EXIT_BAD_INPUT;
}

int app_create_context(const char* tool, cvk_context** out)
{
    cvk_error err;
    cvk_context_desc desc = cvk_default_context_desc();
    desc.log = app_log_validation;
    desc.log_user = (void*)tool;
    if (cvk_context_create(&desc, out, &err) == CVK_SUCCESS)
        return APP_EXIT_OK;
    app_error(tool, "%s", err.message);
    return APP_EXIT_FAILURE;
}

int app_validation_status(const char* tool, const cvk_context* ctx, int status)
{
    uint32_t messages = cvk_context_validation_message_count(ctx);
    if (!messages)
        return status;
    app_error(tool, "%u validation messages", messages);
    return APP_EXIT_FAILURE;
}

int app_open(const char* tool, const char* path, const app_overrides* overrides, cvk_scene** scene,
             cvk_context** ctx)
{
    int status = app_load_scene(tool, path, overrides, scene);
    if (status != APP_EXIT_OK)
        return status;
    status = app_create_context(tool, ctx);
    if (status != APP_EXIT_OK) {
        cvk_scene_destroy(*scene);
        *scene = NULL;
    }
    return status;
}

int app_close(const char* tool, cvk_context* ctx, cvk_scene* scene, int status)
{
    status = app_validation_status(tool, ctx, status);
    cvk_context_destroy(ctx);
    cvk_scene_destroy(scene);
    return status;
}

static volatile sig_atomic_t interrupted;

static void on_signal(int sig)
{
    (void)sig;
    interrupted = 1;
}

void app_catch_interrupts(void)
{
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
}

bool app_interrupted(void)
{
    return interrupted != 0;
}

bool app_output_replaceable(const char* path, char* message, size_t message_size)
{
    struct stat st;
    if (lstat(path, &st) != 0 || S_ISREG(st.st_mode))
        return true;
    snprintf(message, message_size, "%s: exists and is not a regular file (a %s); it is not "
             "replaced", path, S_ISDIR(st.st_mode) ? "folder" : S_ISLNK(st.st_mode) ? "link"
             : S_ISFIFO(st.st_mode) ? "FIFO" : "device or socket");
    return false;
}

bool app_output_option_ok(const char* tool, const char* option, const char* path)
{
    char message[512];
    if (app_output_replaceable(path, message, sizeof message))
        return true;
    app_error(tool, "%s %s", option, message);
    return false;
}

bool app_write_atomic(const char* path, app_writer write, void* user, char* message,
                      size_t message_size)
{
    if (!app_output_replaceable(path, message, message_size))
        return false;
    size_t len = strlen(path);
    char* temp = malloc(len + 16);
    if (!temp) {
        snprintf(message, message_size, "%s: out of memory", path);
        return false;
    }
    snprintf(temp, len + 16, "%s.tmp-XXXXXX", path);
    int fd = mkstemp(temp);
    if (fd < 0) {
        snprintf(message, message_size, "%s: cannot create: %s", path, strerror(errno));
        free(temp);
        return false;
    }
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask); /* mkstemp makes 0600; give the file the usual permissions */
    FILE* file = fdopen(fd, "w");
    if (!file) {
        snprintf(message, message_size, "%s: cannot write: %s", path, strerror(errno));
        close(fd);
        unlink(temp);
        free(temp);
        return false;
    }
    bool ok = write(file, user) && fflush(file) == 0 && !ferror(file);
    int saved = errno;
    ok = (fclose(file) == 0) && ok;
    if (ok && rename(temp, path) != 0) {
        saved = errno;
        ok = false;
    }
    if (!ok) {
        snprintf(message, message_size, "%s: cannot write: %s", path, strerror(saved ? saved : EIO));
        unlink(temp);
    }
    free(temp);
    return ok;
}

double app_now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

uint64_t app_peak_rss(void)
{
    struct rusage usage;
    if (getrusage(RUSAGE_SELF, &usage) != 0)
        return 0;
    return (uint64_t)usage.ru_maxrss * 1024u; /* kilobytes on Linux */
}

void app_print_notes(const char* tool, const cvk_sim* sim)
{
    for (uint32_t i = 0; i < cvk_sim_note_count(sim); i++)
        app_error(tool, "note: %s", cvk_sim_note(sim, i));
}

int app_creation_status(cvk_result r)
{
    bool bad = r == CVK_ERROR_INVALID_ARGUMENT || r == CVK_ERROR_DEVICE_LIMIT || r == CVK_ERROR_IO;
    return bad ? APP_EXIT_BAD_INPUT : APP_EXIT_FAILURE;
}

/* mkdir -p: every parent of `path` that is missing. */
static bool make_parents(const char* tool, const char* path)
{
    char* copy = strdup(path);
    if (!copy) {
        app_error(tool, "out of memory");
        return false;
    }
    for (char* p = copy + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(copy, 0777) != 0 && errno != EEXIST) {
            app_error(tool, "%s: cannot create the output folder: %s", path, strerror(errno));
            free(copy);
            return false;
        }
        *p = '/';
    }
    free(copy);
    return true;
}

bool app_make_output_folder(const char* tool, const char* path)
{
    if (!make_parents(tool, path))
        return false;
    if (mkdir(path, 0777) != 0 && errno != EEXIST) {
        app_error(tool, "%s: cannot create the output folder: %s", path, strerror(errno));
        return false;
    }
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) {
        app_error(tool, "%s: exists and is not a folder", path);
        return false;
    }
    size_t len = strlen(path) + strlen(tool) + 16;
    char* probe = malloc(len);
    if (!probe) {
        app_error(tool, "out of memory");
        return false;
    }
    snprintf(probe, len, "%s/.%s-XXXXXX", path, tool);
    int fd = mkstemp(probe);
    if (fd < 0) {
        app_error(tool, "%s: cannot write into the output folder: %s", path, strerror(errno));
        free(probe);
        return false;
    }
    close(fd);
    unlink(probe);
    free(probe);
    return true;
}

/* The folder part of `path`: "." for a bare name, "/" for a name in the root. */
char* app_folder_of(const char* path)
{
    const char* slash = strrchr(path, '/');
    if (!slash)
        return strdup(".");
    size_t len = slash == path ? 1 : (size_t)(slash - path);
    char* out = malloc(len + 1);
    if (out) {
        memcpy(out, path, len);
        out[len] = '\0';
    }
    return out;
}
