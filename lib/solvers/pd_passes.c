/* The passes of projective dynamics: Verlet prediction, the solve (Gauss-Seidel colour
   sweeps, or Jacobi / Chebyshev sweeps between two iterates), x += u; and the schedule
   that keeps a truncated solve stable (see solve_pd.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "contact/hash.h"
#include "solvers/reference.h"
#include "solvers/solve_pd.h"
#include "contact/collide.h"
#include "features/aero.h"
#include "features/attach.h"
#include "features/grab.h"
#include "features/tear.h"

uint32_t cvk_sweep_cycle(const cvk_solver_desc* solver)
{
    uint32_t sweeps = solver->outer_iterations * solver->inner_iterations;
    if (solver->linear == CVK_LINEAR_CHEBYSHEV && solver->inner_iterations > 1)
        return solver->inner_iterations;
    return sweeps;
}

float cvk_jacobi_sweep_omega(uint32_t sweep, uint32_t cycle, float omega)
{
    if (sweep == 0 && cycle % 2 == 1 && omega > CVK_STABLE_FIRST_OMEGA)
        return CVK_STABLE_FIRST_OMEGA;
    return omega;
}

double cvk_chebyshev_stable_rho(uint32_t m)
{
    if (m == 0)
        return 0.0;
    return 1.0 / cosh(acosh(3.0) / m);
}

static uint32_t effective_delay(uint32_t delay)
{
    return delay < 1 ? 1 : delay; /* the first Chebyshev step needs an older iterate */
}

double cvk_chebyshev_weight(uint32_t sweep, uint32_t delay, double rho)
{
    delay = effective_delay(delay);
    if (sweep < delay)
        return 1.0;
    double w = 2.0 / (2.0 - rho * rho);
    for (uint32_t s = delay; s < sweep; s++)
        w = 4.0 / (4.0 - rho * rho * w);
    return w;
}

double cvk_estimate_jacobi_rho(const cvk_build* b, double inv_h2, double omega)
{
    uint32_t nf = b->free_count;
    if (nf == 0)
        return 0.0;
    double* diag = malloc(nf * sizeof(double));
    double* v = malloc(nf * sizeof(double));
    double* w = malloc(nf * sizeof(double));
    if (!diag || !v || !w) {
        free(diag);
        free(v);
        free(w);
        return 0.0;
    }
    for (uint32_t p = 0; p < nf; p++) {
        diag[p] = b->mass[p] * inv_h2;
        for (uint32_t s = 0; s < b->degree[p]; s++)
            diag[p] += b->adj_k[(size_t)s * nf + p];
    }
    /* A deterministic start vector with components along every mode. */
    uint32_t seed = 12345u;
    for (uint32_t p = 0; p < nf; p++) {
        seed = seed * 1664525u + 1013904223u;
        v[p] = (double)(seed >> 8) / (double)(1u << 24) - 0.5;
    }
    /* G v = (1 − ω) v + ω D⁻¹ Σ k v_c over free neighbours. The spectrum of G can be
       symmetric (bipartite grids), so iterate on G² and take the square root. */
    double rho = 0.0;
    uint32_t iterations = (uint32_t)fmin(400.0, fmax(50.0, 2e8 / ((double)nf * (b->max_degree + 1))));
    for (uint32_t it = 0; it < iterations; it++) {
        double norm_before = 0.0, norm_after = 0.0;
        for (uint32_t p = 0; p < nf; p++)
            norm_before += v[p] * v[p];
        for (int twice = 0; twice < 2; twice++) {
            for (uint32_t p = 0; p < nf; p++) {
                double sum = 0.0;
                for (uint32_t s = 0; s < b->degree[p]; s++) {
                    size_t e = (size_t)s * nf + p;
                    uint32_t n = b->adj_index[e];
                    if (n < nf)
                        sum += b->adj_k[e] * v[n];
                }
                w[p] = (1.0 - omega) * v[p] + omega * sum / diag[p];
            }
            double* t = v;
            v = w;
            w = t;
        }
        for (uint32_t p = 0; p < nf; p++)
            norm_after += v[p] * v[p];
        if (norm_before <= 0.0 || norm_after <= 0.0)
            break;
        rho = pow(norm_after / norm_before, 0.25);
        double scale = 1.0 / sqrt(norm_after);
        for (uint32_t p = 0; p < nf; p++)
            v[p] *= scale;
    }
    free(diag);
    free(v);
    free(w);
    return rho < 1.0 ? rho : 0.999999;
}

double cvk_pd_chebyshev_rho(const cvk_solver_desc* solver, double h, const cvk_build* b,
                            double estimated, double* estimated_out)
{
    uint32_t cycle = cvk_sweep_cycle(solver);
    uint32_t delay = effective_delay(solver->chebyshev_delay);
    double rho;
    if (solver->chebyshev_rho > 0.0f)
        rho = solver->chebyshev_rho;
    else if (estimated >= 0.0)
        rho = estimated;
    else
        rho = cvk_estimate_jacobi_rho(b, 1.0 / (h * h), solver->omega);
    if (estimated_out)
        *estimated_out = rho;
    double cap = cvk_chebyshev_stable_rho(cycle > delay ? cycle - delay : 0);
    return fmin(rho, cap);
}

