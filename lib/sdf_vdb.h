/* The one C++ part of the library: OpenVDB's mesh-to-level-set behind a C function, so that
   lib/sdf.c stays C. Nothing is thrown across it. */
#ifndef CVK_SDF_VDB_H
#define CVK_SDF_VDB_H

#include "clothvk.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fills values[i + dims[0] (j + dims[1] k)] with the signed distance (m, negative inside) from
   origin + voxel (i, j, k) to the closed mesh (xyz: 3 floats per vertex, triangles: 3 indices
   each, counter-clockwise from outside), exact near the surface and signed everywhere in the
   grid. On failure returns CVK_ERROR_OUT_OF_MEMORY or CVK_ERROR_UNSUPPORTED and writes why (one
   sentence fragment, no key) into `why`. */
cvk_result cvk_sdf_vdb_fill(const float* xyz, uint32_t vertex_count, const uint32_t* triangles,
                            uint32_t triangle_count, const uint32_t dims[3], const float origin[3],
                            float voxel, float* values, char* why, size_t why_size);

#ifdef __cplusplus
}
#endif

#endif
