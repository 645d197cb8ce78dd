/* The shape of one cloth, whatever it came from: positions, triangles and typed springs.
   The grid generator and the mesh-file reader both produce it; lib/topology/build.c turns the
   topologies of a scene into particles, colours and adjacency, one path for every cloth.

   Indices here are local to the cloth (0 .. vertex_count − 1) and in user order: a grid row
   by row (i fastest), a mesh in file order (welded vertices once, in order of first
   appearance). */
#ifndef CVK_TOPOLOGY_H
#define CVK_TOPOLOGY_H

#include "scene/scene.h"

#define CVK_NO_SPRING UINT32_MAX
/* Colours at most in a colouring of the particles (topology/colour.h). */
#define CVK_MAX_COLOURS 32

typedef enum cvk_spring_type {
    CVK_SPRING_STRUCTURAL = 0,
    CVK_SPRING_SHEAR = 1,
    CVK_SPRING_BEND = 2,
} cvk_spring_type;

/* Colour of particle [i, j] of a grid cloth whose spring kinds are given, and the number of
   colours that pattern uses. Exposed for the colouring test. */
uint32_t cvk_grid_colour(uint32_t i, uint32_t j, bool shear, bool bend);
uint32_t cvk_grid_colour_count(bool shear, bool bend);

typedef struct cvk_topo_spring {
    uint32_t a, b;        /* local vertex indices, a != b */
    uint32_t type;        /* cvk_spring_type */
} cvk_topo_spring;

typedef struct cvk_topology {
    uint32_t vertex_count;
    float* position;             /* xyz per vertex, m, after any transform */
    float* mass;                 /* kg per vertex */
    uint8_t* pinned;             /* 1 per pinned vertex (pins, pin_vertices, pin_box) */
    float* uv;                   /* 2 per vertex, texture coordinates; only for a cloth with a
                                    texture, else NULL */

    uint32_t triangle_count;
    uint32_t* triangles;         /* 3 vertices per triangle, counter-clockwise from the front */
    uint32_t* triangle_springs;  /* 3 per triangle: the spring along edge (v0,v1), (v1,v2),
                                    (v2,v0), or CVK_NO_SPRING when that edge has none */

    uint32_t spring_count;       /* only springs of non-zero stiffness */
    cvk_topo_spring* springs;    /* rest length = |x_a − x_b| · rest_scale, computed by build */

    /* A closed-form colouring when the generator knows one (grids: cvk_grid_colour), else
       NULL and build colours the spring graph greedily. */
    uint32_t* colour;
    uint32_t colour_count;
} cvk_topology;

/* The topology of cloth `index` of a validated scene: a grid from its keys, or a mesh read
   from its file. Errors name the key path ("cloths.2.mesh: poncho.obj: ...") and return
   CVK_ERROR_IO (file missing or unreadable) or CVK_ERROR_INVALID_ARGUMENT (no triangles,
   degenerate or non-manifold faces, NaN coordinates, a pin out of range). */
cvk_result cvk_topology_create(const cvk_cloth_desc* cloth, uint32_t index, cvk_topology* out,
                               cvk_error* error);
void cvk_topology_destroy(cvk_topology* topology);

/* Sets mark[v] = 1 for every vertex that `pins` names (its pins, pin_vertices and pin_box, as
   a cloth's pins); messages start with base ("cloths.0", "attachments.2"). */
cvk_result cvk_topology_select(const cvk_cloth_desc* pins, const char* base,
                               const cvk_topology* topology, uint8_t* mark, cvk_error* error);

/* The two generators behind cvk_topology_create. Each fills position, triangles,
   triangle_springs, springs (of non-zero stiffness only) and, for grids, colour; mass and
   pinned are filled afterwards by cvk_topology_create for both. lib/topology/topology.c holds the grid,
   lib/topology/topology_mesh.c the mesh reader (Assimp). */
cvk_result cvk_topology_grid(const cvk_cloth_desc* cloth, uint32_t index, cvk_topology* out,
                             cvk_error* error);
cvk_result cvk_topology_mesh(const cvk_cloth_desc* cloth, uint32_t index, cvk_topology* out,
                             cvk_error* error);

/* A mesh file's triangles alone, for colliders: the same reader, welding, checks and messages
   as cvk_topology_mesh (prefixed with `key`, e.g. "colliders.2.file"), the vertices in the same
   order, with `transform` applied; no springs. On failure `out` is zeroed. */
typedef struct cvk_mesh_triangles {
    float* xyz;                  /* 3 floats per vertex, m, after the transform */
    uint32_t vertex_count;
    uint32_t* triangles;         /* 3 vertex indices per triangle, the file's winding */
    uint32_t triangle_count;
} cvk_mesh_triangles;

cvk_result cvk_topology_mesh_triangles(const char* path, const cvk_transform* transform,
                                       const char* key, cvk_mesh_triangles* out, cvk_error* error);
void cvk_mesh_triangles_free(cvk_mesh_triangles* mesh);

/* Lumped masses from the triangles: each vertex gets a third of the area of its triangles
   times density, or, with density 0, that area's share of total_mass. Every vertex must lie
   in a triangle of non-zero area (the mesh reader drops vertices no face uses; scene
   validation keeps density off ropes). */
cvk_result cvk_topology_area_mass(cvk_topology* topology, double density, double total_mass,
                                  cvk_error* error);

#endif