typedef struct pd_builder {
    cvk_sim* sim;
    cvk_plan* plan;
    const cvk_pd* pd;
    const cvk_solver_desc* solver;
    cvk_pd_push base;
    VkDescriptorSet contact_set;       /* set 1 of every dispatch */
    bool contact;                      /* the scene collides: a contact op per outer iteration */
    bool tethers;                      /* a cloth has tethers: a tether op per outer iteration */
    bool tethers_in_finalize;          /* the last outer iteration's tethers: finalize's own */
    uint32_t predict, solve, tether_pass, contact_pass, finalize; /* pass indices */
    uint32_t strain_pass;              /* with solver.strain_limit: one op per colour per outer */
    /* With a tolerance: the check's pass and push data, and whether the substep's first check
       is behind (then the solve's ops are dispatched indirectly: the device may stop them). */
    bool checking, armed;
    uint32_t check_pass;
    cvk_pd_converge_push check;
    bool fused;                        /* rbgs: one fused dispatch for the solve (pd_fused.c) */
    uint32_t copies;                   /* fused: a workgroup each (cvk_sim.fused_copies) */
} pd_builder;

/* The contact pass over every particle: the build for the scene's run count where the
   colliders' types are fixed (cvk_collide.runs), else the one that reads them; without the
   funnels' edge test (pd_contact.glsl, NO_FUNNELS) where the scene has no funnel. */
_Static_assert(CVK_PIPE_PD_CONTACT_PLAIN_RUNS4 == CVK_PIPE_PD_CONTACT_PLAIN_RUNS2 + CVK_COLLIDER_RUNS - 2,
               "one pipeline a run count, in order");
static cvk_pipeline_id contact_pipeline(const cvk_sim* s)
{
    if (cvk_collide_has_funnels(s->collide))
        return cvk_collide_pipeline(s->collide, CVK_PIPE_PD_CONTACT, CVK_PIPE_PD_CONTACT_RUNS2);
    return cvk_collide_pipeline(s->collide, CVK_PIPE_PD_CONTACT_PLAIN, CVK_PIPE_PD_CONTACT_PLAIN_RUNS2);
}
/* The fused sweeps, which run the contact passes themselves: likewise without the funnels'
   edge test where the scene has no funnel. */
static cvk_pipeline_id fused_pipeline(const cvk_sim* s)
{
    return cvk_collide_has_funnels(s->collide) ? CVK_PIPE_GS_FUSED : CVK_PIPE_GS_FUSED_PLAIN;
}

static const char* const set_note[CVK_PD_SET_COUNT] = {
    [CVK_PD_SET_U0_TO_U1] = "u0 -> u1",
    [CVK_PD_SET_U1_TO_U0] = "u1 -> u0",
    [CVK_PD_SET_U0_TO_U0] = "u0 -> u0",
};

/* Appends a dispatch over particles [first, first + count); none when count is 0 (a scene
   whose particles are all pinned has nothing to solve). Returns the op, or NULL. */
static cvk_op* add_op(pd_builder* pb, cvk_pipeline_id pipeline, cvk_pd_set set, uint32_t pass,
                      uint32_t first, uint32_t count, float cheb, float omega)
{
    cvk_pd_push push = pb->base;
    push.first = first;
    push.count = count;
    push.cheb = cheb;
    push.omega = omega;
    cvk_op* op;
    bool listed = pipeline == CVK_PIPE_PD_CLOTH_CONTACT;
    if ((pb->armed || listed) && count > 0) {
        /* The cloth contact pass: the groups of detection's work list (the shader covers the
           list's count); while a checked solve runs, those of the contact pass over every
           particle (0 once the solve has stopped). */
        VkBuffer from = pb->pd->scalars.buffer;
        VkDeviceSize slot = offsetof(cvk_pd_scalars, sweep_groups);
        if (listed && !pb->armed) {
            from = pb->sim->collide->lists.buffer;
            slot = 4u * CVK_LIST_LISTED_GROUPS;
        } else if (listed || pipeline == contact_pipeline(pb->sim)) {
            slot = offsetof(cvk_pd_scalars, contact_groups);
        }
        op = cvk_plan_dispatch_indirect(pb->plan, pass, pipeline,
                                        pb->pd->descriptors.pipeline_layout,
                                        pb->pd->descriptors.sets[set], CVK_DOMAIN_PARTICLES, from,
                                        slot, &push, sizeof push);
        if (op) {
            op->first = first;
            op->count = count;
        }
    } else {
        op = cvk_plan_dispatch(pb->plan, pass, pipeline, pb->pd->descriptors.pipeline_layout,
                               pb->pd->descriptors.sets[set], CVK_DOMAIN_PARTICLES, first, count,
                               &push, sizeof push);
    }
    if (op) {
        op->set1 = pb->contact_set;
        snprintf(op->note, sizeof op->note, "%s", set_note[set]);
    }
    return op;
}

