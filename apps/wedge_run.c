/* Wedges: running one variant into its folder, or every variant, several at a time, each in a
   process of its own; and the preview of a variant's last frame. */
#include "wedge.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* A variant that is still running this long after its own limit has hung inside a frame (the
   limit is checked between frames): --jobs kills it. */
#define KILL_GRACE_S 30

/* ---- one variant ------------------------------------------------------------------------ */

static bool write_json(FILE* file, void* user)
{
    return json_dumpf(user, file, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(9)) ==
               0 && fputc('\n', file) != EOF;
}

static bool write_text(FILE* file, void* user)
{
    return fputs(user, file) >= 0 && fputc('\n', file) != EOF;
}

static int write_json_file(const char* tool, const char* path, json_t* root)
{
    char message[600];
    if (app_write_atomic(path, write_json, root, message, sizeof message))
        return APP_EXIT_OK;
    app_error(tool, "%s", message);
    return APP_EXIT_FAILURE;
}

/* DIR/wedge.json: written when absent or the same; another wedge's is refused. */
static int write_manifest(const app_wedge* w, const char* folder)
{
    size_t len = strlen(folder) + 16;
    char* path = malloc(len);
    if (!path) {
        app_error(w->tool, "out of memory");
        return APP_EXIT_FAILURE;
    }
    snprintf(path, len, "%s/wedge.json", folder);
    json_t* old = json_load_file(path, 0, NULL);
    int status = APP_EXIT_OK;
    if (old && !json_equal(old, w->manifest)) {
        app_error(w->tool, "%s: holds another wedge (its scene, settings or variants differ); "
                  "give another -o folder or remove it", path);
        status = APP_EXIT_BAD_INPUT;
    } else if (!old) {
        status = write_json_file(w->tool, path, w->manifest);
    }
    json_decref(old);
    free(path);
    return status;
}

/* The names a variant's files go by. */
#define PATH_CHARS 4096

typedef struct variant_paths {
    char folder[PATH_CHARS - 16], status[PATH_CHARS], scene[PATH_CHARS], stats[PATH_CHARS],
        log[PATH_CHARS], preview[PATH_CHARS], bake[PATH_CHARS];
} variant_paths;

static bool make_paths(variant_paths* p, const char* out, uint32_t index)
{
    int n = snprintf(p->folder, sizeof p->folder, "%s/v%04u", out, index);
    if (n < 0 || (size_t)n >= sizeof p->folder)
        return false;
    snprintf(p->status, sizeof p->status, "%s/status.json", p->folder);
    snprintf(p->scene, sizeof p->scene, "%s/scene.json", p->folder);
    snprintf(p->stats, sizeof p->stats, "%s/stats.json", p->folder);
    snprintf(p->log, sizeof p->log, "%s/log.txt", p->folder);
    snprintf(p->preview, sizeof p->preview, "%s/last.png", p->folder);
    snprintf(p->bake, sizeof p->bake, "%s/bake", p->folder);
    return true;
}

/* The scene as the variant reads it. */
static int write_resolved_scene(const char* tool, const char* scene, const app_overrides* all,
                                const char* path)
{
    cvk_scene* loaded = NULL;
    int status = app_load_scene(tool, scene, all, &loaded);
    if (status != APP_EXIT_OK)
        return status;
    char message[600];
    if (!app_write_atomic(path, write_text, (void*)cvk_scene_get_json(loaded), message,
                          sizeof message)) {
        app_error(tool, "%s", message);
        status = APP_EXIT_FAILURE;
    }
    cvk_scene_destroy(loaded);
    return status;
}

/* Runs with stderr going to the variant's log, then copies the log to stderr; `last` gets the
   log's last line (the error of a failed run). */
