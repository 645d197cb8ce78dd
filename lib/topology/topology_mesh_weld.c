/* Welding (mesh_reader.h): the vertices faces use, each the first particle within a tolerance
   of it or a new one, found through a hash grid; an OBJ file's particles then renumbered in
   the order of its "v" lines. Welding works in file coordinates, in file order. */
#include "topology/mesh_reader.h"

#include <assimp/scene.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* Vertices closer than this fraction of the bounding-box diagonal are one particle. It is about
   16 float ulps at the diagonal's scale (2^-24 ≈ 6e-8): far above the rounding an exporter adds
   when it writes one position twice for a UV or normal seam (bit-identical or a few ulps apart),
   far below any edge a cloth mesh means (a 1000 × 1000 grid's edges are 7e-4 of its diagonal). */
#define WELD_TOLERANCE 1e-6

/* Marks the vertices faces use (particle_of = 0, others CVK_UNUSED_VERTEX) and measures their
   bounding box; vertices that are not finite are left out of the box (welding reports them). */
static void mark_used(cvk_mesh_reader* r, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (unsigned m = 0; m < r->scene->mNumMeshes; m++) {
        const struct aiMesh* mesh = r->scene->mMeshes[m];
        for (unsigned f = 0; f < mesh->mNumFaces; f++) {
            const struct aiFace* face = &mesh->mFaces[f];
            for (unsigned k = 0; face->mNumIndices >= 3 && k < face->mNumIndices; k++) {
                unsigned v = face->mIndices[k];
                r->particle_of[r->vertex_base[m] + v] = 0;
                const float p[3] = {mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z};
                if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
                    continue;
                for (int c = 0; c < 3; c++) {
                    lo[c] = fmin(lo[c], p[c]);
                    hi[c] = fmax(hi[c], p[c]);
                }
            }
        }
    }
}

/* A hash grid of cells one weld tolerance wide: a vertex's match lies in its cell or one of the
   26 around it. Chains run through the particles, so the grid costs two words per particle. */
typedef struct weld_grid {
    uint32_t* head;   /* per bucket: latest particle, or CVK_UNUSED_VERTEX */
    uint32_t* next;   /* per particle: the one before it in its bucket */
    size_t mask;
    double lo[3];     /* bounding-box minimum: cell coordinates are ≥ 0 from here */
    double cell;      /* file units */
    double tolerance; /* file units */
} weld_grid;

/* Cell coordinates are below 2^21 (the box is 1e6 cells across); one more to keep −1 in range. */
static uint64_t cell_key(int64_t x, int64_t y, int64_t z)
{
    return ((uint64_t)(x + 1) << 42) | ((uint64_t)(y + 1) << 21) | (uint64_t)(z + 1);
}

/* false for a point outside the grid's cells by more than one (an OBJ "v" line of no face, or
   one whose number does not fit a float, read again by obj_vertex_order): it matches no particle,
   and its cell would not fit the key (or, infinite, not an integer: fuzz_mesh found that). */
static bool cell_of(const weld_grid* g, const float p[3], int64_t c[3])
{
    for (int k = 0; k < 3; k++) {
        double cell = floor((p[k] - g->lo[k]) / g->cell);
        if (!(cell >= -1.0 && cell < (double)(1 << 21) - 1.0))
            return false;
        c[k] = (int64_t)cell;
    }
    return true;
}

/* The first particle (lowest index) within the tolerance of p, or CVK_UNUSED_VERTEX. */
static uint32_t weld_find(const weld_grid* g, const float* position, const float p[3])
{
    int64_t c[3];
    if (!cell_of(g, p, c))
        return CVK_UNUSED_VERTEX;
    uint32_t best = CVK_UNUSED_VERTEX;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                size_t b = cvk_hash_u64(cell_key(c[0] + dx, c[1] + dy, c[2] + dz)) & g->mask;
                for (uint32_t q = g->head[b]; q != CVK_UNUSED_VERTEX; q = g->next[q]) {
                    const float* o = &position[3 * (size_t)q];
                    double d[3] = {(double)p[0] - o[0], (double)p[1] - o[1], (double)p[2] - o[2]};
                    double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                    if (q < best && d2 <= g->tolerance * g->tolerance)
                        best = q;
                }
            }
    return best;
}