/* The solve's details for --plan: iteration, colour, weights that differ from the plain. */
static void solve_note(pd_builder* pb, cvk_op* op, uint32_t outer, uint32_t inner, int colour,
                       cvk_pd_set set)
{
    if (!op)
        return;
    cvk_pd_push pushed;
    memcpy(&pushed, op->push, sizeof pushed);
    const cvk_pd_push* push = &pushed;
    int n = snprintf(op->note, sizeof op->note, "outer %u inner %u", outer + 1, inner + 1);
    if (colour >= 0 && n > 0 && (size_t)n < sizeof op->note)
        n += snprintf(op->note + n, sizeof op->note - n, " colour %d", colour);
    if (push->cheb != 1.0f && n > 0 && (size_t)n < sizeof op->note)
        n += snprintf(op->note + n, sizeof op->note - n, " cheb %.4f", push->cheb);
    if (push->omega != pb->solver->omega && n > 0 && (size_t)n < sizeof op->note)
        n += snprintf(op->note + n, sizeof op->note - n, " omega %g", push->omega);
    if (n > 0 && (size_t)n < sizeof op->note)
        snprintf(op->note + n, sizeof op->note - n, ", %s", set_note[set]);
}

/* Sets reading U[src] and writing U[dst]. */
static cvk_pd_set set_for(uint32_t src, uint32_t dst)
{
    if (src == 0 && dst == 0)
        return CVK_PD_SET_U0_TO_U0;
    return src == 0 ? CVK_PD_SET_U0_TO_U1 : CVK_PD_SET_U1_TO_U0;
}

/* y = u (1 - damping) + h² g, and the first iterate y + rest memory into the buffer that
   holds it. */
static void add_predict(pd_builder* pb, const cvk_build* b, uint32_t start)
{
    add_op(pb, CVK_PIPE_PREDICT, set_for(0, start), pb->predict, 0, b->free_count, 1.0f,
           pb->base.omega);
    cvk_grab_add_op(pb->sim, pb->plan, "after predict: y (w: 2^100), u0, u1");
}

/* Whether finalize projects the last outer iteration's tethers itself (shaders/solvers/
   finalize.comp, TETHERED): where nothing would come between that tether pass and finalize —
   no contact, no grab, no convergence check (whose copy-back may come between) — and no
   attached particle, which finalize moves while the tethers read the pinned particles'
   positions. One pass over the particles fewer a substep, the same bits. */
static bool tethers_in_finalize(const cvk_sim* s, const pd_builder* pb)
{
    return pb->tethers && !pb->contact && !pb->checking && !s->grab->planned &&
           s->build.attached_count == 0 && pb->solver->linear != CVK_LINEAR_GS_CPU;
}

/* Whether the tether pass runs after outer iteration `outer` (solver.tether_every, and the
   last, unless finalize projects those). */
static bool tether_pass_after(const pd_builder* pb, uint32_t outer)
{
    uint32_t every = pb->solver->tether_every ? pb->solver->tether_every : 1;
    bool last = outer + 1 == pb->solver->outer_iterations;
    return pb->tethers && ((outer + 1) % every == 0 || last) && !(last && pb->tethers_in_finalize);
}

/* Where the tethers run: finalize's own for the last outer iteration where it can, the tether
   pass listed where some outer iteration still needs it. */
static void plan_tethers(const cvk_sim* s, pd_builder* pb)
{
    pb->tethers_in_finalize = tethers_in_finalize(s, pb);
    for (uint32_t outer = 0; outer < pb->solver->outer_iterations; outer++)
        if (tether_pass_after(pb, outer)) {
            pb->tether_pass = cvk_plan_pass(pb->plan, "tethers");
            return;
        }
}

/* The particles finalize moves: with attachments the pinned particles too (the attached move
   by the displacement the attach pass gave them, the others by their u of 0: x + 0 is x, bit
   for bit). */
static uint32_t finalize_count(const cvk_build* b)
{
    return b->attached_count > 0 ? b->particle_count : b->free_count;
}

/* Whether the grab's op comes between the last outer iteration and finalize: the solved
   displacement of a grabbed particle, again, where tethers or contact may have moved it after
   the last sweep (the sweeps themselves hold it: its weight, grab.h) — except with
   self-contact, where the hand too is kept within the particle's bound. */
static bool grab_before_finalize(const pd_builder* pb)
{
    return (pb->tethers || pb->contact) && !pb->sim->collide->self && pb->sim->grab->planned;
}

/* x += u: the substep's displacement, which the solve left in U0, moves the positions (with
   the last tethers first where tethers_in_finalize says so). */
static void add_finalize(pd_builder* pb, const cvk_build* b)
{
    uint32_t count = finalize_count(b);
    if (grab_before_finalize(pb))
        cvk_grab_add_op(pb->sim, pb->plan, "before finalize: u0, u1");
    add_op(pb, pb->tethers_in_finalize ? CVK_PIPE_FINALIZE_TETHERED : CVK_PIPE_FINALIZE,
           CVK_PD_SET_U0_TO_U0, pb->finalize, 0, count, 1.0f, pb->base.omega);
}

/* One op of a convergence check over `count` items: dispatched directly before the substep's
   first check has armed the indirect commands, then through the group count at `groups_at`
   in the scalars (0 once the solve has stopped). */