static int run_logged(const char* tool, const char* log_path, app_wedge_runner runner, void* user,
                      const app_overrides* all, app_wedge_run* run, char* last, size_t last_size)
{
    last[0] = '\0';
    fflush(stderr);
    int saved = dup(STDERR_FILENO);
    int fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (saved < 0 || fd < 0) {
        app_error(tool, "%s: cannot write: %s", log_path, strerror(errno));
        if (saved >= 0)
            close(saved);
        if (fd >= 0)
            close(fd);
        return APP_EXIT_FAILURE;
    }
    dup2(fd, STDERR_FILENO);
    close(fd);
    int status = runner(user, all, run);
    fflush(stderr);
    dup2(saved, STDERR_FILENO);
    close(saved);
    FILE* log = fopen(log_path, "r");
    char line[2048];
    while (log && fgets(line, sizeof line, log)) {
        fputs(line, stderr);
        line[strcspn(line, "\n")] = '\0';
        if (line[0])
            snprintf(last, last_size, "%s", line);
    }
    if (log)
        fclose(log);
    return status;
}

static json_t* start_status(uint32_t index)
{
    char host[256] = "";
    gethostname(host, sizeof host - 1);
    return json_pack("{sssisssisI}", "state", "running", "variant", (json_int_t)index, "host",
                     host, "pid", (json_int_t)getpid(), "started", (json_int_t)time(NULL));
}

/* The end: what happened, from the exit status and the run. */
static json_t* end_status(uint32_t index, int status, const app_wedge_run* run, const char* error,
                          const char* tool, double seconds)
{
    const char* state = status == APP_EXIT_OK ? "ok"
                        : run->diverged       ? "diverged"
                        : run->timed_out      ? "timed-out"
                                              : "failed";
    size_t prefix = strlen(tool) + 2;
    if (!strncmp(error, tool, prefix - 2) && !strncmp(error + prefix - 2, ": ", 2))
        error += prefix; /* the line without "clothvk-sim: " */
    json_t* root = json_pack("{sssisisisi}", "state", state, "variant", (json_int_t)index, "exit",
                             (json_int_t)status, "frames", (json_int_t)run->frames_done, "of",
                             (json_int_t)run->frames);
    if (run->diverged)
        json_object_set_new(root, "diverged_frame", json_integer((json_int_t)run->diverged_frame));
    json_object_set_new(root, "error", status == APP_EXIT_OK || !error[0] ? json_null()
                                                                          : json_string(error));
    json_object_set_new(root, "seconds", json_real(seconds));
    return root;
}

/* The variant's overrides: `sets`, then its own items (kept in `items`). */
static int variant_overrides(const app_wedge* w, const app_overrides* sets, uint32_t index,
                             json_t* items, app_overrides* all)
{
    const json_t* variants = json_object_get(w->manifest, "variants");
    json_t* own = app_wedge_variant_items(json_array_get(variants, index));
    json_array_extend(items, own);
    json_decref(own);
    int status = APP_EXIT_OK;
    for (uint32_t i = 0; i < sets->count && status == APP_EXIT_OK; i++)
        status = app_overrides_add(all, w->tool, sets->items[i]);
    for (size_t i = 0; i < json_array_size(items) && status == APP_EXIT_OK; i++)
        status = app_overrides_add(all, w->tool, json_string_value(json_array_get(items, i)));
    return status;
}

/* Old outputs of this variant go before it runs: the folder then holds this run's only. */
static void remove_old(const variant_paths* p)
{
    unlink(p->stats);
    unlink(p->preview);
    unlink(p->log);
}

