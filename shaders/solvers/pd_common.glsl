// Particle state and projective-dynamics data shared by the solver passes.
//
// The solver works on displacements: u = x - x_n, where x_n are the positions at the start of
// the substep. Every quantity an iteration touches is then small (a fraction of a spring), so
// float rounding is relative to the motion, not to the distance from the origin; absolute
// positions are rounded once per substep, by the finalize pass, and the solved displacement is
// kept as the velocity (times h). A cloth far from the origin moves as smoothly as one near it.
//
// Arrays are vec4 in internal order: free particles colour by colour, pinned last (their u
// stays 0). Reads go through read-only storage texel buffers (imageLoad) and writes through
// storage buffers: on lavapipe a storage-buffer load is a per-lane loop (2x on a 100x100 sweep
// against a texel read), and a texelFetch of a uniform texel buffer is a call into a separate
// fetch function (Mesa 22.3: the plain sweep's code held 29 calls, around which the 256-bit
// registers live across them were spilled, 141 stores and 197 loads on the stack), while
// imageLoad is the same vectorised gather written inline: peer-hanging.json 19.1-19.4 ->
// 17.3-17.4 CPU ms a frame on one thread, the same bits. GPUs serve all of them well.
//
// Adjacency comes in quads of slots, padded to a multiple of four: for quad q of particle p,
// texel (2q) * pc.stride + p of `adjacency` holds four neighbours and texel (2q + 1) * pc.stride
// + p the bits of their k; texel q * pc.stride + p of `adjacency_rest` holds their rest lengths L. So
// neighbouring invocations read neighbouring texels, and four springs cost two gathers (a
// gather costs the same for one component as for four on lavapipe). Padding slots point at p
// itself with zero stiffness and contribute nothing.

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint MAX_DEGREE = 4;
const uint QUADS = (MAX_DEGREE + 3u) / 4u;

#include "shared/layout.h"

layout(set = 0, binding = CVK_PD_BINDING_SRC, rgba32f) uniform readonly imageBuffer src;
layout(set = 0, binding = CVK_PD_BINDING_DST_READ, rgba32f) uniform readonly imageBuffer dst_read;
#ifdef PD_FUSED
// The fused sweeps (pd_fused.comp) run every outer iteration of a substep in one dispatch and
// read back what other invocations of their workgroup wrote in it: through the storage buffers
// (coherent, after memoryBarrierBuffer and barrier), never a texel buffer, whose cache need not
// see those writes. The two iterates swap roles after each outer iteration, as the unfused
// dispatches' sets do: while `flipped` is false the iterate before is SRC_BUFFER (the texel
// view src's buffer) and the one written DST, while true the other way round.
layout(std430, set = 0, binding = CVK_PD_BINDING_DST) coherent buffer Dst { vec4 dst_u[]; };
layout(std430, set = 0, binding = CVK_PD_BINDING_SRC_BUFFER) coherent buffer Src { vec4 src_u[]; };
bool flipped = false;
#define LOAD_SRC(i) (flipped ? dst_u[i] : src_u[i])
#define LOAD_DST(i) (flipped ? src_u[i] : dst_u[i])
#define STORE_DST(i, value) \
    if (flipped) \
        src_u[i] = (value); \
    else \
        dst_u[i] = (value)
