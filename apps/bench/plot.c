/* Plots: a gnuplot script written beside the CSV and run as a separate process. */
#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "plot.h"

typedef struct script_job {
    const char* name;
    int width, height;
    const bench_text* body;
} script_job;

static bool write_script(FILE* file, void* user)
{
    const script_job* job = user;
    return fprintf(file,
                   "# Draws %s.png from %s.csv (clothvk-bench). Run in this folder: gnuplot %s.gp\n"
                   "if (!exists(\"out\")) out = \"%s.png\"\n"
                   "set terminal pngcairo noenhanced size %d,%d font \"sans,10\"\n"
                   "set output out\n"
                   "set datafile separator \",\"\n"
                   "set grid\n"
                   "%s",
                   job->name, job->name, job->name, job->name, job->width, job->height,
                   job->body->data ? job->body->data : "") >= 0;
}

/* Runs `gnuplot -e out='TEMP' NAME.gp` in dir; its output goes to `log`. Returns the exit
   status, 127 when gnuplot could not be started. */
static int run_gnuplot(const char* dir, const char* name, const char* temp, char* log,
                       size_t log_size)
{
    int pipe_fds[2];
    if (pipe(pipe_fds) != 0)
        return 127;
    char script[256], assign[320];
    snprintf(script, sizeof script, "%s.gp", name);
    snprintf(assign, sizeof assign, "out='%s'", temp);
    const char* program = getenv("CLOTHVK_GNUPLOT");
    if (!program || !*program)
        program = "gnuplot";
    fflush(NULL);
    pid_t child = fork();
    if (child < 0) {
        close(pipe_fds[0]);
        close(pipe_fds[1]);
        return 127;
    }
    if (child == 0) {
        dup2(pipe_fds[1], STDOUT_FILENO);
        dup2(pipe_fds[1], STDERR_FILENO);
        close(pipe_fds[0]);
        close(pipe_fds[1]);
        int null = open("/dev/null", O_RDONLY);
        if (null >= 0)
            dup2(null, STDIN_FILENO);
        if (chdir(dir) == 0)
            execlp(program, program, "-e", assign, script, (char*)NULL);
        _exit(127);
    }
    close(pipe_fds[1]);
    size_t used = 0;
    char chunk[512];
    for (;;) {
        ssize_t got = read(pipe_fds[0], chunk, sizeof chunk);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0)
            break;
        size_t keep = (size_t)got < log_size - 1 - used ? (size_t)got : log_size - 1 - used;
        memcpy(log + used, chunk, keep);
        used += keep;
    }
    log[used] = '\0';
    close(pipe_fds[0]);
    int status = 0;
    while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 127;
}

/* The first line of gnuplot's complaint, for a one-line message. */
static void first_line(const char* log, char* out, size_t size)
{
    while (*log == '\n' || *log == ' ')
        log++;
    size_t n = strcspn(log, "\n");
    if (n >= size)
        n = size - 1;
    memcpy(out, log, n);
    out[n] = '\0';
}

bool bench_plot(const char* dir, const char* name, int width, int height, const bench_text* body,
                char* message, size_t message_size)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.gp", dir, name);
    script_job job = {name, width, height, body};
    if (body->failed) {
        snprintf(message, message_size, "out of memory for the plot script");
        return false;
    }
    if (!app_write_atomic(path, write_script, &job, message, message_size))
        return false;

    char temp[128], log[2048], line[256];
    snprintf(temp, sizeof temp, "%s.png.tmp-%ld", name, (long)getpid());
    int status = run_gnuplot(dir, name, temp, log, sizeof log);
    char temp_path[4352], png[4096];
    snprintf(temp_path, sizeof temp_path, "%s/%s", dir, temp);
    snprintf(png, sizeof png, "%s/%s.png", dir, name);
    struct stat st;
    bool drawn = status == 0 && stat(temp_path, &st) == 0 && st.st_size > 0;
    if (drawn && rename(temp_path, png) == 0)
        return true;
    unlink(temp_path);
    first_line(log, line, sizeof line);
    if (status == 127)
        snprintf(message, message_size, "gnuplot could not be run (install gnuplot-nox)");
    else
        snprintf(message, message_size, "gnuplot failed (status %d): %s", status,
                 line[0] ? line : "no output");
    return false;
}

/* Does the table hold a point of `label` that the axes can show? Rows whose column `only`
   (may be NULL) is not 1 do not count. */
static bool series_has_data(const bench_table* t, const char* label, const char* x, const char* y,
                            bool log_x, bool log_y, const char* only)
{
    for (uint32_t r = 0; r < t->rows; r++) {
        const char* l = bench_table_get_str(t, r, "label");
        double vx = bench_table_get(t, r, x), vy = bench_table_get(t, r, y);
        if (l && !strcmp(l, label) && isfinite(vx) && isfinite(vy) && (!log_x || vx > 0.0) &&
            (!log_y || vy > 0.0) && (!only || bench_table_get(t, r, only) == 1.0))
            return true;
    }
    return false;
}

void bench_plot_solvers(bench* b, const char* csv, const char* x, const char* y, const char* with,
                        bool log_x, bool log_y, const char* only, const bench_text* extra)
{
    bench_text* t = &b->plot;
    bench_text_add(t, "%s logscale x\n%s logscale y\n", log_x ? "set" : "unset", log_y ? "set" : "unset");
    char condition[128] = "";
    if (only)
        snprintf(condition, sizeof condition, " && column(\"%s\") == 1", only);
    const char* sep = "plot ";
    for (uint32_t i = 0; i < b->o->solver_count; i++) {
        const bench_solver* s = &b->o->solvers[i];
        if (!series_has_data(&b->table, s->label, x, y, log_x, log_y, only))
            continue;
        bench_text_add(t, "%s\"%s\" using \"%s\":(strcol(\"label\") eq \"%s\"%s ? column(\"%s\") : NaN) "
                       "with %s linestyle %u%s title \"%s\"",
                       sep, csv, x, s->label, condition, y, with, i + 1,
                       s->linear == CVK_LINEAR_GS_CPU ? " dashtype 2" : "", s->title);
        sep = ", \\\n     ";
    }
    if (!strcmp(sep, "plot ")) {
        bench_plot_empty(t);
        return;
    }
    if (extra && extra->data)
        bench_text_add(t, "%s%s", sep, extra->data);
    bench_text_add(t, "\n");
}

void bench_plot_empty(bench_text* t)
{
    bench_text_add(t, "set label 99 \"no data\" at graph 0.5,0.5 center\n"
                      "unset logscale\nplot [0:1][0:1] 2 notitle\nunset label 99\n");
}

void bench_plot_styles(bench_text* t)
{
    static const char* const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                          "#8c564b", "#e377c2", "#7f7f7f"};
    for (uint32_t i = 0; i < BENCH_MAX_LIST; i++)
        bench_text_add(t, "set style line %u linecolor rgb \"%s\" pointtype %u linewidth 1.5\n",
                       i + 1, colours[i % 8], 1 + i % 13);
}
