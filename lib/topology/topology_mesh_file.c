/* A mesh file through Assimp (mesh_reader.h): the import and its checks, the reader's
   messages and its freeing, the faces as particles once welded, and texture coordinates. */
#include "topology/mesh_reader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"

void cvk_mesh_reader_free(cvk_mesh_reader* r)
{
    cvk_assimp_free(r->importer);
    free(r->vertex_base);
    free(r->particle_of);
    free(r->position);
    free(r->face_start);
    free(r->corner);
    free(r->triangles);
    free(r->edge_kind);
    cvk_u64_map_free(&r->edge_map);
    free(r->edge_ends);
    free(r->edge_faces);
    free(r->edge_opposite);
    cvk_u64_map_free(&r->spring_map);
}

cvk_result cvk_mesh_out_of_memory(cvk_mesh_reader* r, const char* what)
{
    return cvk_fail(r->error, CVK_ERROR_OUT_OF_MEMORY, "%s: %s: out of host memory for %s", r->key,
                    r->path, what);
}

/* "cloths.N.mesh: PATH: <problem>" as CVK_ERROR_INVALID_ARGUMENT. */
cvk_result cvk_mesh_bad(cvk_mesh_reader* r, const char* format, ...)
{
    char problem[384];
    va_list args;
    va_start(args, format);
    vsnprintf(problem, sizeof problem, format, args);
    va_end(args);
    return cvk_fail(r->error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s: %s", r->key, r->path, problem);
}

cvk_result cvk_mesh_cannot_read(cvk_mesh_reader* r, const char* reason)
{
    /* Assimp's messages can run over several lines; the first says what went wrong. */
    char line[256];
    snprintf(line, sizeof line, "%s", reason && reason[0] ? reason : "unknown reason");
    line[strcspn(line, "\r\n")] = '\0';
    return cvk_fail(r->error, CVK_ERROR_IO, "%s: cannot read %s: %s", r->key, r->path, line);
}

/* Counts faces of three or more corners and their corners, and checks every index is a vertex
   of its mesh (Assimp passes out-of-range indices of some formats through). */
static cvk_result count_faces(cvk_mesh_reader* r)
{
    const struct aiScene* s = r->scene;
    r->face_count = r->corner_count = r->file_vertex_count = 0;
    for (unsigned m = 0; m < s->mNumMeshes; m++) {
        const struct aiMesh* mesh = s->mMeshes[m];
        for (unsigned f = 0; f < mesh->mNumFaces; f++) {
            const struct aiFace* face = &mesh->mFaces[f];
            if (face->mNumIndices < 3)
                continue;
            for (unsigned k = 0; k < face->mNumIndices; k++)
                if (face->mIndices[k] >= mesh->mNumVertices)
                    return cvk_mesh_bad(r, "face %zu refers to vertex %u of a mesh of %u vertices",
                                    r->face_count, face->mIndices[k], mesh->mNumVertices);
            r->face_count++;
            r->corner_count += face->mNumIndices;
        }
        r->file_vertex_count += mesh->mNumVertices;
    }
    if (r->face_count == 0)
        return cvk_fail(r->error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s has no triangles", r->key,
                        r->path);
    return CVK_SUCCESS;
}

/* A PLY file declares its element counts in its header, and Assimp reserves memory for them
   before it reads an element: 4e9 declared faces ended in "std::bad_alloc". So the counts are
   read first: each at most CVK_MAX_PARTICLES (more vertices than a scene may hold, or faces
   beyond what any cloth of them has), and together no more than the bytes after the header
   hold, an element with a property taking one at least (a binary uchar). */
static cvk_result check_ply_counts(cvk_mesh_reader* r, FILE* file, uint64_t file_size)
{
    char line[256];
    if (!fgets(line, sizeof line, file) || strncmp(line, "ply", 3) != 0 || !strchr("\r\n", line[3]))
        return CVK_SUCCESS; /* not PLY: its reader has no counts to trust */
    unsigned long long count = 0, least_bytes = 0;
    char element[64] = "";
    while (fgets(line, sizeof line, file)) {
        if (strncmp(line, "end_header", 10) == 0) {
            long header = ftell(file);
            uint64_t after = header >= 0 && (uint64_t)header < file_size ? file_size - (uint64_t)header : 0;
            if (least_bytes > after)
                return cvk_mesh_bad(r, "its header declares %llu elements in all, more than the "
                                    "%llu bytes after it hold (a count is wrong or the file is cut "
                                    "short)", least_bytes, (unsigned long long)after);
            return CVK_SUCCESS;
        }
        if (sscanf(line, "element %63s %llu", element, &count) == 2 && count > CVK_MAX_PARTICLES)
            return cvk_mesh_bad(r, "the mesh is too large: its header declares %llu %s elements, "
                                "and a mesh may have at most %llu", count, element,
                                (unsigned long long)CVK_MAX_PARTICLES);
        if (strncmp(line, "property ", 9) == 0 && element[0]) {
            least_bytes += count; /* the element's first property: its elements take bytes */
            element[0] = '\0';
        }
    }
    return CVK_SUCCESS; /* no end to the header: Assimp says what is wrong */
}

/* Imports the file. Node transforms are applied afterwards (aiProcess_PreTransformVertices),
   once the file is known to hold faces: Assimp fails that step on a file of bare vertices, which
   deserves "no triangles", not "cannot read". Neither triangulation nor vertex joining is asked
   for: quads keep their corners (for shear springs) and welding is done here, by distance. */
cvk_result cvk_mesh_open(cvk_mesh_reader* r)
{
    struct stat st;
    if (stat(r->path, &st) != 0)
        return cvk_mesh_cannot_read(r, strerror(errno));
    if (S_ISDIR(st.st_mode))
        return cvk_mesh_cannot_read(r, "it is a directory");
    if (!S_ISREG(st.st_mode)) /* a FIFO would block, a device be read forever */
        return cvk_mesh_cannot_read(r, "it is not a regular file");
    if ((uint64_t)st.st_size > CVK_MAX_MESH_BYTES) {
        char reason[128];
        snprintf(reason, sizeof reason, "%llu bytes; a mesh file is at most %llu",
                 (unsigned long long)st.st_size, (unsigned long long)CVK_MAX_MESH_BYTES);
        return cvk_mesh_cannot_read(r, reason);
    }
    /* Assimp says only "Unable to open file" where the system says why (permissions). */
    FILE* file = fopen(r->path, "rb");
    if (!file)
        return cvk_mesh_cannot_read(r, strerror(errno));
    cvk_result counts = check_ply_counts(r, file, (uint64_t)st.st_size);
    fclose(file);
    if (counts != CVK_SUCCESS)
        return counts;
    char why[256]; /* cvk_mesh_cannot_read keeps 255 characters */
    r->scene = cvk_assimp_read(r->path, &r->importer, why, sizeof why);
    if (!r->scene)
        return cvk_mesh_cannot_read(r, why);
    cvk_result result = count_faces(r);
    if (result != CVK_SUCCESS)
        return result;
    r->scene = cvk_assimp_post_process(r->importer, aiProcess_PreTransformVertices, why,
                                       sizeof why);
    if (!r->scene)
        return cvk_mesh_cannot_read(r, why);
    return count_faces(r);
}

/* ---- after welding --------------------------------------------------------------------------- */

cvk_result cvk_mesh_gather_faces(cvk_mesh_reader* r)
{
    r->face_start = malloc((r->face_count + 1) * sizeof *r->face_start);
    r->corner = malloc(r->corner_count * sizeof *r->corner);
    if (!r->face_start || !r->corner)
        return cvk_mesh_out_of_memory(r, "the faces");
    size_t f = 0, c = 0;
    for (unsigned m = 0; m < r->scene->mNumMeshes; m++) {
        const struct aiMesh* mesh = r->scene->mMeshes[m];
        for (unsigned i = 0; i < mesh->mNumFaces; i++) {
            const struct aiFace* face = &mesh->mFaces[i];
            if (face->mNumIndices < 3)
                continue;
            r->face_start[f++] = c;
            for (unsigned k = 0; k < face->mNumIndices; k++)
                r->corner[c++] = r->particle_of[r->vertex_base[m] + face->mIndices[k]];
        }
    }
    r->face_start[f] = c;
    /* A triangle per corner bounds the triangle count and the edges' and springs' tables. */
    if (r->corner_count > UINT32_MAX / 4)
        return cvk_fail(r->error, CVK_ERROR_DEVICE_LIMIT, "%s: %s has %zu face corners, more than "
                        "%u a cloth may hold", r->key, r->path, r->corner_count, UINT32_MAX / 4);
    return CVK_SUCCESS;
}

/* Texture coordinates per particle: the first set of the first file vertex welded into it
   (vertices repeated only for a UV seam are welded, so a seam stretches the texture). */
cvk_result cvk_mesh_fill_uv(cvk_mesh_reader* r, cvk_topology* out)
{
    out->uv = calloc(2 * (size_t)(r->vertex_count ? r->vertex_count : 1), sizeof *out->uv);
    uint8_t* set = calloc(r->vertex_count ? r->vertex_count : 1, 1);
    if (!out->uv || !set) {
        free(set);
        return cvk_mesh_out_of_memory(r, "the texture coordinates");
    }
    bool any = false;
    for (unsigned m = 0; m < r->scene->mNumMeshes; m++) {
        const struct aiMesh* mesh = r->scene->mMeshes[m];
        if (!mesh->mTextureCoords[0])
            continue;
        any = true;
        for (unsigned v = 0; v < mesh->mNumVertices; v++) {
            uint32_t p = r->particle_of[r->vertex_base[m] + v];
            if (p == CVK_UNUSED_VERTEX || set[p])
                continue;
            set[p] = 1;
            out->uv[2 * (size_t)p] = mesh->mTextureCoords[0][v].x;
            out->uv[2 * (size_t)p + 1] = mesh->mTextureCoords[0][v].y;
        }
    }
    free(set);
    if (!any)
        return cvk_fail(r->error, CVK_ERROR_INVALID_ARGUMENT,
                        "%.*s%s: %s has no texture coordinates to map the texture by",
                        (int)(strlen(r->key) - strlen("mesh")), r->key,
                        !r->cloth->texture          ? "material.normal_map"
                        : r->cloth->material_texture ? "material.texture"
                                                     : "texture",
                        r->path);
    return CVK_SUCCESS;
}