/* false when p is outside the grid's cells: never for a used vertex, which lies in the box
   the cells were made for. */
static bool weld_insert(weld_grid* g, const float p[3], uint32_t particle)
{
    int64_t c[3];
    if (!cell_of(g, p, c))
        return false;
    size_t b = cvk_hash_u64(cell_key(c[0], c[1], c[2])) & g->mask;
    g->next[particle] = g->head[b];
    g->head[b] = particle;
    return true;
}

/* Walks the used vertices in file order: each becomes the first particle within the tolerance,
   or a new particle. */
static cvk_result weld_walk(cvk_mesh_reader* r, weld_grid* g)
{
    for (unsigned m = 0; m < r->scene->mNumMeshes; m++) {
        const struct aiMesh* mesh = r->scene->mMeshes[m];
        for (unsigned v = 0; v < mesh->mNumVertices; v++) {
            uint32_t* slot = &r->particle_of[r->vertex_base[m] + v];
            if (*slot == CVK_UNUSED_VERTEX)
                continue;
            const float p[3] = {mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z};
            if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
                return cvk_mesh_bad(r, "vertex %u has a coordinate that is not a finite number",
                                r->vertex_count);
            uint32_t found = weld_find(g, r->position, p);
            if (found != CVK_UNUSED_VERTEX) {
                *slot = found;
                continue;
            }
            if ((uint64_t)r->vertex_count + 1 > CVK_MAX_PARTICLES)
                return cvk_fail(r->error, CVK_ERROR_DEVICE_LIMIT,
                                "%s: %s has more than %llu vertices after welding, the most "
                                "particles a scene may hold", r->key, r->path,
                                (unsigned long long)CVK_MAX_PARTICLES);
            if (!weld_insert(g, p, r->vertex_count))
                return cvk_mesh_bad(r, "vertex %u lies outside the box of the vertices faces use",
                                    r->vertex_count);
            memcpy(&r->position[3 * (size_t)r->vertex_count], p, sizeof p);
            *slot = r->vertex_count++;
        }
    }
    return CVK_SUCCESS;
}

/* True when the file is Wavefront OBJ (by its name, as Assimp chooses its reader). */
static bool is_obj(const char* path)
{
    size_t n = strlen(path);
    if (n < 4)
        return false;
    const char* ext = path + n - 4;
    return ext[0] == '.' && (ext[1] | 0x20) == 'o' && (ext[2] | 0x20) == 'b' &&
           (ext[3] | 0x20) == 'j';
}

/* Renumbers the particles so that new_of[old] is each one's place in the order of `rank`
   (lower first; UINT32_MAX last, keeping their order). */
static cvk_result renumber_particles(cvk_mesh_reader* r, const uint32_t* rank, size_t rank_limit)
{
    uint32_t* at = malloc((rank_limit ? rank_limit : 1) * sizeof *at);
    uint32_t* new_of = malloc((r->vertex_count ? r->vertex_count : 1) * sizeof *new_of);
    float* position = malloc(3 * (size_t)(r->vertex_count ? r->vertex_count : 1) * sizeof *position);
    if (!at || !new_of || !position) {
        free(at);
        free(new_of);
        free(position);
        return cvk_mesh_out_of_memory(r, "the file's vertex order");
    }
    memset(at, 0xff, (rank_limit ? rank_limit : 1) * sizeof *at);
    for (uint32_t q = 0; q < r->vertex_count; q++)
        if (rank[q] != UINT32_MAX)
            at[rank[q]] = q;
    uint32_t next = 0;
    for (size_t i = 0; i < rank_limit; i++)
        if (at[i] != UINT32_MAX)
            new_of[at[i]] = next++;
    for (uint32_t q = 0; q < r->vertex_count; q++)
        if (rank[q] == UINT32_MAX)
            new_of[q] = next++;
    for (uint32_t q = 0; q < r->vertex_count; q++)
        memcpy(&position[3 * (size_t)new_of[q]], &r->position[3 * (size_t)q], 3 * sizeof(float));
    for (size_t i = 0; i < r->file_vertex_count; i++)
        if (r->particle_of[i] != CVK_UNUSED_VERTEX)
            r->particle_of[i] = new_of[r->particle_of[i]];
    free(r->position);
    r->position = position;
    free(at);
    free(new_of);
    return CVK_SUCCESS;
}