static cvk_op* check_op(pd_builder* pb, cvk_pipeline_id pipeline, VkDeviceSize groups_at,
                        uint32_t count, const cvk_pd_converge_push* push)
{
    const cvk_pd* pd = pb->pd;
    VkPipelineLayout layout = pd->converge_descriptors.pipeline_layout;
    VkDescriptorSet set = pd->converge_descriptors.sets[0];
    if (!pb->armed)
        return cvk_plan_dispatch(pb->plan, pb->check_pass, pipeline, layout, set,
                                 CVK_DOMAIN_PARTICLES, 0, count, push, sizeof *push);
    cvk_op* op = cvk_plan_dispatch_indirect(pb->plan, pb->check_pass, pipeline, layout, set,
                                            CVK_DOMAIN_PARTICLES, pd->scalars.buffer, groups_at,
                                            push, sizeof *push);
    if (op)
        op->count = count;
    return op;
}

/* The convergence check that follows the first sweep of outer iteration `outer`, which
   measured the iterate that outer iteration started from (in u1 when in_u1) and wrote the
   squared residuals: partial sums, then one invocation that stops the rest of the substep or
   lets it go on. The first check of a substep (outer 0: the first iterate, the measure the
   others are relative to) is dispatched directly and arms the indirect commands every later
   pass of the solve reads; `swept` counts the sweeps run by then. */
static void add_check(pd_builder* pb, uint32_t outer, bool in_u1, uint32_t swept)
{
    cvk_pd_converge_push push = pb->check;
    push.swept = swept;
    push.in_u1 = in_u1;
    push.first_check = outer == 0;
    push.last_check = outer + 1 == pb->solver->outer_iterations;
    /* Each op is finished before the next append, which may move the list. */
    cvk_op* reduce = check_op(pb, CVK_PIPE_PD_REDUCE, offsetof(cvk_pd_scalars, reduce_groups),
                              CVK_PD_PARTIALS, &push);
    if (reduce)
        snprintf(reduce->note, sizeof reduce->note, "residual at the start of outer %u",
                 outer + 1);
    cvk_op* decide = check_op(pb, CVK_PIPE_PD_DECIDE, offsetof(cvk_pd_scalars, single_groups), 1,
                              &push);
    if (decide) {
        decide->barrier = CVK_BARRIER_COMPUTE_TO_INDIRECT;
        snprintf(decide->note, sizeof decide->note, "stop below the tolerance, after %u sweeps",
                 swept);
    }
    pb->armed = true;
}

/* The end of a checked solve: u0 = u1 when it stopped with its solution in u1 (zero groups
   otherwise); finalize, which reads u0, runs unconditionally. */
static void add_copy_back(pd_builder* pb, const cvk_build* b)
{
    if (!pb->checking || !pb->armed)
        return;
    cvk_pd_converge_push push = pb->check;
    cvk_op* op = cvk_plan_dispatch_indirect(pb->plan, pb->check_pass, CVK_PIPE_PD_COPY,
                                            pb->pd->descriptors.pipeline_layout,
                                            pb->pd->descriptors.sets[CVK_PD_SET_U1_TO_U0],
                                            CVK_DOMAIN_PARTICLES, pb->pd->scalars.buffer,
                                            offsetof(cvk_pd_scalars, copy_groups), &push,
                                            sizeof push);
    if (op) {
        op->count = b->free_count;
        snprintf(op->note, sizeof op->note, "when stopped in u1, u1 -> u0");
    }
    pb->armed = false;
}

/* `rounds` rounds of the strain limit, colour by colour, with moves no longer than `most` (m;
   0: any), after outer iteration `outer`. */
static void add_strain(pd_builder* pb, const cvk_build* b, cvk_pd_set set, uint32_t outer,
                       uint32_t rounds, float most, const char* when)
{
    for (uint32_t r = 0; pb->solver->strain_limit > 0.0f && r < rounds * b->colour_count; r++) {
        uint32_t c = r % b->colour_count;
        uint32_t first = b->colour_start[c], count = b->colour_start[c + 1] - first;
        cvk_op* op = add_op(pb, CVK_PIPE_PD_STRAIN, set, pb->strain_pass, first, count, most,
                            1.0f + pb->solver->strain_limit);
        if (op)
            snprintf(op->note, sizeof op->note, "after outer %u%s, colour %u, in place, %s",
                     outer + 1, when, c, set_note[set]);
    }
}

/* Tethers, then contact, after the last sweep of an outer iteration, in place on what it
   wrote (set: the same as that sweep's, so triangle corners come from its src). Contact comes
   last: a tether may pull a particle into a collider, never the other way round. */
