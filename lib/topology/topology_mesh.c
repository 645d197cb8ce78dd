/* Cloth from a mesh file: Assimp reads the file; this file welds its vertices into particles,
   splits its faces into triangles and lays springs along the file's own edges.

   Everything is decided in file order, so one file always gives the same particles, triangles
   and springs in the same order: particles are the welded vertices once, in order of first
   appearance (meshes in the order Assimp yields them, each mesh's vertices in order, vertices
   no face uses skipped) — for OBJ files, in the order of their "v" lines (obj_vertex_order);
   faces are numbered 0, 1, ... over the faces of three or more corners in the same walk. Welding and the degenerate-face checks work in file coordinates; the
   transform is applied last. */
#include "topology/topology.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"
#include "core/vec3.h"
#include "core/u64_map.h"

/* Vertices closer than this fraction of the bounding-box diagonal are one particle. It is about
   16 float ulps at the diagonal's scale (2^-24 ≈ 6e-8): far above the rounding an exporter adds
   when it writes one position twice for a UV or normal seam (bit-identical or a few ulps apart),
   far below any edge a cloth mesh means (a 1000 × 1000 grid's edges are 7e-4 of its diagonal). */
#define WELD_TOLERANCE 1e-6

/* Triangles of less area than this fraction of diagonal² are degenerate. A triangle whose edges
   are at least the weld tolerance (1e-6 · diagonal) long but whose area is below 1e-12 · diagonal²
   is a sliver: with an edge of 1e-3 · diagonal its height is 2e-9 · diagonal, thirty times below
   float resolution there, so its normal and area are rounding noise. */
#define DEGENERATE_AREA 1e-12

/* Faces of more than four corners are fanned from their first corner only when that is safe:
   every corner within this fraction of the face's size from its plane, and the boundary never
   turning against the face's normal by more than this sine (collinear corners are fine). */
#define PLANAR_TOLERANCE 1e-3
#define CONVEX_TOLERANCE 1e-6

#define UNUSED_VERTEX UINT32_MAX
/* Why a triangle edge is there: an edge of the file's face, a quad's split diagonal (its shear
   spring), or a diagonal added to fan a larger face (no spring). */
enum { EDGE_FACE = 0, EDGE_QUAD_DIAGONAL = 1, EDGE_FAN_DIAGONAL = 2 };

/* An unordered pair of particles as one key. */
static uint64_t pair_key(uint32_t a, uint32_t b)
{
    return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}

/* ---- the reader ------------------------------------------------------------------------------ */

typedef struct mesh_reader {
    const cvk_cloth_desc* cloth;
    const char* path;
    char key[CVK_KEY_PATH_MAX];   /* "cloths.N.mesh" */
    cvk_error* error;
    const struct aiScene* scene;

    size_t file_vertex_count;     /* over all meshes */
    size_t* vertex_base;          /* per mesh: its first vertex among all meshes' */
    uint32_t* particle_of;        /* per file vertex: its particle, or UNUSED_VERTEX */
    uint32_t vertex_count;
    float* position;              /* xyz per particle, file units, before the transform */
    double diagonal;              /* of the used vertices' bounding box, file units */

    size_t face_count;            /* faces of three or more corners */
    size_t corner_count;
    size_t* face_start;           /* face f's corners: corner[face_start[f] .. face_start[f + 1]) */
    uint32_t* corner;             /* particles */

    uint32_t triangle_count;
    uint32_t* triangles;          /* 3 particles per triangle, the file's winding */
    uint8_t* edge_kind;           /* 3 per triangle: EDGE_FACE ... for (v0,v1), (v1,v2), (v2,v0) */

    cvk_u64_map edge_map;             /* pair -> edge, for the faces' own edges */
    uint32_t edge_count;
    uint32_t* edge_ends;          /* 2 per edge, as first met */
    uint32_t* edge_faces;         /* per edge: how many faces have it */
    uint32_t* edge_opposite;      /* 2 per edge: the corner opposite it in the triangle on each side */

    cvk_u64_map spring_map;           /* pair -> spring */
} mesh_reader;

