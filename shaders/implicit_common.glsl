// Data of the implicit Euler passes (lib/solve_implicit.c): backward Euler linearised once per
// substep (Baraff & Witkin 1998), (M - h dF/dv - h^2 dF/dx) dv = h (f + h dF/dx v), solved for
// the free particles by filtered preconditioned CG or by block Jacobi.
//
// Pinned particles are the filter: they sit after the free ones, are no unknowns, and a slot
// pointing at one carries no block, so their dv is 0 in every iterate (S = 0 there, S = I
// elsewhere). Every 3x3 block is symmetric and kept as two vec4: (xx, yy, zz, xy), (xz, yz).
//
// Every pass after the assembly reads scalars.converged first and does nothing once it is
// set: the plan records max_iterations iterations and the device decides how many run.

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint MAX_DEGREE = 4;

#include "shared/layout.h"

layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_X) buffer Positions { vec4 x[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_V) buffer Velocities { vec4 v[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_ADJACENCY) readonly buffer Adjacency { uvec4 adjacency[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_DIAG) buffer Diag { vec4 diag[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_OFFDIAG) buffer Offdiag { vec4 offdiag[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_B) buffer Rhs { vec4 b[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_DV0) buffer Dv0 { vec4 dv0[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_DV1) buffer Dv1 { vec4 dv1[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_R) buffer Residual { vec4 r[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_Z) buffer Preconditioned { vec4 z[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_P) buffer Direction { vec4 pdir[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_Q) buffer Product { vec4 q[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_PARTIALS) buffer Partials { float partials[]; };
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_SCALARS) buffer Scalars { cvk_implicit_scalars scalars; };

CVK_DECLARE_PUSH(CVK_IMPLICIT_PUSH_FIELDS)

uint invocation_stride()
{
    return gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}

// Symmetric block m = (s0, s1) times w.
vec3 sym_mul(vec4 s0, vec4 s1, vec3 w)
{
    return vec3(s0.x * w.x + s0.w * w.y + s1.x * w.z,
                s0.w * w.x + s0.y * w.y + s1.y * w.z,
                s1.x * w.x + s1.y * w.y + s0.z * w.z);
}

// dv of neighbour slot e of particle p in `which` (0: dv0, 1: dv1, 2: pdir); a pinned or
// padding neighbour reads p's own value, which its zero block cancels.
uint slot_neighbour(uint e, uint p)
{
    uint c = adjacency[e].x;
    return c < pc.stride ? c : p;
}