static void add_after_outer(pd_builder* pb, const cvk_build* b, cvk_pd_set set, uint32_t outer)
{
    /* Strain limiting first, colour by colour (a particle reads only other colours, which
       its dispatch does not write: shaders/solvers/pd_strain.comp). */
    add_strain(pb, b, set, outer, 1, 0.0f, "");
    if (tether_pass_after(pb, outer)) {
        cvk_op* op = add_op(pb, CVK_PIPE_PD_TETHER, set, pb->tether_pass, 0, b->free_count,
                            1.0f, pb->base.omega);
        if (op)
            snprintf(op->note, sizeof op->note, "after outer %u, in place, %s", outer + 1,
                     set_note[set]);
    }
    if (!pb->contact)
        return;
    bool self = pb->sim->collide->self;
    /* Between cloths first, over the particles in listed pairs (shaders/solvers/pd_contact.comp);
       then every particle: within its bound, out of the colliders. */
    cvk_op* op = self ? add_op(pb, CVK_PIPE_PD_CLOTH_CONTACT, set, pb->contact_pass, 0,
                               b->free_count, 1.0f, pb->base.omega)
                      : NULL;
    if (op)
        snprintf(op->note, sizeof op->note, "after outer %u, the particles in pairs, in place, %s",
                 outer + 1, set_note[set]);
    /* With self-contact the attached particles too: kept within their bounds (collide.h). */
    uint32_t count = self && b->attached_count > 0 ? b->particle_count : b->free_count;
    op = add_op(pb, contact_pipeline(pb->sim), set, pb->contact_pass, 0, count, 1.0f,
                pb->base.omega);
    /* Each particle loops over colliders and traces: a few particles per invocation keep
       lavapipe's per-shader loop budget out of reach (cvk_plan_walk_groups). */
    if (op && !pb->armed)
        op->groups = cvk_plan_walk_groups(pb->plan, op->count);
    if (op)
        snprintf(op->note, sizeof op->note, "after outer %u, in place, %s", outer + 1,
                 set_note[set]);
    /* After the last outer iteration's contact, three rounds more: contact's pushes, which come
       after the strain limit, stretch springs where cloth wraps a collider's edge (table.json's
       corners ended 13 % stretched with a 5 % limit, 5.0 % with these). Each move is kept under
       half the thickness, which contact left the particle off every collider's surface. */
    if (outer + 1 == pb->solver->outer_iterations)
        add_strain(pb, b, set, outer, 3, 0.5f * pb->sim->collide->thickness, " after contact");
}

/* The passes after outer iteration `outer` that add_after_outer would dispatch, run instead by
   the fused dispatch after its sweeps (shaders/solvers/pd_fused.comp), in the same order on the
   same particles: their CVK_PD_FUSED_* bits, with the particle counts they need in `push`. */
static uint32_t fuse_after_outer(const pd_builder* pb, const cvk_build* b, uint32_t outer,
                                 cvk_pd_fused_push* push)
{
    uint32_t after = 0;
    bool strain = pb->solver->strain_limit > 0.0f;
    if (tether_pass_after(pb, outer))
        after |= CVK_PD_FUSED_TETHERS;
    if (strain) {
        after |= CVK_PD_FUSED_STRAIN;
        push->strain_limit = 1.0f + pb->solver->strain_limit;
    }
    if (pb->contact) {
        bool self = pb->sim->collide->self;
        after |= CVK_PD_FUSED_CONTACT | (self ? CVK_PD_FUSED_CLOTH_CONTACT : 0u);
        push->contact_count = self && b->attached_count > 0 ? b->particle_count : b->free_count;
    }
    bool last = outer + 1 == pb->solver->outer_iterations;
    if (strain && last)
        after |= CVK_PD_FUSED_LAST;
    /* finalize too, where no grab op comes before it (its set, u0 -> u0, reads the u0 this last
       outer iteration wrote) */
    if (last && !grab_before_finalize(pb)) {
        after |= CVK_PD_FUSED_FINALIZE | (pb->tethers_in_finalize ? CVK_PD_FUSED_TETHERED : 0u);
        push->finalize_count = finalize_count(b);
    }
    return after;
}

/* The names of the passes in `after` (CVK_PD_FUSED_* bits), for the op's note. */
static void fused_names(uint32_t after, char* out, size_t size)
{
    snprintf(out, size, "%s%s%s%s%s%s", after & CVK_PD_FUSED_STRAIN ? " strain" : "",
             after & CVK_PD_FUSED_TETHERS ? " tethers" : "",
             after & CVK_PD_FUSED_CLOTH_CONTACT ? " pairs" : "",
             after & CVK_PD_FUSED_CONTACT ? " contact" : "",
             after & CVK_PD_FUSED_LAST ? " strain x 3" : "",
             after & CVK_PD_FUSED_FINALIZE ? " finalize" : "");
}

/* Whether the fused dispatch predicts too: where no grab op comes between the prediction and
   the solve (cvk_grab_add_op after predict). */
static bool fused_predict(const pd_builder* pb)
{
    /* a workgroup a copy: predict's count of substeps, which finalize reads, would race */
    return pb->fused && pb->copies == 1 && !pb->sim->grab->planned;
}

/* The fused solve: every outer iteration in one dispatch (shaders/solvers/pd_fused.comp),
   starting from the set of the first, its buffers swapping roles after each as the unfused
   sets alternate; `after` holds the passes after every outer iteration but the last (their
   tethers after every tether_every-th, as tether_pass_after), the last one's and tether_every
   (shared/layout.h). */
