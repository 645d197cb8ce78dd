// Data of the explicit integrators (lib/solvers/solve_explicit.c): a mass-spring cloth advanced by
// forward Euler, TVD-RK2, 4th-order Adams-Bashforth or position Verlet (seed 001 §2.3.4).
// Every step is one or two force passes (explicit_force.comp) and one or two updates
// (explicit_update.comp). Pinned particles sit after the free ones and are never dispatched.

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint MAX_DEGREE = 4;

#include "shared/layout.h"

layout(std430, set = 0, binding = CVK_EXPLICIT_BINDING_X) buffer Positions { vec4 x[]; };
layout(std430, set = 0, binding = CVK_EXPLICIT_BINDING_V) buffer Velocities { vec4 v[]; };
layout(std430, set = 0, binding = CVK_EXPLICIT_BINDING_XS) buffer StagePositions { vec4 xs[]; };
layout(std430, set = 0, binding = CVK_EXPLICIT_BINDING_VS) buffer StageVelocities { vec4 vs[]; };
layout(std430, set = 0, binding = CVK_EXPLICIT_BINDING_ADJACENCY) readonly buffer Adjacency { uvec4 adjacency[]; };
layout(std430, set = 0, binding = CVK_EXPLICIT_BINDING_A) buffer Accelerations { vec4 acc[]; };
layout(std430, set = 0, binding = CVK_EXPLICIT_BINDING_HISTORY) buffer History { vec4 hist[]; };
layout(std430, set = 0, binding = CVK_EXPLICIT_BINDING_WATCH) buffer Watch { cvk_gpu_watch watch; };
layout(std430, set = 0, binding = CVK_EXPLICIT_BINDING_X_IN) readonly buffer PositionsIn { vec4 x_in[]; };
layout(std430, set = 0, binding = CVK_EXPLICIT_BINDING_V_IN) readonly buffer VelocitiesIn { vec4 v_in[]; };

CVK_DECLARE_PUSH(CVK_EXPLICIT_PUSH_FIELDS)

uint invocation_stride()
{
    return gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}
