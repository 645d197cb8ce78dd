#version 450
#extension GL_GOOGLE_include_directive : require
// Every outer iteration of a Gauss-Seidel substep in one dispatch of ONE workgroup: the sweeps
// of pd_gauss_seidel.comp (the first with the local step, as FIRST), colour by colour, with a
// workgroup barrier after each colour instead of a dispatch and a pipeline barrier, and the
// passes between outer iterations likewise. Each particle gets the same floating-point
// operations in the same order as there (the same functions of pd_common.glsl), colours in
// the same order, so the iterate is the same bit for bit; the iterates, the one before and the
// one being written, and the right-hand side are read and written through the storage
// buffers, coherent, after memoryBarrierBuffer() and barrier(). The two iterates swap roles
// after each outer iteration (pd_common.glsl's `flipped`), as the unfused dispatches' sets
// alternate, so the last outer iteration writes u0 there as here. The workgroup's invocations
// stride over each colour; no invocation waits on another workgroup, so this is correct on any
// conformant device. lib/solvers/pd_fused.c decides where it runs (one workgroup's worth of
// work, no pass between the outer iterations that it does not run itself).
//
// After each outer iteration's sweeps, the passes that follow them before the next, where
// pd_passes.c puts them here (pc.after): the strain limit's round colour by colour
// (pd_strain.glsl), the tethers (tether.glsl), the contact between cloths over the particles
// in listed pairs and the contact over every particle (pd_contact.glsl), and after the last
// outer iteration the strain limit's three rounds after contact and finalize (finalize.glsl),
// each with a barrier after it
// — the same functions on the same particles in the same order as their dispatches, so the
// same bits, with one dispatch a substep's solve instead of up to (5 + 4 colours) an outer
// iteration.
#define PD_FUSED 1
// The sweeps read their neighbours' iterate through swept_dst (below): from shared memory where
// the workgroup keeps its copy's iterate there.
vec3 swept_dst(uint i);
#define SWEPT_DST(i) swept_dst(i)
#include "solvers/pd_common.glsl"
#include "solvers/pd_strain.glsl"
#include "solvers/tether.glsl"
#include "solvers/pd_contact.glsl"
#include "solvers/finalize.glsl"
#define PREDICT_WIND_ID 6
#include "solvers/predict.glsl"

// The end of colour c in one copy (shared/layout.h: two 16-bit ends to a uint).
uint colour_end(uint c)
{
    uvec4 group = c < 8u ? pc.ends0 : c < 16u ? pc.ends1 : pc.ends2;
    uint word = group[(c % 8u) / 2u];
    return (c % 2u) == 0u ? (word & 0xffffu) : (word >> 16u);
}

// The workgroup's copy and their number (shared/layout.h): copy k's particles of colour c are
// [C s + k n, C s + (k + 1) n) for C copies, s the colour's start in a copy and n its size.
uint copies = pc.colours >> 8u;
uint colours = pc.colours & 0xffu;
uint copy = 0u;

// The copy's particles of colour c, [begin, end), from the colour's start and end in a copy.
void copy_range(uint start, uint end, out uint begin, out uint stop)
{
    uint n = end - start;
    begin = copies * start + copy * n;
    stop = begin + n;
}

// The copy's pinned particles among the first `count` (finalize's attached ones), after its
// free ones: copy k's are [F + k P, F + (k + 1) P), F the free particles, P a copy's pinned.
void copy_pinned(uint count, out uint begin, out uint stop)
{
    uint n = count > pc.stride ? (count - pc.stride) / copies : 0u;
    begin = pc.stride + copy * n;
    stop = begin + n;
}

// SHARED_SLOTS (id 8) above 0: the sweeps keep the iterate of the workgroup's copy's free
// particles in shared memory, SHARED_SLOTS of them (lib/sim/sim.c, fuse_copies: where they
// fit the device's shared memory, on a GPU or when the caller asks), in place, as Gauss-Seidel
// is: a particle's slot holds the iterate before its colour's update until that update, after
// it the new one. So the
// first sweep reads a neighbour swept before it from its slot and the iterate at the start of
// the outer iteration from src; the later sweeps read only slots. A barrier on shared memory
// alone orders the colours, which on a GPU costs a fraction of a round trip to coherent global
// memory. After the last sweep of an outer iteration every slot goes to dst, where the passes
// after the sweeps, the next outer iteration's local step and finalize read it: the same
// values in the same operations, so the same bits. A copy's particles of colour c lie at
// [C s + k n, C s + (k + 1) n) (copy_range); in the slots at [s, s + n).
layout(constant_id = 8) const uint SHARED_SLOTS = 0u;
const bool SHARED = SHARED_SLOTS > 0u;
shared vec4 slots[SHARED ? SHARED_SLOTS : 1u];