#else
layout(std430, set = 0, binding = CVK_PD_BINDING_DST) writeonly buffer Dst { vec4 dst[]; };
#define LOAD_SRC(i) imageLoad(src, int(i))
#define LOAD_DST(i) imageLoad(dst_read, int(i))
#define STORE_DST(i, value) dst[i] = (value)
#endif
#define FETCH_SRC(i) (LOAD_SRC(i).xyz)
#define FETCH_DST(i) (LOAD_DST(i).xyz)
// A neighbour's iterate as the sweep being run left it: pd_fused.comp reads it from the
// workgroup's shared memory where it keeps the sweeps' iterate there.
#ifndef SWEPT_DST
#define SWEPT_DST(i) FETCH_DST(i)
#endif
layout(set = 0, binding = CVK_PD_BINDING_Y_READ, rgba32f) uniform readonly imageBuffer y_read;
#ifdef PD_FUSED
// The fused dispatch predicts too (predict.glsl): y and the watch read back through the storage
// buffers, coherent.
layout(std430, set = 0, binding = CVK_PD_BINDING_Y) coherent buffer Inertial { vec4 y[]; };
#define LOAD_Y(i) (y[i])
#else
layout(std430, set = 0, binding = CVK_PD_BINDING_Y) writeonly buffer Inertial { vec4 y[]; };
#define LOAD_Y(i) imageLoad(y_read, int(i))
#endif
layout(set = 0, binding = CVK_PD_BINDING_X_READ, rgba32f) uniform readonly imageBuffer x_read;
layout(std430, set = 0, binding = CVK_PD_BINDING_X) writeonly buffer Positions { vec4 x[]; };
layout(set = 0, binding = CVK_PD_BINDING_RHS_READ, rgba32f) uniform readonly imageBuffer rhs_read;
#ifdef PD_FUSED
layout(std430, set = 0, binding = CVK_PD_BINDING_RHS) coherent buffer Rhs { vec4 rhs[]; };
#else
layout(std430, set = 0, binding = CVK_PD_BINDING_RHS) writeonly buffer Rhs { vec4 rhs[]; };
#endif
layout(set = 0, binding = CVK_PD_BINDING_ADJACENCY, rgba32ui) uniform readonly uimageBuffer adjacency;
layout(set = 0, binding = CVK_PD_BINDING_ADJACENCY_REST, rgba32f) uniform readonly imageBuffer adjacency_rest;
#ifdef PD_FUSED
layout(std430, set = 0, binding = CVK_PD_BINDING_WATCH) coherent buffer Watch { cvk_gpu_watch watch; };
#else
layout(std430, set = 0, binding = CVK_PD_BINDING_WATCH) buffer Watch { cvk_gpu_watch watch; };
#endif
layout(set = 0, binding = CVK_PD_BINDING_TETHER_ANCHOR, rgba32ui) uniform readonly uimageBuffer tether_anchor;
layout(set = 0, binding = CVK_PD_BINDING_TETHER_LENGTH, rgba32f) uniform readonly imageBuffer tether_length;
// The rest memory (lib/solvers/solve_pd.h): per free particle, the low-passed correction the solves
// made to their predictions; predict adds it to the first iterate, finalize updates it. REST
// (id 7; true where not specialised) is false where the scene keeps none (no damping, or
// contact): llvmpipe runs a branch's storage-buffer reads and writes whether or not any
// invocation takes it, and finalize's never-taken update cost a third of that pass
// (peer-hanging.json without tethers: finalize 3.2-3.4 -> 2.3-2.4 ms a frame without it, one
// lavapipe thread).
layout(constant_id = 7) const bool REST = true;
layout(std430, set = 0, binding = CVK_PD_BINDING_REST) buffer RestMemory { vec4 rest_memory[]; };
#define CONVERGE_SUMS CVK_PD_BINDING_CONVERGE
#include "solvers/pd_converge.glsl"

// Self-contact: every sweep keeps each particle within its bound (lib/contact/collide.h), so
// no iterate has cloth through cloth and contact's push always starts from the right side.
layout(constant_id = 5) const bool BOUNDED = false;
#include "contact/bounds.glsl"

// The push constants: cvk_pd_push (cvk_pd_fused_push, which begins with it, for the fused
// sweeps), declared with the C side in shared/layout.h.
#ifdef PD_FUSED
CVK_DECLARE_PUSH(CVK_PD_FUSED_PUSH_FIELDS)
#else
CVK_DECLARE_PUSH(CVK_PD_PUSH_FIELDS)
#endif

// The neighbours and stiffnesses of quad q of particle p.
uvec4 quad_neighbours(uint q, uint p)
{
    return imageLoad(adjacency, int(2u * q * pc.stride + p));
}

vec4 quad_k(uint q, uint p)
{
    return uintBitsToFloat(imageLoad(adjacency, int((2u * q + 1u) * pc.stride + p)));
}

// The inertial prediction of a free particle from its last substep's displacement, without
// the air or the rest memory: y = u (1 - damping) + h^2 g (predict.glsl; the first sweep that
// predicts, pd_gauss_seidel.comp's PREDICTS), `precise` so that both round it alike.
vec3 predicted(vec3 last)
{
    precise vec3 y = last * pc.keep + pc.gravity_h2.xyz;
    return y;
}

// A spring stretched past this times its rest length stops the simulation (the divergence
// watch of predict.glsl and of a first sweep that predicts; lib/plan/state.h,
// CVK_DIVERGED_STRETCH).
const float RUNAWAY_STRETCH = 10.0;

