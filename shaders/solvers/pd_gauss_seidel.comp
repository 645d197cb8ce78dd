#version 450
#extension GL_GOOGLE_include_directive : require
// One colour of a multi-colour Gauss-Seidel sweep with SOR, in place on dst:
//   u_p <- u_p + omega ((b_p + sum_c k_c u_c) / (m_p/h^2 + sum_c k_c) - u_p)
// No two particles of one colour share a spring, so a colour updates in parallel.
// FIRST (the first sweep of an outer iteration) also computes b_p from src, the iterate at
// the start of the outer iteration, and reads neighbours of colours not yet swept from src:
// those of lower colours (index < pc.first) were already written to dst in this sweep.
// Built a second time with RESIDUAL: the first sweep of an outer iteration that a convergence
// check follows, which also writes each particle's squared residual at src (pd_common.glsl).
// FIRST does not over-relax a particle the contact pass before it moved (it marked the
// particle's w, pd_contact.comp): the springs pull such a particle back by about kappa d of
// the contact's push d (kappa = sum k / (m/h^2 + sum k), near 1 for a stiff cloth), and omega
// kappa d > d put it back past where it was, into the contact, which pushed it out further
// after the next outer iteration; the last push of a substep becomes velocity. ribbons.json
// diverged so at omega 1.7 on lavapipe (1.6 on an NVIDIA H100), box-stack.json stretched a
// spring ten times on the H100 (README "Never exploding").
// PREDICTS (FIRST only; lib/solvers/pd_passes.c, first_sweep_predicts) folds the prediction
// into the first sweep of a substep where it is plain, y = u (1 - damping) + h^2 g (no air,
// rest memory, contact, check, grab or attached particle): each particle starts from its
// prediction and writes it to y, and neighbours not yet swept are predicted where read. 1: the
// last substep's displacements are in src; 2: in dst (the outer iterations are odd), which the
// colours swept before this one have overwritten, so their starting iterates are read from y.
// The watch is predict's: this pass counts the substep and measures each particle's first
// spring (local_step, flush_stretched). The same bits as the prediction's own pass
// (tests/solvers/test_solver.c), one pass over the particles fewer a substep: peer-hanging.json
// 22.7-23.5 -> 20.0-21.2 ms a frame on one lavapipe thread (docs/performance.md).
// Built a third time with LAST_FINALIZES: the last sweep of a substep where nothing comes
// between it and finalize (lib/solvers/pd_passes.c, last_sweep_finalizes) does finalize's work
// on each particle it sweeps — x_{n+1} = x_n + u and the divergence watch — one pass over the
// particles fewer a substep, the same bits (tests/solvers/test_solver.c). Not with tethers:
// projected colour by colour inside the sweep (the colours after each reading its tethered
// iterate), peer-hanging.json ended 11.4 % stretched instead of 2.1 (docs/limits.md).
layout(constant_id = 6) const uint PREDICTS = 0u;
#define FIRST_PREDICTS PREDICTS
#include "solvers/pd_common.glsl"

layout(constant_id = 2) const bool FIRST = false;

#ifdef LAST_FINALIZES
#include "solvers/finalize.glsl"
bool halted = false, stretched = false;
finalize_record record = finalize_none();

// p's new iterate u moves its position (not once the watch has stopped the simulation).
vec3 finalized(uint p, vec3 u)
{
    if (!halted)
        finalize_u(p, imageLoad(x_read, int(p)), u, stretched, record);
    return u;
}
#define FINALIZED(p, u) finalized(p, u)
#else
#define FINALIZED(p, u) (u)
#endif

void main()
{
    uint stride = invocation_stride();
    uint i = gl_GlobalInvocationID.x;
    vec3 shift = sweep_shift();
    // The divergence watch's count of substeps, as predict.comp keeps it (not in the warm-up
    // dispatches of no particle).
    if (FIRST && PREDICTS != 0u && pc.first == 0u && i == 0u && pc.count > 0u)
        watch.substep += 1u;
#ifdef LAST_FINALIZES
    uint now = watch.substep;
    halted = watch.diverged_at < now;
    stretched = watch.stretched != 0u;
#endif
    // Two particles per pass of the loop where a particle has one quad of springs: a CPU
    // device runs an invocation's reads one after another, and a particle's eight gathers leave
    // their latency unhidden; two particles' sixteen overlap (on lavapipe a 100 x 100 sweep of
    // structural springs 69 -> 64 us). With more quads a particle has reads enough of its own,
    // and two of them spilled registers (the poncho's sweeps 4.7 -> 5.1 ms a frame). The first
    // sweep's local step gained nothing.
    if (!FIRST && QUADS == 1u) {
        for (; i + stride < pc.count; i += 2u * stride) {
            uint p = pc.first + i, q = p + stride;
            vec4 bp = imageLoad(rhs_read, int(p)), bq = imageLoad(rhs_read, int(q));
            vec3 up = fetch(dst_read, p), uq = fetch(dst_read, q);
            float kp, kq;
            vec3 ap = neighbour_sum(dst_read, p, up, kp);
            vec3 aq = neighbour_sum(dst_read, q, uq, kq);
            vec3 np = bounded(p, up + pc.omega * jacobi_move(bp, up, ap, kp), shift);
            vec3 nq = bounded(q, uq + pc.omega * jacobi_move(bq, uq, aq, kq), shift);
            dst[p] = vec4(FINALIZED(p, np), 0.0);
            dst[q] = vec4(FINALIZED(q, nq), 0.0);
        }
    }
    for (; i < pc.count; i += stride) {
        uint p = pc.first + i;
        vec3 acc;
        vec4 b;
        vec3 cur;
        float ksum;
        float omega = pc.omega;
        if (FIRST && PREDICTS != 0u) {
            cur = predicted(PREDICTS == 2u ? fetch(dst_read, p) : fetch(src, p));
            b = local_step(p, cur, pc.first, acc, ksum);
        } else if (FIRST) {
            vec4 start = imageLoad(src, int(p));
            cur = start.xyz;
            if (start.w != 0.0)
                omega = min(omega, 1.0);
            b = local_step(p, cur, pc.first, acc, ksum);
        } else {
            b = imageLoad(rhs_read, int(p));
            cur = fetch(dst_read, p);
            acc = neighbour_sum(dst_read, p, cur, ksum);
        }
        vec3 next = bounded(p, cur + omega * jacobi_move(b, cur, acc, ksum), shift);
        dst[p] = vec4(FINALIZED(p, next), 0.0);
    }
    if (FIRST && PREDICTS != 0u)
        flush_stretched();
#ifdef LAST_FINALIZES
    finalize_watch(record, now);
#endif
}