// ONE_COPY (id 9): the sweeps take the whole scene as one copy (lib/sim/sim.c, fuse_copies:
// cvk_sim.fused_copies 1, the push constants' copies), whose slots are its particles' indices.
layout(constant_id = 9) const bool ONE_COPY = false;

// The slot of free particle q of the workgroup's copy: the colour it lies in, found from the
// colour ends (the push constants; no memory read). With one copy no loop: swept_dst calls this
// at every neighbour read, and llvmpipe runs a loop's body under an empty mask even where no
// invocation enters it, counting each step towards its silent end of an invocation's loops
// after 65,535 (docs/limits.md): the loop over the colours here made a 40 x 40 cloth's
// sweeps in a workgroup of 8 pass it at 3 outer x 4 inner iterations.
uint slot_of(uint q)
{
    if (ONE_COPY)
        return q;
    uint start = 0u;
    for (uint c = 0u; c < colours; c++) {
        uint end = colour_end(c), begin, stop;
        copy_range(start, end, begin, stop);
        // a particle of a later colour lies at or past copies * end >= stop
        if (q < stop)
            return start + (q - begin);
        start = end;
    }
    return 0u;
}

vec3 swept_dst(uint i)
{
    if (SHARED && i < pc.stride)
        return slots[slot_of(i)].xyz;
    return FETCH_DST(i);
}

// The iterate of every free particle of the copy from the slots into dst, where the passes
// after the sweeps find it.
void slots_to_dst()
{
    uint lanes = gl_WorkGroupSize.x;
    uint lane = gl_LocalInvocationID.x;
    uint start = 0u;
    for (uint c = 0u; c < colours; c++) {
        uint end = colour_end(c), begin, stop;
        copy_range(start, end, begin, stop);
        for (uint p = begin + lane; p < stop; p += lanes)
            STORE_DST(p, slots[start + (p - begin)]);
        start = end;
    }
    memoryBarrierBuffer();
    barrier();
}

// One round of the strain limit, colour by colour, moves at most `most` m (0: any).
void strain_round(float most, vec3 shift)
{
    uint lanes = gl_WorkGroupSize.x;
    uint start = 0u;
    for (uint c = 0u; c < colours; c++) {
        uint end = colour_end(c), begin, stop;
        copy_range(start, end, begin, stop);
        for (uint p = begin + gl_LocalInvocationID.x; p < stop; p += lanes)
            strain_one(p, pc.strain_limit, most, shift);
        memoryBarrierBuffer();
        barrier();
        start = end;
    }
}

// The copy's free particles, colour by colour, for a pass over every one of them: FOR_FREE(p,
// body) runs body for each p of the copy the invocation takes.
#define FOR_FREE(p, body) \
    { \
        uint start_ = 0u; \
        for (uint c_ = 0u; c_ < colours; c_++) { \
            uint end_ = colour_end(c_), begin_, stop_; \
            copy_range(start_, end_, begin_, stop_); \
            for (uint p = begin_ + lane; p < stop_; p += lanes) \
                body; \
            start_ = end_; \
        } \
    }

// The passes after the sweeps (`after`: CVK_PD_FUSED_* bits), as pd_passes.c's
// add_after_outer orders them.
void after_sweeps(uint after, vec3 shift)
{
    uint lanes = gl_WorkGroupSize.x;
    uint lane = gl_LocalInvocationID.x;
    if ((after & CVK_PD_FUSED_STRAIN) != 0u)
        strain_round(0.0, shift);
    if ((after & CVK_PD_FUSED_TETHERS) != 0u) {
        FOR_FREE(p, tether_one(p))
        memoryBarrierBuffer();
        barrier();
    }
    // Between cloths: one copy only (pd_passes.c fuses copies without it).
    if ((after & CVK_PD_FUSED_CLOTH_CONTACT) != 0u) {
        uint count = lists[CVK_LIST_LISTED_COUNT], start = list_start(CVK_LIST_LISTED_GROUPS);
        for (uint i = lane; i < count; i += lanes)
            contact_one(lists[start + i], true, shift);
        memoryBarrierBuffer();
        barrier();
    }
    // Over the free particles, and with one copy the attached ones past them where
    // contact_count takes them (pd_passes.c).
    if ((after & CVK_PD_FUSED_CONTACT) != 0u) {
        FOR_FREE(p, contact_one(p, false, shift))
        for (uint p = pc.stride + lane; ONE_COPY && p < pc.contact_count; p += lanes)
            contact_one(p, false, shift);
        memoryBarrierBuffer();
        barrier();
    }
    // The strain limit's rounds after the last outer iteration's contact: moves under half the
    // thickness (pd_passes.c).
    for (uint r = 0u; (after & CVK_PD_FUSED_LAST) != 0u && r < 3u; r++)
        strain_round(0.5 * contact_u.thickness, shift);
    // finalize after the last outer iteration (finalize.comp): nothing reads x after it here
    if ((after & CVK_PD_FUSED_FINALIZE) == 0u)
        return;
    bool tether_first = (after & CVK_PD_FUSED_TETHERED) != 0u;
    uint now = watch.substep;
    bool halted = watch.diverged_at < now;
    if (halted && !tether_first)
        return;
    bool stretched = watch.stretched != 0u;
    finalize_record record = finalize_none();
    FOR_FREE(p, finalize_one(p, halted, stretched, tether_first, record))
    uint begin, stop;
    copy_pinned(pc.finalize_count, begin, stop);
    for (uint p = begin + lane; p < stop; p += lanes)
        finalize_one(p, halted, stretched, tether_first, record);
    finalize_watch(record, now);
}

