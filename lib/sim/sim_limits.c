/* Device limits a scene must fit: checked from the scene before anything is built (grid
   sizes are known from their keys, so a 20000 x 20000 grid fails at once), and from the
   build before anything large is allocated on the device (mesh cloths, exact degrees). */
#include "sim/sim_limits.h"

#include "core/error.h"
#include "sim/memory.h"
#include "shared/layout.h"

/* The adjacency takes two texels per quad of spring slots (see solve_pd.c). */
static uint64_t adjacency_texels(uint64_t particles, uint32_t max_degree)
{
    uint32_t quads = max_degree ? (max_degree + 3u) / 4u : 1u;
    return particles * 2u * quads;
}

static cvk_result check_counts(const cvk_context* context, const cvk_scene_desc* scene,
                               const char* where, uint64_t total, uint32_t degree,
                               cvk_error* error)
{
    const VkPhysicalDeviceLimits* limits = &context->properties.limits;
    uint64_t max_particles = cvk_context_max_particles(context);
    if (total > max_particles)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "%s: %llu particles are too many for %s, which holds at most %llu "
                        "(maxStorageBufferRange %u bytes, 16 bytes per particle)",
                        where, (unsigned long long)total, context->properties.deviceName,
                        (unsigned long long)max_particles, limits->maxStorageBufferRange);
    uint64_t texels = adjacency_texels(total, degree);
    if (total > limits->maxTexelBufferElements || texels > limits->maxTexelBufferElements)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "%s: %llu particles with up to %u springs each need %llu adjacency "
                        "texels; %s allows %u texel buffer elements (maxTexelBufferElements)",
                        where, (unsigned long long)total, degree, (unsigned long long)texels,
                        context->properties.deviceName, limits->maxTexelBufferElements);
    return cvk_memory_check(context, scene, where, total, degree, error);
}

/* Springs per grid particle, at most, from the stiffnesses present. */
static uint32_t grid_degree_bound(const cvk_cloth_desc* cloth)
{
    const cvk_stiffness* k = &cloth->stiffness;
    return (k->structural > 0 ? 4u : 0u) + (k->shear > 0 ? 4u : 0u) + (k->bend > 0 ? 4u : 0u);
}

cvk_result cvk_check_scene_limits(const cvk_context* context, const cvk_scene_desc* scene,
                                  uint32_t workgroup_size, cvk_error* error)
{
    const VkPhysicalDeviceLimits* limits = &context->properties.limits;
    if (workgroup_size > limits->maxComputeWorkGroupSize[0] ||
        workgroup_size > limits->maxComputeWorkGroupInvocations)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "workgroup size %u exceeds the device's limit of %u", workgroup_size,
                        limits->maxComputeWorkGroupSize[0]);
    uint64_t total = 0;
    uint32_t degree = 0;
    for (uint32_t c = 0; c < scene->cloth_count; c++) {
        const cvk_cloth_desc* cloth = &scene->cloths[c];
        if (cloth->mesh)
            continue; /* known after reading the file: checked from the build */
        total += (uint64_t)cloth->grid[0] * cloth->grid[1];
        uint32_t d = grid_degree_bound(cloth);
        degree = d > degree ? d : degree;
    }
    /* One record per collider in a storage buffer (shared/layout.h), read per particle. */
    uint64_t collider_bytes = (uint64_t)scene->collider_count * sizeof(cvk_gpu_collider);
    if (collider_bytes > limits->maxStorageBufferRange)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "%s: %u colliders need %llu bytes of collider records, more than %s's "
                        "storage buffers hold (maxStorageBufferRange %u bytes)",
                        scene->instances.count > 1 ? "instances.count" : "colliders",
                        scene->collider_count, (unsigned long long)collider_bytes,
                        context->properties.deviceName, limits->maxStorageBufferRange);
    const char* where = scene->cloth_count == 1 ? "cloths.0.grid" : "cloths";
    if (scene->instances.count > 1)
        where = "instances.count";
    return check_counts(context, scene, where, total, degree, error);
}

cvk_result cvk_check_build_limits(void* limits, uint32_t particle_count, uint32_t max_degree,
                                  cvk_error* error)
{
    const cvk_build_limits* l = limits;
    const char* where = "cloths";
    if (l->scene->cloth_count == 1)
        where = l->scene->cloths[0].mesh ? "cloths.0.mesh" : "cloths.0.grid";
    if (l->scene->instances.count > 1)
        where = "instances.count";
    return check_counts(l->context, l->scene, where, particle_count, max_degree, error);
}

static double spring_sum(const cvk_build* b, uint32_t p)
{
    double sum = 0.0;
    for (uint32_t slot = 0; slot < b->degree[p]; slot++)
        sum += b->adj_k[(size_t)slot * b->free_count + p];
    return sum;
}

cvk_result cvk_check_derived(const cvk_scene_desc* scene, const cvk_build* b, double h,
                             cvk_error* error)
{
    double inv_h2 = 1.0 / (h * h);
    for (uint32_t p = 0; p < b->free_count; p++) {
        uint32_t c = cvk_build_cloth_of(b, p);
        const char* mass_key = scene->cloths[c].density > 0.0f ? "density" : "mass";
        double inertia = b->mass[p] * inv_h2, springs = spring_sum(b, p);
        if (inertia > CVK_MAX_DIAGONAL || inertia < CVK_MIN_INERTIA)
            return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                            "cloths.%u.%s: a particle of %g kg with a step of %g s has "
                            "m/h² = %g kg/s², outside [%g, %g] where single-precision solves "
                            "hold it", c, mass_key, (double)b->mass[p], h, inertia,
                            CVK_MIN_INERTIA, CVK_MAX_DIAGONAL);
        if (inertia + springs > CVK_MAX_DIAGONAL)
            return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                            "cloths.%u.stiffness: a particle's springs sum to %g N/m; with "
                            "m/h² = %g kg/s² its row's diagonal exceeds %g, beyond what "
                            "single-precision solves hold", c, springs, inertia, CVK_MAX_DIAGONAL);
    }
    return CVK_SUCCESS;
}
