/* Device limits a scene must fit (sim_limits.c). */
#ifndef CVK_SIM_LIMITS_H
#define CVK_SIM_LIMITS_H

#include "build.h"
#include "context.h"

/* From the scene alone, before building: the workgroup size, grid cloths' particle counts. */
cvk_result cvk_check_scene_limits(const cvk_context* context, const cvk_scene_desc* scene,
                                  uint32_t workgroup_size, cvk_error* error);

/* From the build, before device allocation: every cloth's particles and springs. */
cvk_result cvk_check_build_limits(const cvk_context* context, const cvk_scene_desc* scene,
                                  const cvk_build* build, cvk_error* error);

#endif