// The lowest particle of this invocation whose first spring the prediction found stretched past
// RUNAWAY_STRETCH times its rest length (predict.glsl, local_step where the first sweep
// predicts), written to the watch once after the invocation's particles (flush_stretched): the
// same watch, and no atomics in the loop, which llvmpipe runs whether or not any invocation
// takes their branch (finalize.glsl).
uint stretched_first = CVK_WATCH_NONE;

// Notes p for flush_stretched where the watch is on (pc.max_u2 > 0) and p's first spring — of
// stiffness k and rest length L, e = x_p - x_c at the start of the substep — is longer than
// RUNAWAY_STRETCH L. One spring a particle is enough (a solve that blows up stretches every
// spring around where it starts).
void watch_first_spring(uint p, float k, float rest, vec3 e)
{
    float limit = RUNAWAY_STRETCH * rest;
    if (pc.max_u2 > 0.0 && k > 0.0 && dot(e, e) > limit * limit)
        stretched_first = min(stretched_first, p);
}

void flush_stretched()
{
    if (stretched_first != CVK_WATCH_NONE) {
        watch.stretched = 1u;
        atomicMin(watch.particle, stretched_first);
    }
}

// Where the first sweep finds the last substep's displacements when it predicts itself
// (pd_gauss_seidel.comp's PREDICTS; 0 in every other pass): 1 in src, 2 in dst, which the
// colours swept before this one have overwritten (their predictions are in y).
#ifndef FIRST_PREDICTS
#define FIRST_PREDICTS 0u
#endif

// Invocations stride over the dispatch, so a few workgroups can cover many particles.
uint invocation_stride()
{
    return gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}

// The xyz of texel `index` of one of the bindings above (a macro: an image passed to a
// function would need its format written in the parameter, which GLSL does not allow).
#define fetch(data, index) (imageLoad(data, int(index)).xyz)

// The common shift of the bounds (bound_shift), read once before a loop over particles; 0
// without self-contact.
vec3 sweep_shift()
{
    return BOUNDED ? bound_shift() : vec3(0.0);
}

// p's displacement u kept within its bound, shift the common one (nothing without
// self-contact).
vec3 bounded(uint p, vec3 u, vec3 shift)
{
    if (!BOUNDED)
        return u;
    vec3 x0 = fetch(x_read, p);
    return within_bound(p, x0 + u, shift) - x0;
}

// One spring's part of the right-hand side in displacement form: k (L t/|t| - e), where
// e = x_p - x_c at the start of the substep, du = u_p - u_c at the start of the outer
// iteration and t = e + du (the local step: the spring's best direction, at rest length).
// Computed as k (du - s t) with s = (|t| - L) / |t| = (t.t - L^2) / ((|t| + L) |t|): the
// stretch comes from t.t - L^2, sums and products that every Vulkan device rounds
// correctly, and |t| enters only s's denominator. The direct form k L t/|t| - k e is the
// difference of two terms of size k L, so the few ulp that a device may err by in a square
// root or a division (Vulkan allows 2.5 ulp for a division; lavapipe rounds both correctly,
// NVIDIA's GPUs do not) became a few ulp of k L of force in every spring, which a cloth at
// rest cannot tell from stretch: the 17-particle chain of tests/solvers/test_rest.c rested 1.9e-6 m
// from its equilibrium (rbgs 4x4, lavapipe) and 2.7e-5 m (jacobi 1x1, H200); 1.8e-7 and
// 9e-6 m now. Coincident particles give no direction and only pull together
// (s t = 0: k (du - t) = -k e).
vec3 spring_rhs(vec3 du, vec3 t, float k, float rest)
{
    float tt = dot(t, t);
    float len = sqrt(tt);
    float s = len > 0.0 ? (tt - rest * rest) / ((len + rest) * len) : 0.0;
    return k * (du - s * t);
}

#ifdef RESIDUAL
// The rounding of d_p (local_step) relative to the sizes of the terms it is summed from: a
// spring's stretch comes from t.t - L^2, two terms of size L^2 that cancel, so each spring
// term carries about an ulp of k L whatever the device; the sums around it add a few more.
// The check counts only the part of |d_p|^2 above this floor: where d_p is no larger than its
// rounding, the iterate solves the system as well as float can tell. Without it the measure
// of a solve from rest (where the first residual is itself small) stalled above the
// tolerance on devices whose square roots and divisions are not correctly rounded: on an
// NVIDIA H200 a tolerance of 5 % stopped no solve of tests/solvers/test_pd_tolerance.c's cloth.
const float RESIDUAL_ROUNDING = 4.0 / 16777216.0; // 4 units of 2^-24 of the terms' sizes