static void add_fused(pd_builder* pb, const cvk_build* b, cvk_pd_set first_set)
{
    uint32_t outer = pb->solver->outer_iterations, inner = pb->solver->inner_iterations;
    cvk_pd_fused_push push = cvk_pd_fused_push_of(
        &pb->base, b, inner, outer, cvk_gs_sweep_omega(inner - 1, inner, outer, pb->base.omega),
        pb->copies);
    uint32_t every = pb->solver->tether_every ? pb->solver->tether_every : 1;
    uint32_t between = 0;
    if (outer > 1)
        between = fuse_after_outer(pb, b, 0, &push) | (pb->tethers ? CVK_PD_FUSED_TETHERS : 0u);
    uint32_t last = fuse_after_outer(pb, b, outer - 1, &push);
    bool predict = fused_predict(pb);
    push.after = between | last << 8 | (every & 0x7fffu) << 16 |
                 (predict ? CVK_PD_FUSED_PREDICT : 0u);
    cvk_op* op = cvk_pd_add_fused(pb->plan, pb->solve, pb->pd->descriptors.pipeline_layout,
                                  pb->pd->descriptors.sets[first_set], &push,
                                  fused_pipeline(pb->sim));
    if (!op)
        return;
    op->set1 = pb->contact_set;
    char each[64], extra[64], gone[64], range[40] = "outer 1";
    fused_names(between, each, sizeof each);
    fused_names(last & ~between, extra, sizeof extra);
    fused_names(between & ~last, gone, sizeof gone);
    if (outer > 1)
        snprintf(range, sizeof range, "%souters 1-%u", predict ? "predict, " : "", outer);
    else if (predict)
        snprintf(range, sizeof range, "predict, outer 1");
    char note[384], memory[40] = "global memory";
    const char* groups = pb->copies > 1 ? "a workgroup a copy" : "one workgroup";
    uint32_t slots = pb->sim->fused_shared_slots;
    if (slots)
        snprintf(memory, sizeof memory, "shared memory %.1f KB", slots / 64.0);
    snprintf(note, sizeof note,
             "%s: %u sweeps x %u colours%s%s%s%s%s%s%s; %s of %u, %s; %s first", range,
             inner, b->colour_count, each[0] ? ", then" : "", each,
             extra[0] || gone[0] ? " (the last" : "", extra[0] ? " +" : "", extra,
             gone[0] ? " -" : "", extra[0] || gone[0] ? ")" : "", groups,
             pb->plan->fused_workgroup_size, memory,
             set_note[first_set]);
    snprintf(op->note, sizeof op->note, "%.*s", (int)sizeof op->note - 1, note);
}

/* Whether the unfused Gauss-Seidel's first sweep predicts too (shaders/solvers/
   pd_gauss_seidel.comp, PREDICTS): where the prediction is its plain y = u (1 - damping) +
   h^2 g — no air, no rest memory — and nothing comes between it and the first sweep or reads
   what predict leaves in the first iterate's buffer: no grab, no contact (whose marks the
   first sweep reads), no convergence check (whose residual reads the first iterate), no
   attached particle — and colour 0 has particles (its dispatch counts the substep for the
   divergence watch). One pass over the particles fewer a substep, the same bits. */
static bool first_sweep_predicts(const pd_builder* pb, const cvk_build* b)
{
    return !pb->fused && !pb->checking && !pb->contact && !pb->sim->grab->planned &&
           !pb->sim->aero->enabled && b->attached_count == 0 && pb->base.rest_rate == 0.0f &&
           b->colour_count > 0 && b->colour_start[1] > 0;
}

/* Whether its last sweep finalizes too (pd_gauss_seidel.comp, LAST_FINALIZES, which says why
   not with tethers): nothing between them, and not the first sweep of its outer iteration. */
static bool last_sweep_finalizes(const pd_builder* pb, const cvk_build* b)
{
    return !pb->fused && !pb->checking && !pb->contact && !pb->sim->grab->planned &&
           !pb->tethers && b->attached_count == 0 && pb->base.rest_rate == 0.0f &&
           pb->solver->strain_limit == 0.0f && pb->solver->inner_iterations > 1;
}

/* Gauss-Seidel: every outer iteration reads the previous iterate from one displacement buffer
   (T) and sweeps in place in the other (W); buffers alternate so the last outer iteration
   writes U0, where finalize and the next prediction find it. Where the first sweep predicts,
   the first outer iteration finds the last substep's displacements in U0: in T when the
   outer iterations are even, in W when odd. */
static void plan_gauss_seidel(pd_builder* pb, const cvk_build* b)
{
    uint32_t outer = pb->solver->outer_iterations, inner = pb->solver->inner_iterations;
    bool folded = first_sweep_predicts(pb, b);
    cvk_pipeline_id last_sweep = last_sweep_finalizes(pb, b) ? CVK_PIPE_GS_LAST : CVK_PIPE_GS;
    if (!fused_predict(pb) && !folded)
        add_predict(pb, b, outer % 2);
    if (pb->fused) /* every outer iteration, from the first one's set */
        add_fused(pb, b, set_for(outer % 2, 1 - outer % 2));
    for (uint32_t o = 0; o < outer && !pb->fused; o++) {
        uint32_t t = (outer - o) % 2, w = 1 - t;
        for (uint32_t i = 0; i < inner; i++) {
            cvk_pipeline_id first = pb->checking ? CVK_PIPE_GS_FIRST_CHECK : CVK_PIPE_GS_FIRST;
            if (folded && o == 0)
                first = t == 0 ? CVK_PIPE_GS_FIRST_PREDICT_SRC : CVK_PIPE_GS_FIRST_PREDICT_DST;
            for (uint32_t c = 0; c < b->colour_count; c++) {
                bool last = o + 1 == outer && i + 1 == inner;
                cvk_op* op = add_op(pb, i == 0 ? first : last ? last_sweep : CVK_PIPE_GS,
                                    set_for(t, w), pb->solve, b->colour_start[c],
                                    b->colour_start[c + 1] - b->colour_start[c], 1.0f,
                                    cvk_gs_sweep_omega(i, inner, outer, pb->base.omega));
                solve_note(pb, op, o, i, (int)c, set_for(t, w));
            }
            if (i == 0 && pb->checking)
                add_check(pb, o, t == 1, o * inner + 1);
        }
        add_after_outer(pb, b, set_for(t, w), o);
    }
    add_copy_back(pb, b);
    if ((!pb->fused && last_sweep == CVK_PIPE_GS) || grab_before_finalize(pb))
        add_finalize(pb, b); /* else in the last sweep or the last fused dispatch */
}

