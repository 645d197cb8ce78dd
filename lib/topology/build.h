/* Scene description -> particles, springs, triangles, colouring and adjacency, on the host,
   once. Every cloth comes through one path: its topology (lib/topology/topology.h: a grid generator or
   a mesh file) gives positions, masses, pins, triangles and typed springs.

   User order: cloth by cloth, each in its topology's order (grids row by row, meshes in file
   order). Internal particle order: the free particles of colour 0, then colour 1, ..., then
   every pinned particle. Inside a colour, particles keep user order. The solver dispatches one
   contiguous range per colour, and a neighbour's index tells its colour range without a
   lookup. */
#ifndef CVK_BUILD_H
#define CVK_BUILD_H

#include "topology/topology.h"

typedef struct cvk_spring {
    uint32_t a, b;  /* internal particle indices */
    float rest;     /* rest length, m */
    float k;        /* stiffness, N/m */
    uint32_t type;  /* cvk_spring_type */
} cvk_spring;

typedef struct cvk_cloth_range {
    char name[64];             /* the scene's name, or "cloth<N>" */
    uint32_t first_user;       /* its first particle in user order */
    uint32_t particle_count;
    uint32_t first_triangle;   /* its triangles in build.triangles */
    uint32_t triangle_count;
    bool mesh;                 /* read from a file; false: a grid */
    uint32_t grid[2];          /* a grid's particles along u and v; 0 for a mesh */
    float rest_scale;          /* for the renderer: how far the cloth can reach */
    float color[3];            /* linear RGB, for the renderer */
    char* texture;             /* the scene's texture path (a copy), or NULL */
    float back_color[3];       /* for the renderer: cvk_cloth_desc's back_color, sheen, */
    float sheen, roughness;    /* roughness, thickness and material_texture */
    float thickness;
    char* normal_map;          /* the scene's normal_map path (a copy), or NULL */
    float normal_strength;
    bool material_texture;
} cvk_cloth_range;

typedef struct cvk_build {
    uint32_t particle_count;
    uint32_t free_count;                          /* particles [0, free_count) move */
    uint32_t colour_count;
    uint32_t colour_start[CVK_MAX_COLOURS + 1];   /* colour c: [start[c], start[c+1]) */

    float* position;          /* xyz per particle, internal order, initial state */
    float* mass;              /* kg per particle, internal order */
    uint32_t* user_of;        /* internal index -> user index */
    uint32_t* internal_of;    /* user index -> internal index */

    cvk_spring* springs;
    uint32_t spring_count;
    uint64_t springs_by_type[3];

    /* Adjacency of the free particles, slot-major: entry s of particle p at s·free_count + p,
       a spring for s < degree[p], padding (p itself, k = 0) up to max_degree. */
    uint32_t max_degree;
    uint32_t* degree;
    uint32_t* adj_index;
    float* adj_k;
    float* adj_rest;
    uint32_t* adj_spring;     /* the spring (index into springs) of each entry; UINT32_MAX for
                                 padding. Tearing zeroes the k of a broken spring's entries. */

    /* Triangles of every cloth, cloth by cloth: 3 user indices each, counter-clockwise seen
       from the front, and the spring index (into springs) along edges (v0,v1), (v1,v2),
       (v2,v0), or UINT32_MAX where the edge has no spring. Wind, collisions and the mesh
       generation read them. */
    uint32_t triangle_count;
    uint32_t* triangles;
    uint32_t* triangle_springs;

    uint32_t cloth_count;
    cvk_cloth_range* cloths;

    /* Tethers (cvk_build_tethers below): CVK_TETHER_SLOTS pins (internal indices, nearest first) per free
       particle and the length each tether allows, m; NULL when no cloth has tethers. */
    uint32_t* tether_anchor;
    float* tether_length;
    uint32_t tether_slots;    /* the most tethers one particle has (its slots in use, nearest
                                 first; the rest are empty): 0 without tethers */
    /* Attached (kinematic) particles, all of them pinned: attached[i] is an internal index,
       attached_to[i] its attachment (scene order); cloth by cloth in user order. */
    uint32_t attached_count;
    uint32_t* attached;
    uint32_t* attached_to;
    /* Texture coordinates, 2 per particle in user order (0 on cloths without a texture);
       NULL when no cloth has a texture. */
    float* uv;
} cvk_build;

/* Called once the particle count and the largest number of springs on one particle are known,
   before the adjacency tables (max_degree × free particles entries) are allocated: a scene
   too large for the device fails here instead of after gigabytes of host memory. A result
   other than CVK_SUCCESS stops the build with it. */
typedef cvk_result (*cvk_build_check)(void* user, uint32_t particle_count, uint32_t max_degree,
                                      cvk_error* error);

/* cvk_build_create with a check (may be NULL). */
cvk_result cvk_build_create_checked(const cvk_scene_desc* scene, cvk_build_check check,
                                    void* check_user, cvk_build* out, cvk_error* error);

/* The scene must have passed cvk_scene_desc_validate. Mesh files are read here: their errors
   name the key path (see cvk_topology_create). */
cvk_result cvk_build_create(const cvk_scene_desc* scene, cvk_build* out, cvk_error* error);
void cvk_build_destroy(cvk_build* build);

/* Returns the index of a spring whose two ends are free and share a colour, or -1 when the
   colouring is valid. */
int64_t cvk_build_find_colour_conflict(const cvk_build* build);

/* Colour of an internal free particle index. */
uint32_t cvk_build_colour_of(const cvk_build* build, uint32_t particle);

/* The cloth (scene order) of a particle by its user index, and by its internal index. */
uint32_t cvk_build_cloth_of_user(const cvk_build* build, uint32_t user);
uint32_t cvk_build_cloth_of(const cvk_build* build, uint32_t particle);

/* Tethers (long-range attachments; Kim, Chentanez & Müller 2012, "Long range attachments"; the
   tether constraints of NvCloth): each free particle of a cloth with `tethers` > 0 may not get
   farther from any of its CVK_TETHER_SLOTS nearest pins than tethers × its rest distance to
   that pin across the cloth. One-sided and per particle, so one pass after each outer
   iteration holds them exactly, whatever the size of the cloth; the local sweeps alone let a
   long hanging cloth stretch in proportion to its length.

   Rest distance: a grid's rest shape is a flat rectangle, convex, so its geodesic distances
   are straight lines: rest_scale × the distance between the two particles' initial positions.
   A mesh cloth's is the shortest path along its springs' rest lengths, which is at least the
   geodesic (a path across triangles is no shorter than the surface's): the tether never pulls
   a particle closer than the true rest distance allows. Nearest pins are nearest along the
   springs, in both cases. */
#define CVK_TETHER_SLOTS 4u
#define CVK_TETHER_NONE UINT32_MAX
/* CVK_TETHER_ROUNDS (shaders/shared/layout.h): how many times the pass projects a particle
   onto each of its tethers' spheres in turn. */
#include "shared/layout.h"

/* The tethers of every free particle, for the cloths of `scene` that have them, in
   build->tether_anchor (CVK_TETHER_SLOTS internal indices per free particle, nearest first,
   CVK_TETHER_NONE where fewer pins are reachable) and build->tether_length (m, the scaled rest
   distance). Both stay NULL when no cloth has tethers and pins. */
cvk_result cvk_build_tethers(const cvk_scene_desc* scene, cvk_build* build, cvk_error* error);

#endif