/* Assimp's OBJ reader yields one vertex per face corner, in face order, so "first appearance"
   would be the order in which faces first use each vertex. What a person means by an OBJ
   file's vertex order — what Blender and every viewer number — is the order of its "v" lines:
   each particle takes the place of the first "v" line at its position. Only the "v" lines are
   read here (x y z, the first three numbers); Assimp has parsed the file already. */
static cvk_result obj_vertex_order(cvk_mesh_reader* r, const weld_grid* g)
{
    FILE* file = fopen(r->path, "r");
    if (!file)
        return cvk_mesh_cannot_read(r, strerror(errno));
    uint32_t* rank = malloc((r->vertex_count ? r->vertex_count : 1) * sizeof *rank);
    if (!rank) {
        fclose(file);
        return cvk_mesh_out_of_memory(r, "the file's vertex order");
    }
    memset(rank, 0xff, (r->vertex_count ? r->vertex_count : 1) * sizeof *rank);
    char line[512];
    size_t lines = 0;
    while (fgets(line, sizeof line, file)) {
        bool whole = strchr(line, '\n') || feof(file);
        if (line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) {
            char* at = line + 2;
            float p[3];
            int k = 0;
            for (char* end; k < 3; k++, at = end) {
                p[k] = strtof(at, &end);
                if (end == at)
                    break;
            }
            uint32_t q = k == 3 ? weld_find(g, r->position, p) : CVK_UNUSED_VERTEX;
            if (q != CVK_UNUSED_VERTEX && rank[q] == UINT32_MAX)
                rank[q] = (uint32_t)lines;
            lines++;
        }
        /* The rest of an overlong line is not a new line. */
        while (!whole && fgets(line, sizeof line, file))
            whole = strchr(line, '\n') != NULL;
    }
    fclose(file);
    cvk_result result = lines <= UINT32_MAX ? renumber_particles(r, rank, lines) : CVK_SUCCESS;
    free(rank);
    return result;
}

cvk_result cvk_mesh_weld(cvk_mesh_reader* r)
{
    unsigned meshes = r->scene->mNumMeshes;
    r->vertex_base = malloc((meshes ? meshes : 1) * sizeof *r->vertex_base);
    r->particle_of = malloc(r->file_vertex_count * sizeof *r->particle_of);
    r->position = malloc(3 * r->file_vertex_count * sizeof *r->position);
    if (!r->vertex_base || !r->particle_of || !r->position)
        return cvk_mesh_out_of_memory(r, "the vertices");
    for (size_t i = 0, base = 0; i < meshes; base += r->scene->mMeshes[i]->mNumVertices, i++)
        r->vertex_base[i] = base;
    for (size_t i = 0; i < r->file_vertex_count; i++)
        r->particle_of[i] = CVK_UNUSED_VERTEX;

    weld_grid g = {0};
    double hi[3];
    mark_used(r, g.lo, hi);
    double d2 = 0.0;
    for (int k = 0; k < 3; k++)
        d2 += hi[k] > g.lo[k] ? (hi[k] - g.lo[k]) * (hi[k] - g.lo[k]) : 0.0;
    r->diagonal = sqrt(d2);
    g.tolerance = WELD_TOLERANCE * r->diagonal;
    g.cell = g.tolerance > 0.0 ? g.tolerance : 1.0; /* one point: every vertex in cell 0 */
    size_t buckets = 16;
    while (buckets < 2 * r->file_vertex_count)
        buckets *= 2;
    g.mask = buckets - 1;
    g.head = malloc(buckets * sizeof *g.head);
    g.next = malloc(r->file_vertex_count * sizeof *g.next);
    cvk_result result = cvk_mesh_out_of_memory(r, "welding");
    if (g.head && g.next) {
        memset(g.head, 0xff, buckets * sizeof *g.head);
        result = weld_walk(r, &g);
    }
    if (result == CVK_SUCCESS && is_obj(r->path))
        result = obj_vertex_order(r, &g);
    free(g.head);
    free(g.next);
    return result;
}
