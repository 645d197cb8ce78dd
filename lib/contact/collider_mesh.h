/* Triangles of a collider's surface at rest (scene coordinates before its motion), for the
   renderer: spheres and capsules tessellated as finely as the pixels their radius spans need
   to look round, boxes with flat faces, the funnel's surface of revolution, a plane as a square of side
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

/* sdf: the collider's field for CVK_COLLIDER_MESH (its triangles are used), NULL otherwise.
   radius_pixels: for a sphere or a capsule, the most pixels its radius spans in the picture,
   which sets its segments (cvk_collider_round_segments); 0: unknown, the finest. */
cvk_result cvk_collider_mesh_make(const cvk_collider_desc* collider, const cvk_sdf* sdf,
                                  const float focus[3], float plane_extent, double radius_pixels,
                                  cvk_collider_mesh* out, cvk_error* error);
/* Segments around a round shape whose radius spans radius_pixels (rings from pole to pole: half
   as many): the fewest, a multiple of 4 from 12 to 64, that keep its outline within 0.45 pixels
   of round; 64 where radius_pixels is 0, not finite or more than a 720-pixel image needs. */
uint32_t cvk_collider_round_segments(double radius_pixels);
void cvk_collider_mesh_destroy(cvk_collider_mesh* mesh);

#endif
