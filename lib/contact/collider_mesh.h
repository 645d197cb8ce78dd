/* Triangles of a collider's surface at rest (scene coordinates before its motion), for the
   renderer: spheres and capsules tessellated finely enough to look round at 1280×720, boxes
   with flat faces, the funnel's surface of revolution, a plane as a square of side
   `plane_extent` centred on the point nearest `focus`, a mesh collider's own triangles.
   Normals point out of the solid (for the funnel: away from the axis; renderers light both
   sides). */
#ifndef CVK_COLLIDER_MESH_H
#define CVK_COLLIDER_MESH_H

#include "clothvk.h"
#include "contact/sdf.h"

typedef struct cvk_collider_mesh {
    float* xyz;              /* 3 floats per vertex, m */
    float* normals;          /* 3 floats per vertex, unit */
    uint32_t vertex_count;
    uint32_t* triangles;     /* 3 indices per triangle */
    uint32_t triangle_count;
} cvk_collider_mesh;

/* sdf: the collider's field for CVK_COLLIDER_MESH (its triangles are used), NULL otherwise. */
cvk_result cvk_collider_mesh_make(const cvk_collider_desc* collider, const cvk_sdf* sdf,
                                  const float focus[3], float plane_extent,
                                  cvk_collider_mesh* out, cvk_error* error);
void cvk_collider_mesh_destroy(cvk_collider_mesh* mesh);

#endif