float l1(vec3 v)
{
    return abs(v.x) + abs(v.y) + abs(v.z);
}

// The scene has tethers (the tether buffers hold one texel otherwise: nothing to read).
layout(constant_id = 3) const bool TETHERS = false;

// A tether that holds p takes the part of its correction d that points out of its sphere: the
// projected residual of the one-sided constraint, which is 0 at the constrained solution
// (without it a cloth hanging on its tethers never converges: the springs keep pulling the
// held particles outward). t is the tether's vector from the pin to p in the iterate; p is
// held when on its sphere to float rounding (the tether pass put it there) or past it. A
// missing tether points at p itself (t = 0, an unreachable limit).
vec3 tether_free(vec3 d, vec3 t, float limit)
{
    float far = length(t);
    if (far < limit * (1.0 - 1e-5))
        return d;
    vec3 n = t / far;
    float outward = dot(d, n);
    return outward > 0.0 ? d - outward * n : d;
}

// d with every tether of p that holds it applied (shaders/solvers/pd_tether.comp's data).
vec3 free_of_tethers(uint p, vec3 xp, vec3 cur, vec3 d)
{
    if (!TETHERS)
        return d;
    uvec4 anchor = imageLoad(tether_anchor, int(p));
    vec4 limit = imageLoad(tether_length, int(p));
    for (uint j = 0u; j < 4u; j++) {
        vec3 t = cur - FETCH_SRC(anchor[j]) + xp - fetch(x_read, anchor[j]);
        d = tether_free(d, t, limit[j]);
    }
    return d;
}
#endif

// The move one Jacobi step gives particle p from its displacement cur:
//   (w y + r - w cur + sum_c k_c (u_c - cur)) / (w + sum_c k_c),
// with b = (w y + r, w) from the local step (w = m/h^2, y the prediction, r the springs'
// part of the right-hand side), acc = sum_c k_c (u_c - cur) and ksum = sum_c k_c. It equals
// (w y + r + sum_c k_c u_c) / diag - cur, the update written from scratch, but the
// neighbours enter as differences of nearby displacements and w y - w cur as the difference
// of two products rounded alike (`precise`: no fused multiply-add), so a cloth that moves as
// a whole (y = cur = u_c, r = 0) moves by exactly 0. The sum is `precise` too: where the first
// sweep predicts (pd_gauss_seidel.comp's PREDICTS), y and cur are one value in one shader, and
// the compiler folded (w y + r) - w cur to r, which float rounding does not: a hanging cloth
// was an ulp off the prediction's own pass after 6 frames. From scratch the quotient rounded
// by an ulp of u every substep, the same way each time, and a freely falling cloth's velocity
// drifted by it: 5e-5 m in 0.8 s on lavapipe, 1.5e-4 m on an NVIDIA H200 (5.3e-6 m now on
// both). No texel more than before: diag is w + ksum, summed from the k the sweep reads.
vec3 jacobi_move(vec4 b, vec3 cur, vec3 acc, float ksum)
{
    precise vec3 held = b.w * cur;
    precise vec3 move = b.xyz - held + acc;
    return move / (b.w + ksum);
}