/* rbgs, its sweeps fused where pd_fused.c allows; --plan's solver line says which and why. */
static void plan_rbgs(pd_builder* pb)
{
    cvk_sim* s = pb->sim;
    const char* unfused = cvk_pd_plan_fuse_refusal(s, pb->solver);
    pb->fused = unfused == NULL;
    pb->copies = s->fused_copies;
    char* note = pb->plan->solver_note;
    size_t used = strlen(note);
    if (pb->fused)
        snprintf(note + used, sizeof pb->plan->solver_note - used,
                 ", sweeps fused (one dispatch for every outer iteration)");
    else
        snprintf(note + used, sizeof pb->plan->solver_note - used, ", sweeps not fused: %s",
                 unfused);
    plan_gauss_seidel(pb, &s->build);
}

/* Jacobi and Chebyshev: every sweep reads one buffer and writes the other. */
static void plan_jacobi(pd_builder* pb, const cvk_build* b, double rho, bool chebyshev)
{
    const cvk_solver_desc* solver = pb->solver;
    uint32_t sweeps = solver->outer_iterations * solver->inner_iterations;
    uint32_t cycle = cvk_sweep_cycle(solver);
    add_predict(pb, b, sweeps % 2);
    for (uint32_t s = 0; s < sweeps; s++) {
        uint32_t src = (sweeps - s) % 2, dst = 1 - src;
        uint32_t inner = s % solver->inner_iterations;
        double cheb = chebyshev ? cvk_chebyshev_weight(s % cycle, solver->chebyshev_delay, rho)
                                : 1.0;
        float omega = cvk_jacobi_sweep_omega(s % cycle, cycle, solver->omega);
        uint32_t outer = s / solver->inner_iterations;
        bool check = inner == 0 && pb->checking;
        cvk_op* op = add_op(pb, check ? CVK_PIPE_JACOBI_FIRST_CHECK
                                      : inner == 0 ? CVK_PIPE_JACOBI_FIRST : CVK_PIPE_JACOBI,
                            set_for(src, dst), pb->solve, 0, b->free_count, (float)cheb, omega);
        solve_note(pb, op, outer, inner, -1, set_for(src, dst));
        if (check)
            add_check(pb, outer, src == 1, s + 1);
        if (inner + 1 == solver->inner_iterations)
            add_after_outer(pb, b, set_for(src, dst), outer);
    }
    add_copy_back(pb, b);
    add_finalize(pb, b);
}

/* Chebyshev's spectral radius is estimated once per omega: it depends only on the scene, h
   and omega, and costs a power iteration. */
static double chebyshev_rho(cvk_sim* s, cvk_pd* pd, const cvk_solver_desc* solver)
{
    double estimated = -1.0;
    if (solver->chebyshev_rho <= 0.0f) {
        if (pd->rho_estimate < 0.0 || pd->rho_omega != solver->omega) {
            pd->rho_estimate = cvk_estimate_jacobi_rho(&s->build, cvk_ref_params_of(&s->params).inv_h2,
                                                        solver->omega);
            pd->rho_omega = solver->omega;
        }
        estimated = pd->rho_estimate;
    }
    return cvk_pd_chebyshev_rho(solver, s->params.dt, &s->build, estimated,
                                &pd->chebyshev_rho_estimated);
}

static cvk_pd_push base_push(const cvk_sim* s, const cvk_solver_desc* solver)
{
    const cvk_step_params* scene = &s->params;
    double h = scene->dt;
    cvk_pd_push base = {0};
    base.stride = s->build.free_count;
    base.inv_h2 = (float)(1.0 / (h * h));
    base.max_u2 = (float)(CVK_DIVERGED_SPEED * h * CVK_DIVERGED_SPEED * h);
    base.omega = solver->omega;
    base.keep = scene->integrate ? 1.0f - scene->damping : 0.0f;
    for (int k = 0; k < 3; k++)
        base.gravity_h2[k] = scene->integrate ? (float)(scene->gravity[k] * h * h) : 0.0f;
    base.rest_rate = (float)cvk_ref_params_of(scene).rest_rate; /* solve_pd.h */
    return base;
}

/* Whether the solve checks its convergence on the device (a tolerance). */
static bool checks(const cvk_sim* s, const cvk_solver_desc* solver)
{
    return solver->tolerance > 0.0f && s->build.free_count > 0 &&
           solver->linear != CVK_LINEAR_GS_CPU;
}

