/* Mesh colliders: a closed triangle mesh read through the cloth mesh reader (Assimp) and turned
   into a signed distance field on a regular grid at load time (negative inside), sampled
   trilinearly on the host here and on the device in shaders/contact/collide.glsl (same layout). */
#ifndef CVK_SDF_H
#define CVK_SDF_H

#include "clothvk.h"

typedef struct cvk_sdf {
    uint32_t dims[3];        /* samples along x, y, z, each ≥ 2 */
    float origin[3];         /* position of sample [0, 0, 0], m (collider coordinates at rest) */
    float voxel;             /* m between neighbouring samples */
    float* values;           /* dims[0]·dims[1]·dims[2] signed distances, m, x fastest */
    /* The mesh itself (after the transform), for drawing and for tests. */
    float* xyz;              /* 3 floats per vertex */
    uint32_t vertex_count;
    uint32_t* triangles;     /* 3 vertex indices per triangle, counter-clockwise from outside */
    uint32_t triangle_count;
} cvk_sdf;

/* Reads `path` (relative to the working directory) with `transform` applied and builds the
   field: voxel = max(diagonal of the mesh's box / resolution, min_voxel), a margin of a few
   voxels around the box. The mesh must be closed (every edge shared by exactly two triangles
   after welding): otherwise CVK_ERROR_INVALID_ARGUMENT naming `key` ("colliders.2.file"), the
   file and one open edge. A file that cannot be read: CVK_ERROR_IO with the same key. On
   failure nothing is left to free. */
cvk_result cvk_sdf_from_mesh_file(const char* path, const cvk_transform* transform,
                                  uint32_t resolution, float min_voxel, const char* key,
                                  cvk_sdf* out, cvk_error* error);
void cvk_sdf_destroy(cvk_sdf* sdf);

/* Trilinear sample at p (collider coordinates at rest); outside the grid, the value at the
   nearest grid point plus the distance to it (a bound that keeps sphere tracing safe). */
float cvk_sdf_sample(const cvk_sdf* sdf, const float p[3]);

#endif