static void reader_free(mesh_reader* r)
{
    if (r->scene)
        aiReleaseImport(r->scene);
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

static cvk_result out_of_memory(mesh_reader* r, const char* what)
{
    return cvk_fail(r->error, CVK_ERROR_OUT_OF_MEMORY, "%s: %s: out of host memory for %s", r->key,
                    r->path, what);
}

/* "cloths.N.mesh: PATH: <problem>" as CVK_ERROR_INVALID_ARGUMENT. */
__attribute__((format(printf, 2, 3)))
static cvk_result bad_mesh(mesh_reader* r, const char* format, ...)
{
    char problem[384];
    va_list args;
    va_start(args, format);
    vsnprintf(problem, sizeof problem, format, args);
    va_end(args);
    return cvk_fail(r->error, CVK_ERROR_INVALID_ARGUMENT, "%s: %s: %s", r->key, r->path, problem);
}

static cvk_result cannot_read(mesh_reader* r, const char* reason)
{
    /* Assimp's messages can run over several lines; the first says what went wrong. */
    char line[256];
    snprintf(line, sizeof line, "%s", reason && reason[0] ? reason : "unknown reason");
    line[strcspn(line, "\r\n")] = '\0';
    return cvk_fail(r->error, CVK_ERROR_IO, "%s: cannot read %s: %s", r->key, r->path, line);
}

/* Counts faces of three or more corners and their corners, and checks every index is a vertex
   of its mesh (Assimp passes out-of-range indices of some formats through). */
static cvk_result count_faces(mesh_reader* r)
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
                    return bad_mesh(r, "face %zu refers to vertex %u of a mesh of %u vertices",
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

/* Imports the file. Node transforms are applied afterwards (aiProcess_PreTransformVertices),
   once the file is known to hold faces: Assimp fails that step on a file of bare vertices, which
   deserves "no triangles", not "cannot read". Neither triangulation nor vertex joining is asked
   for: quads keep their corners (for shear springs) and welding is done here, by distance. */
static cvk_result open_scene(mesh_reader* r)
{
    struct stat st;
    if (stat(r->path, &st) != 0)
        return cannot_read(r, strerror(errno));
    if (S_ISDIR(st.st_mode))
        return cannot_read(r, "it is a directory");
    if (!S_ISREG(st.st_mode)) /* a FIFO would block, a device be read forever */
        return cannot_read(r, "it is not a regular file");
    if ((uint64_t)st.st_size > CVK_MAX_MESH_BYTES) {
        char reason[128];
        snprintf(reason, sizeof reason, "%llu bytes; a mesh file is at most %llu",
                 (unsigned long long)st.st_size, (unsigned long long)CVK_MAX_MESH_BYTES);
        return cannot_read(r, reason);
    }
    /* Assimp says only "Unable to open file" where the system says why (permissions). */
    FILE* file = fopen(r->path, "rb");
    if (!file)
        return cannot_read(r, strerror(errno));
    fclose(file);
    r->scene = aiImportFile(r->path, 0);
    if (!r->scene)
        return cannot_read(r, aiGetErrorString());
    cvk_result result = count_faces(r);
    if (result != CVK_SUCCESS)
        return result;
    /* On failure Assimp releases the scene itself. */
    r->scene = aiApplyPostProcessing(r->scene, aiProcess_PreTransformVertices);
    if (!r->scene)
        return cannot_read(r, aiGetErrorString());
    return count_faces(r);
}

/* ---- welding --------------------------------------------------------------------------------- */

/* Marks the vertices faces use (particle_of = 0, others UNUSED_VERTEX) and measures their
   bounding box; vertices that are not finite are left out of the box (welding reports them). */
static void mark_used(mesh_reader* r, double lo[3], double hi[3])
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
    uint32_t* head;   /* per bucket: latest particle, or UNUSED_VERTEX */
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

/* The first particle (lowest index) within the tolerance of p, or UNUSED_VERTEX. */
static uint32_t weld_find(const weld_grid* g, const float* position, const float p[3])
{
    int64_t c[3];
    if (!cell_of(g, p, c))
        return UNUSED_VERTEX;
    uint32_t best = UNUSED_VERTEX;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                size_t b = cvk_hash_u64(cell_key(c[0] + dx, c[1] + dy, c[2] + dz)) & g->mask;
                for (uint32_t q = g->head[b]; q != UNUSED_VERTEX; q = g->next[q]) {
                    const float* o = &position[3 * (size_t)q];
                    double d[3] = {(double)p[0] - o[0], (double)p[1] - o[1], (double)p[2] - o[2]};
                    double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                    if (q < best && d2 <= g->tolerance * g->tolerance)
                        best = q;
                }
            }
    return best;
}

static void weld_insert(weld_grid* g, const float p[3], uint32_t particle)
{
    int64_t c[3];
    cell_of(g, p, c); /* a particle lies in the box: always in range */
    size_t b = cvk_hash_u64(cell_key(c[0], c[1], c[2])) & g->mask;
    g->next[particle] = g->head[b];
    g->head[b] = particle;
}

/* Walks the used vertices in file order: each becomes the first particle within the tolerance,
   or a new particle. */
static cvk_result weld_walk(mesh_reader* r, weld_grid* g)
{
    for (unsigned m = 0; m < r->scene->mNumMeshes; m++) {
        const struct aiMesh* mesh = r->scene->mMeshes[m];
        for (unsigned v = 0; v < mesh->mNumVertices; v++) {
            uint32_t* slot = &r->particle_of[r->vertex_base[m] + v];
            if (*slot == UNUSED_VERTEX)
                continue;
            const float p[3] = {mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z};
            if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
                return bad_mesh(r, "vertex %u has a coordinate that is not a finite number",
                                r->vertex_count);
            uint32_t found = weld_find(g, r->position, p);
            if (found != UNUSED_VERTEX) {
                *slot = found;
                continue;
            }
            if ((uint64_t)r->vertex_count + 1 > CVK_MAX_PARTICLES)
                return cvk_fail(r->error, CVK_ERROR_DEVICE_LIMIT,
                                "%s: %s has more than %llu vertices after welding, the most "
                                "particles a scene may hold", r->key, r->path,
                                (unsigned long long)CVK_MAX_PARTICLES);
            memcpy(&r->position[3 * (size_t)r->vertex_count], p, sizeof p);
            weld_insert(g, p, r->vertex_count);
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
static cvk_result renumber_particles(mesh_reader* r, const uint32_t* rank, size_t rank_limit)
{
    uint32_t* at = malloc((rank_limit ? rank_limit : 1) * sizeof *at);
    uint32_t* new_of = malloc((r->vertex_count ? r->vertex_count : 1) * sizeof *new_of);
    float* position = malloc(3 * (size_t)(r->vertex_count ? r->vertex_count : 1) * sizeof *position);
    if (!at || !new_of || !position) {
        free(at);
        free(new_of);
        free(position);
        return out_of_memory(r, "the file's vertex order");
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
        if (r->particle_of[i] != UNUSED_VERTEX)
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
static cvk_result obj_vertex_order(mesh_reader* r, const weld_grid* g)
{
    FILE* file = fopen(r->path, "r");
    if (!file)
        return cannot_read(r, strerror(errno));
    uint32_t* rank = malloc((r->vertex_count ? r->vertex_count : 1) * sizeof *rank);
    if (!rank) {
        fclose(file);
        return out_of_memory(r, "the file's vertex order");
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
            uint32_t q = k == 3 ? weld_find(g, r->position, p) : UNUSED_VERTEX;
            if (q != UNUSED_VERTEX && rank[q] == UINT32_MAX)
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

static cvk_result weld(mesh_reader* r)
{
    unsigned meshes = r->scene->mNumMeshes;
    r->vertex_base = malloc((meshes ? meshes : 1) * sizeof *r->vertex_base);
    r->particle_of = malloc(r->file_vertex_count * sizeof *r->particle_of);
    r->position = malloc(3 * r->file_vertex_count * sizeof *r->position);
    if (!r->vertex_base || !r->particle_of || !r->position)
        return out_of_memory(r, "the vertices");
    for (size_t i = 0, base = 0; i < meshes; base += r->scene->mMeshes[i]->mNumVertices, i++)
        r->vertex_base[i] = base;
    for (size_t i = 0; i < r->file_vertex_count; i++)
        r->particle_of[i] = UNUSED_VERTEX;

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
    cvk_result result = out_of_memory(r, "welding");
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

/* ---- faces into triangles -------------------------------------------------------------------- */

static cvk_result gather_faces(mesh_reader* r)
{
    r->face_start = malloc((r->face_count + 1) * sizeof *r->face_start);
    r->corner = malloc(r->corner_count * sizeof *r->corner);
    if (!r->face_start || !r->corner)
        return out_of_memory(r, "the faces");
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

static void sub3(const float* a, const float* b, double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = (double)a[k] - b[k];
}


static bool degenerate(const mesh_reader* r, const uint32_t t[3])
{
    double e1[3], e2[3], c[3];
    sub3(&r->position[3 * (size_t)t[1]], &r->position[3 * (size_t)t[0]], e1);
    sub3(&r->position[3 * (size_t)t[2]], &r->position[3 * (size_t)t[0]], e2);
    cvk_cross3d(e1, e2, c);
    return 0.5 * sqrt(cvk_dot3d(c, c)) < DEGENERATE_AREA * r->diagonal * r->diagonal;
}

/* Whether a face of n > 4 corners is planar and convex, so that a fan from its first corner
   covers it exactly. The normal is Newell's, which any simple polygon has. */
static bool fan_safe(const mesh_reader* r, const uint32_t* c, size_t n)
{
    double normal[3] = {0.0, 0.0, 0.0}, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3];
    for (int k = 0; k < 3; k++)
        hi[k] = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        const float* p = &r->position[3 * (size_t)c[i]];
        const float* q = &r->position[3 * (size_t)c[(i + 1) % n]];
        normal[0] += ((double)p[1] - q[1]) * ((double)p[2] + q[2]);
        normal[1] += ((double)p[2] - q[2]) * ((double)p[0] + q[0]);
        normal[2] += ((double)p[0] - q[0]) * ((double)p[1] + q[1]);
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], p[k]);
            hi[k] = fmax(hi[k], p[k]);
        }
    }
    double length = sqrt(cvk_dot3d(normal, normal));
    if (length == 0.0)
        return false;
    double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    double size = sqrt(cvk_dot3d(d, d));
    for (int k = 0; k < 3; k++)
        normal[k] /= length;
    for (size_t i = 0; i < n; i++) {
        const float* p0 = &r->position[3 * (size_t)c[i]];
        const float* p1 = &r->position[3 * (size_t)c[(i + 1) % n]];
        const float* p2 = &r->position[3 * (size_t)c[(i + 2) % n]];
        double a[3], b[3], turn[3], off[3];
        sub3(p1, p0, a);
        sub3(p2, p1, b);
        sub3(p0, &r->position[3 * (size_t)c[0]], off);
        cvk_cross3d(a, b, turn);
        if (fabs(cvk_dot3d(off, normal)) > PLANAR_TOLERANCE * size)
            return false;
        if (cvk_dot3d(turn, normal) < -CONVEX_TOLERANCE * sqrt(cvk_dot3d(a, a) * cvk_dot3d(b, b)))
            return false;
    }
    return true;
}

static void emit_triangle(mesh_reader* r, uint32_t a, uint32_t b, uint32_t c, uint8_t k0,
                          uint8_t k1, uint8_t k2)
{
    size_t t = r->triangle_count++;
    r->triangles[3 * t] = a;
    r->triangles[3 * t + 1] = b;
    r->triangles[3 * t + 2] = c;
    r->edge_kind[3 * t] = k0;
    r->edge_kind[3 * t + 1] = k1;
    r->edge_kind[3 * t + 2] = k2;
}

/* Quads split along v1–v3 into (v0, v1, v3) and (v1, v2, v3), so that a grid written as quads
   a b d c gives the grid's own triangles (a, b, c), (b, d, c); larger faces are fanned from
   their first corner. Winding is kept. */
static void split_face(mesh_reader* r, const uint32_t* c, size_t n)
{
    if (n == 3) {
        emit_triangle(r, c[0], c[1], c[2], EDGE_FACE, EDGE_FACE, EDGE_FACE);
    } else if (n == 4) {
        emit_triangle(r, c[0], c[1], c[3], EDGE_FACE, EDGE_QUAD_DIAGONAL, EDGE_FACE);
        emit_triangle(r, c[1], c[2], c[3], EDGE_FACE, EDGE_FACE, EDGE_QUAD_DIAGONAL);
    } else {
        for (size_t k = 1; k + 1 < n; k++)
            emit_triangle(r, c[0], c[k], c[k + 1], k == 1 ? EDGE_FACE : EDGE_FAN_DIAGONAL,
                          EDGE_FACE, k + 2 == n ? EDGE_FACE : EDGE_FAN_DIAGONAL);
    }
}

/* Splits every face, checking on the way that no face repeats a particle (two corners welded
   together), that larger faces can be fanned, and that no triangle has zero area. */
static cvk_result split_faces(mesh_reader* r)
{
    r->triangles = malloc(3 * r->corner_count * sizeof *r->triangles);
    r->edge_kind = malloc(3 * r->corner_count * sizeof *r->edge_kind);
    size_t* stamp = calloc(r->vertex_count, sizeof *stamp); /* face + 1 that last used a particle */
    cvk_result result = CVK_SUCCESS;
    if (!r->triangles || !r->edge_kind || !stamp)
        result = out_of_memory(r, "the triangles");
    for (size_t f = 0; f < r->face_count && result == CVK_SUCCESS; f++) {
        const uint32_t* c = &r->corner[r->face_start[f]];
        size_t n = r->face_start[f + 1] - r->face_start[f];
        bool repeats = false;
        for (size_t i = 0; i < n; i++) {
            repeats = repeats || stamp[c[i]] == f + 1;
            stamp[c[i]] = f + 1;
        }
        if (!repeats && n > 4 && !fan_safe(r, c, n)) {
            result = bad_mesh(r, "face %zu has %zu corners and is not planar and convex, so it "
                              "cannot be split into triangles; triangulate it", f, n);
            break;
        }
        uint32_t first = r->triangle_count;
        split_face(r, c, n);
        for (uint32_t t = first; t < r->triangle_count; t++)
            repeats = repeats || degenerate(r, &r->triangles[3 * (size_t)t]);
        if (repeats)
            result = bad_mesh(r, "face %zu is degenerate (zero area)", f);
    }
    free(stamp);
    return result;
}

/* ---- edges and springs ----------------------------------------------------------------------- */

/* Every edge of the file's faces once, in order of first appearance (faces in order, each
   face's edges from its first corner), with the number of faces that have it. */
static cvk_result find_edges(mesh_reader* r)
{
    r->edge_ends = malloc(2 * r->corner_count * sizeof *r->edge_ends);
    r->edge_faces = calloc(r->corner_count, sizeof *r->edge_faces);
    r->edge_opposite = malloc(2 * r->corner_count * sizeof *r->edge_opposite);
    if (!r->edge_ends || !r->edge_faces || !r->edge_opposite ||
        !cvk_u64_map_init(&r->edge_map, r->corner_count))
        return out_of_memory(r, "the edges");
    for (size_t f = 0; f < r->face_count; f++) {
        const uint32_t* c = &r->corner[r->face_start[f]];
        size_t n = r->face_start[f + 1] - r->face_start[f];
        for (size_t i = 0; i < n; i++) {
            uint32_t a = c[i], b = c[(i + 1) % n];
            size_t slot = cvk_u64_map_slot(&r->edge_map, pair_key(a, b));
            if (r->edge_map.key[slot] == CVK_U64_MAP_EMPTY) {
                r->edge_map.key[slot] = pair_key(a, b);
                r->edge_map.value[slot] = r->edge_count;
                r->edge_ends[2 * (size_t)r->edge_count] = a;
                r->edge_ends[2 * (size_t)r->edge_count + 1] = b;
                r->edge_count++;
            }
            r->edge_faces[r->edge_map.value[slot]]++;
        }
    }
    for (uint32_t e = 0; e < r->edge_count; e++) {
        if (r->edge_faces[e] <= 2)
            continue;
        uint32_t a = r->edge_ends[2 * (size_t)e], b = r->edge_ends[2 * (size_t)e + 1];
        return bad_mesh(r, "the edge between vertices %u and %u is shared by %u faces "
                        "(non-manifold)", a < b ? a : b, a < b ? b : a, r->edge_faces[e]);
    }
    return CVK_SUCCESS;
}

/* For each face edge, the corner opposite it in the triangle that holds it: the two ends of a
   bend spring across an interior edge. Two triangles on one edge with the same opposite
   corner are one triangle twice (a face the file repeats): each of its edges then has two
   faces, which the non-manifold check cannot see, and it would count its mass twice. */
static cvk_result find_opposites(mesh_reader* r)
{
    uint32_t* seen = r->edge_faces; /* reused as a count of sides filled */
    memset(seen, 0, r->edge_count * sizeof *seen);
    for (uint32_t t = 0; t < r->triangle_count; t++) {
        const uint32_t* v = &r->triangles[3 * (size_t)t];
        for (int k = 0; k < 3; k++) {
            if (r->edge_kind[3 * (size_t)t + k] != EDGE_FACE)
                continue;
            size_t slot = cvk_u64_map_slot(&r->edge_map, pair_key(v[k], v[(k + 1) % 3]));
            uint32_t e = r->edge_map.value[slot];
            r->edge_opposite[2 * (size_t)e + seen[e]++] = v[(k + 2) % 3];
        }
    }
    for (uint32_t e = 0; e < r->edge_count; e++) {
        const uint32_t* o = &r->edge_opposite[2 * (size_t)e];
        if (seen[e] < 2 || o[0] != o[1])
            continue;
        uint32_t a = r->edge_ends[2 * (size_t)e], b = r->edge_ends[2 * (size_t)e + 1];
        return bad_mesh(r, "the faces on the edge between vertices %u and %u both have corner "
                        "%u (a face repeated)", a < b ? a : b, a < b ? b : a, o[0]);
    }
    return CVK_SUCCESS;
}

/* Adds spring (a, b) unless the pair already has one. */
static void add_spring(mesh_reader* r, cvk_topology* out, uint32_t a, uint32_t b, uint32_t type)
{
    if (a == b)
        return;
    size_t slot = cvk_u64_map_slot(&r->spring_map, pair_key(a, b));
    if (r->spring_map.key[slot] != CVK_U64_MAP_EMPTY)
        return;
    r->spring_map.key[slot] = pair_key(a, b);
    r->spring_map.value[slot] = out->spring_count;
    out->springs[out->spring_count++] = (cvk_topo_spring){.a = a, .b = b, .type = type};
}

/* Structural springs on the edges, then shear springs across quads, then bend springs across
   interior edges; each kind only with non-zero stiffness, and the first spring of a pair wins. */
static cvk_result lay_springs(mesh_reader* r, cvk_topology* out)
{
    size_t most = 2 * (size_t)r->edge_count + r->corner_count;
    out->springs = malloc(most * sizeof *out->springs);
    if (!out->springs || !cvk_u64_map_init(&r->spring_map, most))
        return out_of_memory(r, "the springs");
    const cvk_stiffness* k = &r->cloth->stiffness;
    for (uint32_t e = 0; k->structural > 0.0f && e < r->edge_count; e++)
        add_spring(r, out, r->edge_ends[2 * (size_t)e], r->edge_ends[2 * (size_t)e + 1],
                   CVK_SPRING_STRUCTURAL);
    for (size_t f = 0; k->shear > 0.0f && f < r->face_count; f++) {
        const uint32_t* c = &r->corner[r->face_start[f]];
        if (r->face_start[f + 1] - r->face_start[f] != 4)
            continue;
        add_spring(r, out, c[0], c[2], CVK_SPRING_SHEAR);
        add_spring(r, out, c[1], c[3], CVK_SPRING_SHEAR);
    }
    for (uint32_t e = 0; k->bend > 0.0f && e < r->edge_count; e++)
        if (r->edge_faces[e] == 2)
            add_spring(r, out, r->edge_opposite[2 * (size_t)e], r->edge_opposite[2 * (size_t)e + 1],
                       CVK_SPRING_BEND);
    return CVK_SUCCESS;
}

/* Per triangle edge: the spring on a face edge (structural), on a quad's split diagonal (its
   shear spring), none on a fan diagonal. */
static cvk_result link_triangle_springs(mesh_reader* r, cvk_topology* out)
{
    out->triangle_springs = malloc(3 * (size_t)r->triangle_count * sizeof *out->triangle_springs);
    if (!out->triangle_springs)
        return out_of_memory(r, "the triangles' springs");
    const cvk_stiffness* k = &r->cloth->stiffness;
    for (uint32_t t = 0; t < r->triangle_count; t++) {
        const uint32_t* v = &r->triangles[3 * (size_t)t];
        for (int e = 0; e < 3; e++) {
            uint8_t kind = r->edge_kind[3 * (size_t)t + e];
            bool has = (kind == EDGE_FACE && k->structural > 0.0f) ||
                       (kind == EDGE_QUAD_DIAGONAL && k->shear > 0.0f);
            size_t slot = cvk_u64_map_slot(&r->spring_map, pair_key(v[e], v[(e + 1) % 3]));
            out->triangle_springs[3 * (size_t)t + e] =
                has && r->spring_map.key[slot] != CVK_U64_MAP_EMPTY ? r->spring_map.value[slot] : CVK_NO_SPRING;
        }
    }
    return CVK_SUCCESS;
}

/* ---- output ---------------------------------------------------------------------------------- */

/* x' = translation + rotation (scale ⊙ x), the rotation a unit quaternion [w, x, y, z]:
   v' = v + 2w (u × v) + 2 u × (u × v), u its vector part. */
static void transform_positions(const cvk_transform* t, const float* in, float* out, uint32_t n)
{
    double q[4] = {t->rotation[0], t->rotation[1], t->rotation[2], t->rotation[3]};
    double norm = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; k++)
        q[k] = norm > 0.0 && isfinite(norm) ? q[k] / norm : (k == 0); /* scene checks catch 0 */
    const double u[3] = {q[1], q[2], q[3]};
    for (uint32_t i = 0; i < n; i++) {
        double v[3], c[3], cc[3];
        for (int k = 0; k < 3; k++)
            v[k] = (double)in[3 * (size_t)i + k] * t->scale[k];
        cvk_cross3d(u, v, c);
        cvk_cross3d(u, c, cc);
        for (int k = 0; k < 3; k++)
            out[3 * (size_t)i + k] = (float)(v[k] + 2.0 * q[0] * c[k] + 2.0 * cc[k] + t->translation[k]);
    }
}

/* The simulation works in metres in single precision: positions beyond MAX_COORDINATE are
   resolved to worse than 0.1 mm (2^-24 · 1e6 m ≈ 0.06 m at 1e6 m; spring lengths, squared,
   overflow far sooner at 1e30), and a cloth smaller than MIN_EXTENT has springs whose squared
   lengths approach float's smallest numbers. Either gives garbage, not a simulation. */
#define MAX_COORDINATE 1e5
#define MIN_EXTENT 1e-4

static cvk_result check_extent(mesh_reader* r, const float* position)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < r->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            double x = position[3 * (size_t)v + k];
            if (!(fabs(x) <= MAX_COORDINATE))
                return bad_mesh(r, "vertex %u lies %g m from the origin on axis %c (after the "
                                "transform); positions are single-precision metres, at most "
                                "%g m", v, fabs(x), "xyz"[k], MAX_COORDINATE);
            lo[k] = fmin(lo[k], x);
            hi[k] = fmax(hi[k], x);
        }
    double d2 = 0.0;
    for (int k = 0; k < 3; k++)
        d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    if (sqrt(d2) < MIN_EXTENT)
        return bad_mesh(r, "the mesh is %g m across (after the transform); positions are "
                        "single-precision metres, at least %g m across", sqrt(d2), MIN_EXTENT);
    return CVK_SUCCESS;
}

/* Texture coordinates per particle: the first set of the first file vertex welded into it
   (vertices repeated only for a UV seam are welded, so a seam stretches the texture). */
static cvk_result fill_uv(mesh_reader* r, cvk_topology* out)
{
    out->uv = calloc(2 * (size_t)(r->vertex_count ? r->vertex_count : 1), sizeof *out->uv);
    uint8_t* set = calloc(r->vertex_count ? r->vertex_count : 1, 1);
    if (!out->uv || !set) {
        free(set);
        return out_of_memory(r, "the texture coordinates");
    }
    bool any = false;
    for (unsigned m = 0; m < r->scene->mNumMeshes; m++) {
        const struct aiMesh* mesh = r->scene->mMeshes[m];
        if (!mesh->mTextureCoords[0])
            continue;
        any = true;
        for (unsigned v = 0; v < mesh->mNumVertices; v++) {
            uint32_t p = r->particle_of[r->vertex_base[m] + v];
            if (p == UNUSED_VERTEX || set[p])
                continue;
            set[p] = 1;
            out->uv[2 * (size_t)p] = mesh->mTextureCoords[0][v].x;
            out->uv[2 * (size_t)p + 1] = mesh->mTextureCoords[0][v].y;
        }
    }
    free(set);
    if (!any)
        return cvk_fail(r->error, CVK_ERROR_INVALID_ARGUMENT,
                        "%.*stexture: %s has no texture coordinates to map the texture by",
                        (int)(strlen(r->key) - strlen("mesh")), r->key, r->path);
    return CVK_SUCCESS;
}

static cvk_result fill_output(mesh_reader* r, cvk_topology* out)
{
    out->vertex_count = r->vertex_count;
    out->position = malloc(3 * (size_t)r->vertex_count * sizeof *out->position);
    out->mass = calloc(r->vertex_count, sizeof *out->mass);
    out->pinned = calloc(r->vertex_count, sizeof *out->pinned);
    if (!out->position || !out->mass || !out->pinned)
        return out_of_memory(r, "the particles");
    transform_positions(&r->cloth->transform, r->position, out->position, r->vertex_count);
    cvk_result result = check_extent(r, out->position);
    if (result != CVK_SUCCESS)
        return result;
    out->triangle_count = r->triangle_count;
    out->triangles = r->triangles;
    r->triangles = NULL;
    return r->cloth->texture ? fill_uv(r, out) : CVK_SUCCESS;
}

static cvk_result read_mesh(mesh_reader* r, cvk_topology* out)
{
    cvk_result result = open_scene(r);
    if (result == CVK_SUCCESS)
        result = weld(r);
    if (result == CVK_SUCCESS)
        result = gather_faces(r);
    if (result == CVK_SUCCESS)
        result = split_faces(r);
    if (result == CVK_SUCCESS)
        result = find_edges(r);
    if (result == CVK_SUCCESS)
        result = find_opposites(r);
    if (result == CVK_SUCCESS)
        result = lay_springs(r, out);
    if (result == CVK_SUCCESS)
        result = link_triangle_springs(r, out);
    if (result == CVK_SUCCESS)
        result = fill_output(r, out);
    return result;
}

/* The same reader up to the triangles (welded, checked, no springs), then the transform. */
cvk_result cvk_topology_mesh_triangles(const char* path, const cvk_transform* transform,
                                       const char* key, cvk_mesh_triangles* out, cvk_error* error)
{
    memset(out, 0, sizeof *out);
    mesh_reader r = {.path = path, .error = error};
    snprintf(r.key, sizeof r.key, "%s", key);
    cvk_result result = open_scene(&r);
    if (result == CVK_SUCCESS)
        result = weld(&r);
    if (result == CVK_SUCCESS)
        result = gather_faces(&r);
    if (result == CVK_SUCCESS)
        result = split_faces(&r);
    if (result == CVK_SUCCESS)
        result = find_edges(&r);
    if (result == CVK_SUCCESS)
        result = find_opposites(&r);
    if (result == CVK_SUCCESS) {
        out->xyz = malloc(3 * (size_t)r.vertex_count * sizeof *out->xyz);
        result = out->xyz ? CVK_SUCCESS : out_of_memory(&r, "the vertices");
    }
    if (result == CVK_SUCCESS) {
        out->vertex_count = r.vertex_count;
        transform_positions(transform, r.position, out->xyz, r.vertex_count);
        result = check_extent(&r, out->xyz);
    }
    if (result == CVK_SUCCESS) {
        out->triangle_count = r.triangle_count;
        out->triangles = r.triangles;
        r.triangles = NULL;
    }
    reader_free(&r);
    if (result != CVK_SUCCESS)
        cvk_mesh_triangles_free(out);
    return result;
}

void cvk_mesh_triangles_free(cvk_mesh_triangles* mesh)
{
    free(mesh->xyz);
    free(mesh->triangles);
    memset(mesh, 0, sizeof *mesh);
}

cvk_result cvk_topology_mesh(const cvk_cloth_desc* cloth, uint32_t index, cvk_topology* out,
                             cvk_error* error)
{
    memset(out, 0, sizeof *out);
    mesh_reader r = {.cloth = cloth, .path = cloth->mesh, .error = error};
    cvk_key_path(r.key, "cloths.%u.mesh", index);
    cvk_result result = read_mesh(&r, out);
    reader_free(&r);
    if (result != CVK_SUCCESS)
        cvk_topology_destroy(out);
    return result;
}