// The local step of particle p at the start of an outer iteration, from the iterate in src
// (cur is its own): writes and returns b = (w_p y_p + r_p, w_p), r_p the springs' part of the
// right-hand side, and sets acc = sum_c k_c (u_c - cur) and ksum = sum_c k_c for the first
// linear sweep (jacobi_move). Neighbours below `swept_below` were already updated in this
// sweep (Gauss-Seidel colours before this one) and are read from dst_read; the rest from src.
// RESIDUAL (the checking variants of the first sweeps) also writes |d_p|^2, the squared
// Jacobi move of the springs' system at src, less what the tethers holding p take
// (free_of_tethers).
vec4 local_step(uint p, vec3 cur, uint swept_below, out vec3 acc, out float ksum)
{
#ifdef RESIDUAL
    vec3 src_acc = vec3(0.0);
    float size = 0.0; // the sum of the sizes of the spring terms
#endif
    vec4 xp4 = imageLoad(x_read, int(p));
    vec3 xp = xp4.xyz;
    // A sweep that predicts starts from the prediction (cur) and writes it to y.
    vec4 yp = FIRST_PREDICTS != 0u ? vec4(cur, xp4.w) : LOAD_Y(p);
    if (FIRST_PREDICTS != 0u)
        y[p] = yp;
    vec3 r = vec3(0.0);
    ksum = 0.0;
    acc = vec3(0.0);
    for (uint q = 0; q < QUADS; q++) {
        uvec4 n = quad_neighbours(q, p);
        vec4 k = quad_k(q, p);
        vec4 rest = imageLoad(adjacency_rest, int(q * pc.stride + p));
        for (uint j = 0; j < 4u; j++) {
            // un: the neighbour's iterate at the start of the outer iteration; now: where it
            // is in this sweep (swept already when below swept_below). Where the sweep
            // predicts, a free neighbour not yet predicted starts from its prediction, one
            // predicted starts from its y, and a pinned one stays where it is.
            vec3 un, now;
            bool swept = n[j] < swept_below;
            if (FIRST_PREDICTS == 2u) {
                vec3 raw = FETCH_DST(n[j]);
                un = swept ? LOAD_Y(n[j]).xyz : n[j] < pc.stride ? predicted(raw) : raw;
                now = swept ? raw : un;
            } else {
                vec3 raw = FETCH_SRC(n[j]);
                un = FIRST_PREDICTS == 1u && n[j] < pc.stride ? predicted(raw) : raw;
                now = swept ? SWEPT_DST(n[j]) : un;
            }
            vec3 edge = xp - fetch(x_read, n[j]);
            // The divergence watch of a sweep that predicts, as predict.glsl's.
            if (FIRST_PREDICTS != 0u && q == 0u && j == 0u)
                watch_first_spring(p, k[0], rest[0], edge);
            vec3 du = cur - un;
            r += spring_rhs(du, edge + du, k[j], rest[j]);
            ksum += k[j];
            acc += k[j] * (now - cur);
#ifdef RESIDUAL
            src_acc -= k[j] * du;
            size += k[j] * (rest[j] + l1(edge) + l1(un));
#endif
        }
    }
    precise vec3 inertia = yp.w * yp.xyz;
    vec4 b = vec4(inertia + r, yp.w);
    rhs[p] = b;
#ifdef RESIDUAL
    vec3 d = free_of_tethers(p, xp, cur, jacobi_move(b, cur, src_acc, ksum));
    float floor = RESIDUAL_ROUNDING * ((size + yp.w * l1(yp.xyz)) / (yp.w + ksum) + l1(cur));
    residual[p] = max(dot(d, d) - floor * floor, 0.0);
#endif
    return b;
}

#ifdef PD_FUSED
// neighbour_sum(dst_read, ...) with the neighbours read through the storage buffer, or the
// workgroup's shared memory (SWEPT_DST).
vec3 neighbour_sum_dst(uint p, vec3 cur, out float ksum)
{
    vec3 acc = vec3(0.0);
    ksum = 0.0;
    for (uint q = 0; q < QUADS; q++) {
        uvec4 n = quad_neighbours(q, p);
        vec4 k = quad_k(q, p);
        for (uint j = 0; j < 4u; j++) {
            acc += k[j] * (SWEPT_DST(n[j]) - cur);
            ksum += k[j];
        }
    }
    return acc;
}
#endif

// sum_c k_c (u_c - cur) over the springs of p, the neighbours' displacements read from
// `from`, dst_read or src (jacobi_move): neighbour_sum(from, p, cur, ksum) calls the function
// written for that binding.
#define NEIGHBOUR_SUM(NAME, FROM) \
vec3 NAME(uint p, vec3 cur, out float ksum) \
{ \
    vec3 acc = vec3(0.0); \
    ksum = 0.0; \
    for (uint q = 0; q < QUADS; q++) { \
        uvec4 n = quad_neighbours(q, p); \
        vec4 k = quad_k(q, p); \
        for (uint j = 0; j < 4u; j++) { \
            acc += k[j] * (fetch(FROM, n[j]) - cur); \
            ksum += k[j]; \
        } \
    } \
    return acc; \
}
NEIGHBOUR_SUM(neighbour_sum_dst_read, dst_read)
NEIGHBOUR_SUM(neighbour_sum_src, src)
#define neighbour_sum(from, p, cur, ksum) neighbour_sum_##from(p, cur, ksum)
