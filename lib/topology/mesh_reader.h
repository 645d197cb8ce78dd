/* The mesh-file reader's state and the steps its three files share. topology_mesh.c drives
   the reader (its opening comment says what it decides and in which order) and makes the
   triangles, springs and topology; topology_mesh_file.c reads the file through Assimp and words
   its messages; topology_mesh_weld.c welds the file's vertices into particles. */
#ifndef CVK_MESH_READER_H
#define CVK_MESH_READER_H

#include "core/u64_map.h"
#include "topology/assimp_import.h"
#include "topology/topology.h"

#define CVK_UNUSED_VERTEX UINT32_MAX

typedef struct cvk_mesh_reader {
    const cvk_cloth_desc* cloth;
    const char* path;
    char key[CVK_KEY_PATH_MAX];   /* "cloths.N.mesh" */
    cvk_error* error;
    cvk_assimp* importer;         /* the file's importer, which owns scene */
    const struct aiScene* scene;

    size_t file_vertex_count;     /* over all meshes */
    size_t* vertex_base;          /* per mesh: its first vertex among all meshes' */
    uint32_t* particle_of;        /* per file vertex: its particle, or CVK_UNUSED_VERTEX */
    uint32_t vertex_count;
    float* position;              /* xyz per particle, file units, before the transform */
    double diagonal;              /* of the used vertices' bounding box, file units */

    size_t face_count;            /* faces of three or more corners */
    size_t corner_count;
    size_t* face_start;           /* face f's corners: corner[face_start[f] .. face_start[f + 1]) */
    uint32_t* corner;             /* particles */

    uint32_t triangle_count;
    uint32_t* triangles;          /* 3 particles per triangle, the file's winding */
    uint8_t* edge_kind;           /* 3 per triangle: EDGE_* (topology_mesh.c) of (v0,v1), ... */

    cvk_u64_map edge_map;             /* pair -> edge, for the faces' own edges */
    uint32_t edge_count;
    uint32_t* edge_ends;          /* 2 per edge, as first met */
    uint32_t* edge_faces;         /* per edge: how many faces have it */
    uint32_t* edge_opposite;      /* 2 per edge: the corner opposite it in the triangle on each side */

    cvk_u64_map spring_map;           /* pair -> spring */
} cvk_mesh_reader;

/* ---- the file (topology_mesh_file.c) ---- */

void cvk_mesh_reader_free(cvk_mesh_reader* r);
/* "KEY: PATH: out of host memory for <what>" as CVK_ERROR_OUT_OF_MEMORY. */
cvk_result cvk_mesh_out_of_memory(cvk_mesh_reader* r, const char* what);
/* "KEY: PATH: <problem>" as CVK_ERROR_INVALID_ARGUMENT. */
cvk_result cvk_mesh_bad(cvk_mesh_reader* r, const char* format, ...)
    __attribute__((format(printf, 2, 3)));
/* "KEY: cannot read PATH: <the first line of reason>" as CVK_ERROR_IO. */
cvk_result cvk_mesh_cannot_read(cvk_mesh_reader* r, const char* reason);
/* Imports r->path into r->scene (its importer r->importer) and counts its faces and corners. */
cvk_result cvk_mesh_open(cvk_mesh_reader* r);
/* The faces of three or more corners as particles (face_start, corner), after welding. */
cvk_result cvk_mesh_gather_faces(cvk_mesh_reader* r);
/* The topology's texture coordinates, for a cloth with a texture. */
cvk_result cvk_mesh_fill_uv(cvk_mesh_reader* r, cvk_topology* out);

/* ---- welding (topology_mesh_weld.c) ---- */

/* Welds the used vertices into particles (vertex_base, particle_of, vertex_count, position,
   diagonal); for an OBJ file, numbered in the order of its "v" lines. */
cvk_result cvk_mesh_weld(cvk_mesh_reader* r);

#endif