int app_wedge_run_index(const app_wedge* w, const app_overrides* sets, const app_wedge_options* o,
                        uint32_t index, app_wedge_runner runner, void* user)
{
    double start = app_now_ms();
    if (index >= w->count) {
        app_error(w->tool, "--wedge-index %u: the wedge has %u variant%s (0 to %u)", index,
                  w->count, w->count == 1 ? "" : "s", w->count - 1);
        return APP_EXIT_BAD_INPUT;
    }
    variant_paths p;
    if (!make_paths(&p, o->out, index)) {
        app_error(w->tool, "-o %s: the name is too long", o->out);
        return APP_EXIT_BAD_INPUT;
    }
    if (!app_make_output_folder(w->tool, o->out))
        return APP_EXIT_BAD_INPUT;
    int status = write_manifest(w, o->out);
    if (status != APP_EXIT_OK)
        return status;
    if (!app_make_output_folder(w->tool, p.folder))
        return APP_EXIT_FAILURE;
    remove_old(&p);
    json_t* started = start_status(index);
    status = write_json_file(w->tool, p.status, started);
    json_decref(started);
    json_t* items = json_array();
    app_overrides all = {0};
    if (status == APP_EXIT_OK)
        status = variant_overrides(w, sets, index, items, &all);
    if (status == APP_EXIT_OK)
        status = write_resolved_scene(w->tool, json_string_value(json_object_get(w->manifest,
                                      "scene")), &all, p.scene);
    app_wedge_run run = {.stats_path = p.stats, .preview_path = o->preview ? p.preview : NULL,
                         .bake_path = o->bake ? p.bake : NULL, .time_limit_s = o->time_limit_s,
                         .deadline_ms = o->time_limit_s ? start + 1e3 * o->time_limit_s : 0};
    char last[2048] = "";
    if (status == APP_EXIT_OK)
        status = run_logged(w->tool, p.log, runner, user, &all, &run, last, sizeof last);
    json_t* end = end_status(index, status, &run, last, w->tool, (app_now_ms() - start) / 1e3);
    int written = write_json_file(w->tool, p.status, end);
    json_decref(end);
    app_overrides_free(&all);
    json_decref(items);
    return status != APP_EXIT_OK ? status : written;
}

/* ---- every variant on this machine -------------------------------------------------------- */

typedef struct child {
    pid_t pid;
    uint32_t index;
    double started_ms;
    bool killed;
} child;

/* One line of DIR/states.tsv for a child that did not end by itself. */
static void note_state(json_t* states, const child* c, int wait_status, uint32_t limit_s)
{
    char detail[256];
    const char* state;
    if (c->killed) {
        state = "KILLED";
        snprintf(detail, sizeof detail, "still running %d s past its time limit of %u s; killed",
                 KILL_GRACE_S, limit_s);
    } else if (WIFSIGNALED(wait_status)) {
        state = "SIGNALED";
        snprintf(detail, sizeof detail, "ended by signal %d (%s)", WTERMSIG(wait_status),
                 strsignal(WTERMSIG(wait_status)));
    } else {
        return;
    }
    char line[400];
    snprintf(line, sizeof line, "%u\t%s\t%s\n", c->index, state, detail);
    json_array_append_new(states, json_string(line));
}

static bool write_lines(FILE* file, void* user)
{
    size_t i;
    json_t* line;
    json_array_foreach((json_t*)user, i, line)
        if (fputs(json_string_value(line), file) < 0)
            return false;
    return true;
}

/* Starts variant `index` in a child process. */
static int spawn(const app_wedge* w, const app_overrides* sets, const app_wedge_options* o,
                 uint32_t index, app_wedge_runner runner, void* user, child* c)
{
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) {
        app_error(w->tool, "cannot start a process for variant %u: %s", index, strerror(errno));
        return APP_EXIT_FAILURE;
    }
    if (pid == 0) {
        int status = app_wedge_run_index(w, sets, o, index, runner, user);
        fflush(stdout);
        fflush(stderr);
        _exit(status);
    }
    *c = (child){pid, index, app_now_ms(), false};
    return APP_EXIT_OK;
}

