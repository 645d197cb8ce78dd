/* Mesh to signed distance with OpenVDB (tools::meshToSignedDistanceField): exact distances to
   the nearest triangle in a band around the surface, the sign from a flood fill of the outside,
   and both bands as wide as the whole grid so every sample is a distance, not a clamp.

   OpenVDB needs no openvdb::initialize() for this (that registers grid and metadata types for
   file I/O, which is global state we do not want); grids, transforms and the mesh tools work
   without it. Its threads (TBB) are confined to an arena of one thread: the build then does
   the same arithmetic in the same order every time, so a scene gives bit-identical fields
   from run to run, which the simulation's determinism needs. */
#include "sdf_vdb.h"

#include <cstdio>
#include <exception>
#include <new>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/task_arena.h>

namespace {

void build(const float* xyz, uint32_t vertex_count, const uint32_t* triangles,
           uint32_t triangle_count, const uint32_t dims[3], const float origin[3], float voxel,
           float* values)
{
    std::vector<openvdb::Vec3s> points(vertex_count);
    for (uint32_t v = 0; v < vertex_count; v++)
        points[v] = openvdb::Vec3s(xyz[3 * size_t(v)], xyz[3 * size_t(v) + 1], xyz[3 * size_t(v) + 2]);
    /* OpenVDB's inside is to the left of clockwise triangles seen from outside; the sign comes
       from its flood fill either way, the order is kept as the file's. */
    std::vector<openvdb::Vec3I> faces(triangle_count);
    for (uint32_t t = 0; t < triangle_count; t++)
        faces[t] = openvdb::Vec3I(triangles[3 * size_t(t)], triangles[3 * size_t(t) + 1],
                                  triangles[3 * size_t(t) + 2]);
    std::vector<openvdb::Vec4I> quads;

    openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(voxel);
    transform->postTranslate(openvdb::Vec3d(origin[0], origin[1], origin[2]));
    /* Bands in voxels: the grid's longest side reaches every sample from the surface. */
    uint32_t longest = dims[0] > dims[1] ? dims[0] : dims[1];
    longest = longest > dims[2] ? longest : dims[2];
    const float band = float(longest) + 1.0f;
    openvdb::FloatGrid::Ptr grid = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
        *transform, points, faces, quads, band, band);

    openvdb::FloatGrid::ConstAccessor sample = grid->getConstAccessor();
    size_t at = 0;
    for (uint32_t k = 0; k < dims[2]; k++)
        for (uint32_t j = 0; j < dims[1]; j++)
            for (uint32_t i = 0; i < dims[0]; i++)
                values[at++] = sample.getValue(openvdb::Coord(int(i), int(j), int(k)));
}

} // namespace

extern "C" cvk_result cvk_sdf_vdb_fill(const float* xyz, uint32_t vertex_count,
                                       const uint32_t* triangles, uint32_t triangle_count,
                                       const uint32_t dims[3], const float origin[3], float voxel,
                                       float* values, char* why, size_t why_size)
{
    try {
        tbb::task_arena one(1);
        one.execute([&] {
            build(xyz, vertex_count, triangles, triangle_count, dims, origin, voxel, values);
        });
        return CVK_SUCCESS;
    } catch (const std::bad_alloc&) {
        std::snprintf(why, why_size, "out of host memory for the signed distance field");
        return CVK_ERROR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        std::snprintf(why, why_size, "OpenVDB could not build the signed distance field: %s",
                      e.what());
        return CVK_ERROR_UNSUPPORTED;
    } catch (...) {
        std::snprintf(why, why_size, "OpenVDB could not build the signed distance field");
        return CVK_ERROR_UNSUPPORTED;
    }
}