const char* cvk_pd_plan_fuse_refusal(const cvk_sim* s, const cvk_solver_desc* requested)
{
    cvk_solver_desc solver = cvk_solver_desc_resolve(requested);
    return cvk_pd_fuse_refusal(&s->build, &solver, checks(s, &solver), s->fused_copies);
}

/* The checks' push data, and whether the plan checks at all: a tolerance, a device solver and
   free particles. */
static bool plan_checks(const cvk_sim* s, const cvk_solver_desc* solver, const cvk_plan* plan,
                        cvk_pd_converge_push* check)
{
    uint32_t nf = s->build.free_count;
    *check = (cvk_pd_converge_push){
        .stride = nf,
        .sweeps = solver->outer_iterations * solver->inner_iterations,
        .tol2 = (float)((double)solver->tolerance * solver->tolerance),
        .sweep_groups = cvk_plan_groups_of(plan, CVK_PIPE_GS, nf),
        .contact_groups = cvk_plan_walk_groups(plan, nf),
        .reduce_groups = cvk_plan_groups(plan, CVK_PD_PARTIALS),
    };
    return checks(s, solver);
}

cvk_result cvk_pd_add_passes(cvk_sim* s, void* self, const cvk_solver_desc* requested,
                             cvk_plan* plan, cvk_error* error)
{
    cvk_pd* pd = self;
    cvk_solver_desc resolved = cvk_solver_desc_resolve(requested); /* max_iterations: outer */
    const cvk_solver_desc* solver = &resolved;
    pd_builder pb = {.sim = s, .plan = plan, .pd = pd, .solver = solver,
                     .base = base_push(s, solver), .contact_set = s->collide->set,
                     .contact = s->collide->colliding,
                     .tethers = s->build.tether_anchor != NULL};
    pb.checking = plan_checks(s, solver, plan, &pb.check);
    if (pb.checking)
        pb.base.rest_rate = 0.0f; /* no rest memory in checked solves (solve_pd.h) */
    pb.predict = cvk_plan_pass(plan, "predict");
    if (s->grab->planned && solver->linear != CVK_LINEAR_GS_CPU)
        cvk_plan_pass(plan, "grab"); /* listed after predict, where it first runs */
    pb.solve = cvk_plan_pass(plan, "solve");
    if (solver->strain_limit > 0.0f)
        pb.strain_pass = cvk_plan_pass(plan, "strain limit");
    plan_tethers(s, &pb);
    if (pb.contact)
        pb.contact_pass = cvk_plan_pass(plan, "contact");
    pb.finalize = cvk_plan_pass(plan, "finalize");
    if (pb.checking) {
        /* The frame's count starts at its first substep, first of all: only the frame's
           opening barrier (which covers transfers) is before it. */
        pb.check_pass = cvk_plan_pass(plan, "convergence");
        cvk_op* reset = cvk_plan_fill(plan, pb.check_pass, pd->scalars.buffer,
                                      offsetof(cvk_pd_scalars, frame_iterations), 4, 0);
        if (reset) {
            reset->every = s->params.substeps;
            snprintf(reset->note, sizeof reset->note, "the frame's sweep count = 0");
        }
    }
    pd->chebyshev_rho = pd->chebyshev_rho_estimated = 0.0;
    if (solver->linear != CVK_LINEAR_GS_CPU) {
        cvk_result r = cvk_attach_add_passes(s, plan, error);
        if (r == CVK_SUCCESS)
            r = cvk_aero_add_passes(s, plan, error);
        if (r != CVK_SUCCESS)
            return r;
    }
    if (pb.checking)
        snprintf(plan->solver_note, sizeof plan->solver_note,
                 ", tolerance %g (checked on the device), "
                 "at most %u sweeps", solver->tolerance, pb.check.sweeps);
    switch (solver->linear) {
    case CVK_LINEAR_RBGS:
        plan_rbgs(&pb);
        break;
    case CVK_LINEAR_CHEBYSHEV:
        pd->chebyshev_rho = chebyshev_rho(s, pd, solver);
        size_t used = strlen(plan->solver_note);
        snprintf(plan->solver_note + used, sizeof plan->solver_note - used,
                 ", rho %.6f (estimated %.6f, capped for stability), delay %u", pd->chebyshev_rho,
                 pd->chebyshev_rho_estimated, solver->chebyshev_delay);
        plan_jacobi(&pb, &s->build, pd->chebyshev_rho, true);
        break;
    case CVK_LINEAR_JACOBI:
        plan_jacobi(&pb, &s->build, 0.0, false);
        break;
    case CVK_LINEAR_CG: /* the implicit family's (scene validation keeps it there) */
        break;
    case CVK_LINEAR_GS_CPU:
        plan->host = true; /* no dispatches */
        snprintf(plan->host_note, sizeof plan->host_note,
                 "%u substeps on the host (sequential double-precision Gauss-Seidel, colour "
                 "order), then one upload of the positions", s->params.substeps);
        break;
    }
    if (solver->linear != CVK_LINEAR_GS_CPU) {
        cvk_result r = cvk_tear_add_passes(s, CVK_TEAR_FOR_PD, plan, error); /* after finalize */
        if (r != CVK_SUCCESS)
            return r;
    } else if (s->tear->count > 0) {
        cvk_plan_pass(plan, "tear"); /* timed on the host (cvk_tear_host) */
    }
    return cvk_plan_check(plan, error);
}
