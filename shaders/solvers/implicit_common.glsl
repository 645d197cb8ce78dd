// Data of the implicit Euler passes (lib/solvers/solve_implicit.c): backward Euler linearised once per
// substep (Baraff & Witkin 1998), (M - h dF/dv - h^2 dF/dx) dv = h (f + h dF/dx v), solved for
// the free particles by filtered preconditioned CG or by block Jacobi.
//
// Pinned particles are the filter: they sit after the free ones and are no unknowns, so their
// dv is 0 in every iterate (S = 0 there, S = I elsewhere). Every 3x3 block is symmetric and kept as two vec4: (xx, yy, zz, xy), (xz, yz).
//
// Contact (a scene with colliders: COLLIDER_TYPES != 0, specialisation id 2) adds the filter
// S = I - n n^T of a free particle held on a collider along its outward normal n
// (implicit_contact.comp writes n per substep, 0 for the others; Baraff & Witkin section 5,
// seed 000 listing 4.1): r, z, q and every Jacobi iterate are filtered, so dv never has a
// component along n and the velocity the contact pass prescribed along n is kept. The
// preconditioner of a held particle is the block of S A_pp S + m n n^T, which maps the tangent
// plane onto itself (an exact 2x2 solve there). Without colliders FILTER is false and every
// filter below compiles to nothing.
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
layout(set = 0, binding = CVK_IMPLICIT_BINDING_P_READ) uniform samplerBuffer pdir_read;
layout(set = 0, binding = CVK_IMPLICIT_BINDING_OFFDIAG_READ) uniform samplerBuffer offdiag_read;

CVK_DECLARE_PUSH(CVK_IMPLICIT_PUSH_FIELDS)

#ifdef IMPLICIT_CONTACT
#define CONTACT_TYPES_ID 2
#include "contact/collide.glsl" // the contact set (set 1) and the colliders' distances and normals
#else
layout(constant_id = 2) const uint COLLIDER_TYPES = 0u;
#endif
const bool FILTER = (COLLIDER_TYPES & CVK_COLLIDER_TYPE_MASK) != 0u;
layout(std430, set = 0, binding = CVK_IMPLICIT_BINDING_FILTER) buffer ContactFilter { vec4 contact_filter[]; };

// S w for free particle p: w less its part along p's contact normal (0 when p is not held).
vec3 filtered(uint p, vec3 w)
{
    if (!FILTER)
        return w;
    vec3 n = contact_filter[p].xyz;
    return w - dot(w, n) * n;
}

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

// The block-Jacobi preconditioner: A_pp = L D L^T (L unit lower triangular), kept as
// f = (l10, l20, l21) and g = 1/d. Its pivots are clamped at m, which bounds the exact ones
// from below (A_pp >= m I): at large steps h^2 k / m reaches 1e8 and the float pivot of a
// direction only m resists is rounding noise that can come out negative. So P^-1 stays
// positive definite and r.P^-1 r = |D^-1/2 L^-1 r|^2 is a sum of squares.
vec3 lower_solve(vec3 f, vec3 r)
{
    float y1 = r.y - f.x * r.x;
    return vec3(r.x, y1, r.z - f.y * r.x - f.z * y1);
}

vec3 upper_solve(vec3 f, vec3 w)
{
    float z1 = w.y - f.z * w.z;
    return vec3(w.x - f.x * z1 - f.y * w.z, z1, w.z);
}

// z = P^-1 r for particle p; rz receives r.z.
vec3 precondition(uint p, vec3 r, out float rz)
{
    vec3 f = diag[4u * p + 2u].xyz, g = diag[4u * p + 3u].xyz;
    vec3 y = lower_solve(f, r);
    rz = dot(y * y, g);
    return upper_solve(f, y * g);
}

// Slot e of particle p: its neighbour, and whether that neighbour is an unknown (a pinned
// neighbour's dv is 0 in every iterate: the filter). Padding slots point at p with H = 0.
uint slot_neighbour(uint e, uint p)
{
    uint c = adjacency[e].x;
    return c < pc.stride ? c : p;
}

float slot_free(uint e)
{
    return adjacency[e].x < pc.stride ? 1.0 : 0.0;
}