// One copy's substep.
void solve_copy()
{
    uint lanes = gl_WorkGroupSize.x;
    uint lane = gl_LocalInvocationID.x;
    uint sweeps = pc.iterations & 0xffffu, outers = pc.iterations >> 16u;
    uint every = (pc.after >> 16u) & 0x7fffu;
    vec3 shift = sweep_shift();
    if ((pc.after & CVK_PD_FUSED_PREDICT) != 0u) {
        // predict.comp's work: from u0, the last substep's displacement (the first outer
        // iteration's dst where their count is odd, else its src), into the first one's src.
        // One copy only (pd_passes.c): the substep's count would race between workgroups.
        bool odd = (outers & 1u) != 0u;
        if (lane == 0u)
            watch.substep += 1u;
        FOR_FREE(p, src_u[p] = predict_one(p, (odd ? dst_u[p] : src_u[p]).xyz))
        flush_stretched();
        memoryBarrierBuffer();
        barrier();
    }
    for (uint outer = 0u; outer < outers; outer++) {
        flipped = (outer & 1u) != 0u;
        for (uint sweep = 0u; sweep < sweeps; sweep++) {
            uint start = 0u;
            for (uint c = 0u; c < colours; c++) {
                uint end = colour_end(c), begin, stop;
                copy_range(start, end, begin, stop);
                // Below `begin`, the colours before c (of every copy): swept in this sweep.
                for (uint p = begin + lane; p < stop; p += lanes) {
                    vec3 acc;
                    vec4 b;
                    vec3 cur;
                    float ksum;
                    // The last sweep's omega comes apart (cvk_gs_sweep_omega).
                    float omega = sweep + 1u == sweeps ? pc.last_omega : pc.omega;
                    uint slot = start + (p - begin);
                    if (sweep == 0u) {
                        vec4 start = LOAD_SRC(p);
                        cur = start.xyz;
                        if (start.w != 0.0)
                            omega = min(omega, 1.0);
                        b = local_step(p, cur, begin, acc, ksum);
                    } else {
                        b = rhs[p];
                        cur = SHARED ? slots[slot].xyz : FETCH_DST(p);
                        acc = neighbour_sum_dst(p, cur, ksum);
                    }
                    vec4 next = vec4(bounded(p, cur + omega * jacobi_move(b, cur, acc, ksum), shift), 0.0);
                    if (SHARED)
                        slots[slot] = next;
                    else
                        STORE_DST(p, next);
                }
                if (SHARED)
                    memoryBarrierShared();
                else
                    memoryBarrierBuffer();
                barrier();
                start = end;
            }
        }
        if (SHARED)
            slots_to_dst();
        // The passes after this outer iteration: the last one's, or the others' with the
        // tethers after every `every`-th only (pd_passes.c's tether_pass_after).
        uint after = pc.after & 0xffu;
        if (outer + 1u == outers)
            after = (pc.after >> 8u) & 0xffu;
        else if ((outer + 1u) % max(every, 1u) != 0u)
            after &= ~CVK_PD_FUSED_TETHERS;
        after_sweeps(after, shift);
    }
}

void main()
{
    // Copies past the dispatch's workgroups (shared/layout.h): each workgroup strides over
    // them. No barrier between two: they share no particle.
    for (copy = gl_WorkGroupID.x; copy < copies; copy += gl_NumWorkGroups.x)
        solve_copy();
    // Whether the device ended this invocation's loops early (loops_cut, contact/bounds.glsl):
    // the sweeps' loop over a colour's particles reaches llvmpipe's limit in a caller's small
    // workgroup (docs/limits.md); the watch's flag, which cvk_sim_step reports.
    if (loops_cut(pc.count))
        atomicOr(watch.sweeps_cut, 1u);
}