/* Waits for one child to end (killing one past its limit and grace); returns its slot. */
static size_t reap(child* running, size_t count, uint32_t limit_s, json_t* states)
{
    for (;;) {
        int wait_status = 0;
        pid_t pid = waitpid(-1, &wait_status, WNOHANG);
        for (size_t i = 0; pid > 0 && i < count; i++) {
            if (running[i].pid != pid)
                continue;
            note_state(states, &running[i], wait_status, limit_s);
            return i;
        }
        if (pid < 0 && errno != EINTR)
            return count; /* no children left: cannot happen while count > 0 */
        double now = app_now_ms();
        for (size_t i = 0; i < count && limit_s; i++) {
            if (!running[i].killed && now - running[i].started_ms > 1e3 * (limit_s + KILL_GRACE_S)) {
                kill(running[i].pid, SIGKILL);
                running[i].killed = true;
            }
        }
        struct timespec nap = {0, 20 * 1000 * 1000};
        nanosleep(&nap, NULL);
    }
}

int app_wedge_run_all(const app_wedge* w, const app_overrides* sets, const app_wedge_options* o,
                      app_wedge_runner runner, void* user)
{
    if (!app_make_output_folder(w->tool, o->out))
        return APP_EXIT_BAD_INPUT;
    int status = write_manifest(w, o->out);
    if (status != APP_EXIT_OK)
        return status;
    size_t len = strlen(o->out) + 16;
    char* states_path = malloc(len);
    child* running = calloc(o->jobs ? o->jobs : 1, sizeof *running);
    json_t* states = json_array();
    if (!states_path || !running) {
        free(states_path);
        free(running);
        json_decref(states);
        app_error(w->tool, "out of memory");
        return APP_EXIT_FAILURE;
    }
    snprintf(states_path, len, "%s/states.tsv", o->out);
    unlink(states_path);
    uint32_t jobs = o->jobs ? o->jobs : 1;
    size_t active = 0;
    for (uint32_t next = 0; (next < w->count && !app_interrupted()) || active > 0;) {
        if (next < w->count && active < jobs && !app_interrupted() && status == APP_EXIT_OK) {
            status = spawn(w, sets, o, next, runner, user, &running[active]);
            active += status == APP_EXIT_OK;
            next++;
            continue;
        }
        if (active == 0)
            break;
        size_t done = reap(running, active, o->time_limit_s, states);
        if (done >= active)
            break;
        running[done] = running[--active];
    }
    char message[600];
    if (json_array_size(states) && !app_write_atomic(states_path, write_lines, states, message,
                                                     sizeof message)) {
        app_error(w->tool, "%s", message);
        status = APP_EXIT_FAILURE;
    }
    free(states_path);
    free(running);
    json_decref(states);
    if (status != APP_EXIT_OK)
        return status;
    status = app_wedge_gather(w->tool, o->out);
    if (status == APP_EXIT_OK && app_interrupted()) {
        app_error(w->tool, "interrupted: the table holds the variants run so far");
        status = APP_EXIT_FAILURE;
    }
    return status;
}

/* ---- the preview -------------------------------------------------------------------------- */

int app_wedge_preview(const char* tool, cvk_sim* sim, const cvk_scene_desc* scene,
                      uint32_t frames, const char* path)
{
    cvk_mesh* mesh = NULL;
    cvk_renderer* renderer = NULL;
    cvk_error err;
    cvk_result r = cvk_mesh_create(sim, NULL, &mesh, &err);
    if (r == CVK_SUCCESS)
        r = cvk_renderer_create(mesh, &scene->render, &renderer, &err);
    if (r == CVK_SUCCESS) {
        cvk_renderer_set_time(renderer, (double)frames * scene->dt * scene->substeps);
        r = cvk_renderer_draw(renderer, &err);
    }
    if (r == CVK_SUCCESS) {
        cvk_image image = cvk_renderer_get_image(renderer);
        r = cvk_image_write_png(&image, path, &err);
    }
    cvk_renderer_destroy(renderer);
    cvk_mesh_destroy(mesh);
    if (r == CVK_SUCCESS)
        return APP_EXIT_OK;
    app_error(tool, "preview %s: %s", path, err.message);
    return APP_EXIT_FAILURE;
}
