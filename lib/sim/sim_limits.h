/* Device limits a scene must fit (sim_limits.c). */
#ifndef CVK_SIM_LIMITS_H
#define CVK_SIM_LIMITS_H

#include "topology/build.h"
#include "core/context.h"

/* From the scene alone, before building: the workgroup size, grid cloths' particle counts. */
cvk_result cvk_check_scene_limits(const cvk_context* context, const cvk_scene_desc* scene,
                                  uint32_t workgroup_size, cvk_error* error);

/* From the build, before its adjacency tables and any device allocation: every cloth's
   particles and springs. A cvk_build_check for cvk_build_create_checked, whose user data is a
   cvk_build_limits. */
typedef struct cvk_build_limits {
    const cvk_context* context;
    const cvk_scene_desc* scene;
} cvk_build_limits;

cvk_result cvk_check_build_limits(void* limits, uint32_t particle_count, uint32_t max_degree,
                                  cvk_error* error);

/* The derived quantities of the solve, from the build: every free particle's m/h² and the
   diagonal m/h² + Σk of its row must be representable in single precision with room for the
   products the sweeps form with displacements (CVK_MAX_DIAGONAL), and m/h² must not vanish.
   CVK_ERROR_INVALID_ARGUMENT naming the cloth's key ("cloths.0.mass", "cloths.0.stiffness"). */
#define CVK_MAX_DIAGONAL 1e30 /* kg/s²: float's largest is 3.4e38 */
#define CVK_MIN_INERTIA 1e-30 /* kg/s²: m/h² below this is lost against any spring */

cvk_result cvk_check_derived(const cvk_scene_desc* scene, const cvk_build* build, double h,
                             cvk_error* error);

#endif
