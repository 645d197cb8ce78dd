#include "pc2.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common.h"

enum {
    PC2_HEADER_BYTES = 32,
    PC2_SAMPLES_OFFSET = 28, /* numSamples, fixed up once the run is over */
};

/* ---- names ----------------------------------------------------------------------------- */

/* `path` with the extension of its last component replaced by ".obj" (appended when it has
   none; a leading dot, as in ".pc2", starts a name, not an extension). */
static char* rest_mesh_path(const char* path)
{
    const char* base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char* dot = strrchr(base, '.');
    size_t keep = dot && dot > base ? (size_t)(dot - path) : strlen(path);
    char* out = malloc(keep + 5);
    if (out) {
        memcpy(out, path, keep);
        memcpy(out + keep, ".obj", 5);
    }
    return out;
}

static bool is_folder(const char* path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* One line and false when the names cannot be written as files. */
static bool names_usable(const app_pc2* p)
{
    if (!strcmp(p->obj_path, p->path)) {
        app_error(p->tool, "--pc2 %s: the rest mesh goes to the same name with .obj, so the cache "
                  "needs another extension (.pc2)", p->path);
        return false;
    }
    const char* base = strrchr(p->path, '/');
    if (!(base ? base[1] : p->path[0]) || is_folder(p->path)) {
        app_error(p->tool, "--pc2 %s: is a folder; expected a file name (FILE.pc2)", p->path);
        return false;
    }
    if (is_folder(p->obj_path)) {
        app_error(p->tool, "--pc2 %s: the rest mesh %s is a folder", p->path, p->obj_path);
        return false;
    }
    return app_output_option_ok(p->tool, "--pc2", p->path) &&
           app_output_option_ok(p->tool, "--pc2 (rest mesh)", p->obj_path);
}

/* ---- the file -------------------------------------------------------------------------- */

static void put_u32(unsigned char* out, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        out[i] = (unsigned char)(v >> (8 * i));
}

static void put_f32(unsigned char* out, float v)
{
    uint32_t bits;
    memcpy(&bits, &v, sizeof bits);
    put_u32(out, bits);
}

static bool write_header(app_pc2* p)
{
    unsigned char h[PC2_HEADER_BYTES];
    memcpy(h, "POINTCACHE2", 12); /* with its terminating zero: 12 bytes */
    put_u32(h + 12, 1);
    put_u32(h + 16, (uint32_t)p->points);
    put_f32(h + 20, 0.0f);
    put_f32(h + 24, (float)p->every);
    put_u32(h + PC2_SAMPLES_OFFSET, 0);
    return fwrite(h, sizeof h, 1, p->file) == 1;
}

/* The cache's temporary file in its folder, with the usual permissions (mkstemp makes 0600),
   and its header. */
static bool start_file(app_pc2* p)
{
    size_t len = strlen(p->path) + 16;
    p->temp_path = malloc(len);
    if (!p->temp_path) {
        app_error(p->tool, "out of memory");
        return false;
    }
    snprintf(p->temp_path, len, "%s.tmp-XXXXXX", p->path);
    int fd = mkstemp(p->temp_path);
    if (fd < 0) {
        app_error(p->tool, "%s: cannot create: %s", p->path, strerror(errno));
        free(p->temp_path);
        p->temp_path = NULL;
        return false;
    }
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    p->file = fdopen(fd, "wb");
    if (!p->file) {
        close(fd);
        app_error(p->tool, "%s: cannot write: %s", p->path, strerror(errno));
        return false;
    }
    if (!write_header(p)) {
        app_error(p->tool, "%s: cannot write: %s", p->path, strerror(errno));
        return false;
    }
    return true;
}

int app_pc2_open(app_pc2* p, const char* tool, cvk_sim* sim, const char* path,
                 const cvk_scene_desc* scene, uint32_t every)
{
    memset(p, 0, sizeof *p);
    p->tool = tool;
    p->sim = sim;
    p->path = path;
    p->every = every;
    p->points = cvk_sim_particle_count(sim);
    p->obj_path = rest_mesh_path(path);
    p->folder = app_folder_of(path);
    if (!p->obj_path || !p->folder) {
        app_error(tool, "out of memory");
        return APP_EXIT_FAILURE;
    }
    if (!names_usable(p) || !app_make_output_folder(tool, p->folder))
        return APP_EXIT_BAD_INPUT;
    if (p->points > INT32_MAX) {
        app_error(tool, "--pc2 %s: %llu particles are more than a PC2 file can hold (2^31 - 1)",
                  path, (unsigned long long)p->points);
        return APP_EXIT_BAD_INPUT;
    }
    p->xyz = malloc(3 * p->points * sizeof(float));
    p->bytes = malloc(3 * p->points * 4);
    if (!p->xyz || !p->bytes) {
        app_error(tool, "out of memory for a point cache of %llu particles",
                  (unsigned long long)p->points);
        return APP_EXIT_FAILURE;
    }
    if (!app_obj_frames_init(&p->rest, tool, sim, p->folder, scene) ||
        !app_obj_frames_read(&p->rest) || !start_file(p))
        return APP_EXIT_FAILURE;
    return APP_EXIT_OK;
}

bool app_pc2_write(app_pc2* p)
{
    cvk_error err;
    if (cvk_sim_read_positions(p->sim, p->xyz, p->points, &err) != CVK_SUCCESS) {
        app_error(p->tool, "%s", err.message);
        return false;
    }
    for (uint64_t i = 0; i < 3 * p->points; i++)
        put_f32(p->bytes + 4 * i, p->xyz[i]);
    if (p->points && fwrite(p->bytes, 12 * p->points, 1, p->file) != 1) {
        app_error(p->tool, "%s: cannot write: %s", p->path, strerror(errno));
        return false;
    }
    p->samples++;
    return true;
}

/* The sample count into the header, then everything onto the disk before the rename, so
   that the name never points at a cache the machine could lose half of. */
static bool close_file(app_pc2* p)
{
    unsigned char count[4];
    put_u32(count, p->samples);
    bool ok = fseek(p->file, PC2_SAMPLES_OFFSET, SEEK_SET) == 0 &&
              fwrite(count, sizeof count, 1, p->file) == 1 && fflush(p->file) == 0 &&
              fsync(fileno(p->file)) == 0;
    int saved = errno;
    ok = fclose(p->file) == 0 && ok;
    p->file = NULL;
    if (!ok)
        app_error(p->tool, "%s: cannot write: %s", p->path, strerror(saved ? saved : EIO));
    return ok;
}

static void print_summary(const app_pc2* p, uint32_t frames)
{
    /* A finished run wrote at least the start, sample 0. */
    printf("  PC2 %s: %u sample%s of %llu points (frames 0 to %u of %u, every %u), rest mesh %s\n",
           p->path, p->samples, p->samples == 1 ? "" : "s", (unsigned long long)p->points,
           (p->samples - 1) * p->every, frames, p->every, p->obj_path);
}

int app_pc2_finish(app_pc2* p, uint32_t frames, bool summary)
{
    if (!close_file(p) || !app_obj_write_file(&p->rest, p->obj_path, 0))
        return APP_EXIT_FAILURE;
    if (rename(p->temp_path, p->path) != 0) {
        app_error(p->tool, "%s: cannot write: %s", p->path, strerror(errno));
        unlink(p->obj_path); /* a rest mesh without its cache would only mislead */
        return APP_EXIT_FAILURE;
    }
    free(p->temp_path);
    p->temp_path = NULL;
    if (summary)
        print_summary(p, frames);
    return APP_EXIT_OK;
}

void app_pc2_free(app_pc2* p)
{
    if (p->file)
        fclose(p->file);
    if (p->temp_path)
        unlink(p->temp_path);
    free(p->temp_path);
    free(p->obj_path);
    free(p->folder);
    free(p->xyz);
    free(p->bytes);
    app_obj_frames_free(&p->rest);
    memset(p, 0, sizeof *p);
}
