#include "obj.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common.h"

bool app_obj_frames_init(app_obj_frames* f, const char* tool, cvk_sim* sim, const char* folder,
                         const cvk_scene_desc* scene)
{
    memset(f, 0, sizeof *f);
    f->tool = tool;
    f->sim = sim;
    f->folder = folder;
    f->scene_name = scene->name ? scene->name : "scene";
    f->frame_seconds = (double)scene->dt * scene->substeps;
    f->vertex_count = cvk_sim_particle_count(sim);
    f->triangle_count = cvk_sim_triangle_count(sim);
    f->xyz = malloc(3 * f->vertex_count * sizeof(float));
    f->normals = malloc(3 * f->vertex_count * sizeof(float));
    f->triangles = malloc((3 * f->triangle_count + 1) * sizeof(uint32_t));
    f->path = malloc(strlen(folder) + 32);
    if (!f->xyz || !f->normals || !f->triangles || !f->path) {
        app_error(tool, "out of memory for the OBJ frames of %llu particles and %llu triangles",
                  (unsigned long long)f->vertex_count, (unsigned long long)f->triangle_count);
        app_obj_frames_free(f);
        return false;
    }
    return true;
}

void app_obj_frames_free(app_obj_frames* f)
{
    free(f->xyz);
    free(f->normals);
    free(f->triangles);
    free(f->path);
    f->xyz = f->normals = NULL;
    f->triangles = NULL;
    f->path = NULL;
}

/* ---- one file ------------------------------------------------------------------------------ */

typedef struct obj_job {
    const app_obj_frames* f;
    uint32_t frame;
} obj_job;

/* A torn triangle has three equal indices (see cvk_sim_read_mesh): it is left out. */
static bool triangle_exists(const uint32_t* t)
{
    return !(t[0] == t[1] && t[1] == t[2]);
}

static uint64_t live_triangles(const app_obj_frames* f)
{
    uint64_t live = 0;
    for (uint64_t t = 0; t < f->triangle_count; t++)
        live += triangle_exists(&f->triangles[3 * t]);
    return live;
}

/* "o NAME", its v lines, its vn lines and its f lines. Vertex numbers count from 1 over the
   whole file: particle p (in the order of cvk_sim_read_positions) is vertex p + 1, since the
   cloths follow each other in that order. */
static bool write_cloth(FILE* file, const app_obj_frames* f, uint32_t index)
{
    cvk_cloth_info c = cvk_sim_get_cloth(f->sim, index);
    bool ok = c.name && c.name[0] ? fprintf(file, "o %s\n", c.name) >= 0
                                  : fprintf(file, "o cloth%u\n", index) >= 0;
    uint64_t end = (uint64_t)c.first_particle + c.particle_count;
    for (uint64_t p = c.first_particle; ok && p < end; p++) {
        const float* x = &f->xyz[3 * p];
        ok = fprintf(file, "v %.9g %.9g %.9g\n", x[0], x[1], x[2]) >= 0;
    }
    for (uint64_t p = c.first_particle; ok && p < end; p++) {
        const float* n = &f->normals[3 * p];
        ok = fprintf(file, "vn %.9g %.9g %.9g\n", n[0], n[1], n[2]) >= 0;
    }
    end = (uint64_t)c.first_triangle + c.triangle_count;
    for (uint64_t t = c.first_triangle; ok && t < end; t++) {
        const uint32_t* v = &f->triangles[3 * t];
        if (triangle_exists(v))
            ok = fprintf(file, "f %u//%u %u//%u %u//%u\n", v[0] + 1, v[0] + 1, v[1] + 1, v[1] + 1,
                         v[2] + 1, v[2] + 1) >= 0;
    }
    return ok;
}

static bool write_obj(FILE* file, void* user)
{
    const obj_job* job = user;
    const app_obj_frames* f = job->f;
    if (fprintf(file,
                "# %s: scene %s, frame %u (t = %g s): %llu vertices, %llu triangles, "
                "positions in m\n",
                f->tool, f->scene_name, job->frame, job->frame * f->frame_seconds,
                (unsigned long long)f->vertex_count, (unsigned long long)live_triangles(f)) < 0)
        return false;
    uint32_t cloths = cvk_sim_cloth_count(f->sim);
    for (uint32_t c = 0; c < cloths; c++)
        if (!write_cloth(file, f, c))
            return false;
    return true;
}

bool app_obj_frames_read(app_obj_frames* f)
{
    cvk_error err;
    if (cvk_sim_read_mesh(f->sim, f->xyz, f->normals, f->triangles, f->vertex_count,
                          f->triangle_count, &err) != CVK_SUCCESS) {
        app_error(f->tool, "%s", err.message);
        return false;
    }
    return true;
}

bool app_obj_write_file(const app_obj_frames* f, const char* path, uint32_t frame)
{
    obj_job job = {f, frame};
    char message[600];
    if (!app_write_atomic(path, write_obj, &job, message, sizeof message)) {
        app_error(f->tool, "%s", message);
        return false;
    }
    return true;
}

bool app_obj_frames_write(app_obj_frames* f, uint32_t number, uint32_t frame)
{
    if (!app_obj_frames_read(f))
        return false;
    snprintf(f->path, strlen(f->folder) + 32, "%s/frame_%04u.obj", f->folder, number);
    if (!app_obj_write_file(f, f->path, frame))
        return false;
    f->written++;
    return true;
}
