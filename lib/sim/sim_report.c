/* What a simulation reports: timings and statistics, and the printed plan (--plan). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "topology/metrics.h"
#include "scene/scene.h"
#include "sim/sim.h"
#include "solvers/solve_implicit.h"
#include "solvers/solve_pd.h"

/* ---- statistics ------------------------------------------------------------------------ */

static void read_gpu_times(const cvk_sim* s, cvk_sim_stats* st)
{
    st->gpu_ms_per_frame = -1.0;
    for (uint32_t p = 0; p < st->pass_count; p++)
        st->passes[p].gpu_ms = -1.0;
    if (s->plan.host) {
        if (!s->host_timed)
            return;
        st->gpu_ms_per_frame = 0.0;
        for (uint32_t p = 0; p < st->pass_count; p++) {
            st->passes[p].gpu_ms = s->host_pass_ms[p];
            st->gpu_ms_per_frame += s->host_pass_ms[p];
        }
        return;
    }
    if (!s->timing)
        return;
    uint64_t* data = calloc(2 * (size_t)s->query_count, sizeof(uint64_t));
    if (!data)
        return;
    VkResult vr = vkGetQueryPoolResults(s->device.context->device, s->queries, 0, s->query_count,
                                        2 * s->query_count * sizeof(uint64_t), data,
                                        2 * sizeof(uint64_t),
                                        VK_QUERY_RESULT_64_BIT |
                                            VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
    bool available = vr == VK_SUCCESS;
    for (uint32_t q = 0; q < s->query_count && available; q++)
        available = data[2 * q + 1] != 0;
    if (available) {
        uint32_t bits = s->device.context->timestamp_valid_bits;
        uint64_t mask = bits >= 64 ? UINT64_MAX : ((uint64_t)1 << bits) - 1;
        double period_ms = s->device.context->properties.limits.timestampPeriod * 1e-6;
        double per_pass[CVK_MAX_PASSES] = {0};
        for (uint32_t q = 1; q < s->query_count; q++)
            if (s->query_pass[q] < CVK_MAX_PASSES)
                per_pass[s->query_pass[q]] += (double)((data[2 * q] - data[2 * (q - 1)]) & mask) * period_ms;
        st->gpu_ms_per_frame =
            (double)((data[2 * (s->query_count - 1)] - data[0]) & mask) * period_ms;
        for (uint32_t p = 0; p < st->pass_count; p++)
            st->passes[p].gpu_ms = per_pass[p];
    }
    free(data);
}

void cvk_sim_get_timing(const cvk_sim* s, cvk_sim_stats* st)
{
    memset(st, 0, sizeof *st);
    const cvk_build* b = &s->build;
    st->particles = b->particle_count;
    st->pinned = b->particle_count - b->free_count;
    for (int t = 0; t < 3; t++)
        st->springs[t] = b->springs_by_type[t];
    st->colours = b->colour_count;
    st->frames = s->frames;
    /* At most CVK_MAX_PASSES: sim creation refuses a plan with more (cvk_plan_check). */
    st->pass_count = s->plan.pass_count;
    for (uint32_t p = 0; p < st->pass_count; p++) {
        st->passes[p].name = s->plan.pass_names[p];
        st->passes[p].dispatches = cvk_plan_frame_ops(&s->plan, p);
    }
    st->dispatches_per_substep = s->plan.op_count;
    st->dispatches_per_frame = cvk_plan_frame_ops(&s->plan, UINT32_MAX);
    read_gpu_times(s, st);
}

/* The spring and energy figures of `st` from the state in s->scratch, over the live springs. */
static cvk_result spring_stats(cvk_sim* s, const uint32_t* alive, cvk_sim_stats* st,
                               cvk_error* error)
{
    const cvk_build* b = &s->build;
    cvk_metrics m;
    cvk_metrics_compute_live(b, s->scratch, s->scratch_v,
                             s->params.integrate ? s->params.gravity : NULL, alive, &m);
    st->residual = m.residual[CVK_SPRING_STRUCTURAL];
    for (int t = 0; t < 3; t++)
        st->residual_per_type[t] = m.residual[t];
    st->residual_normalized = m.residual_normalized;
    st->max_stretch = m.max_stretch;
    if (!cvk_metrics_live_stretch_quantile(b, s->scratch, alive, 0.99, &st->p99_stretch))
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "out of host memory for the stretch percentile (%llu springs)",
                        (unsigned long long)b->springs_by_type[CVK_SPRING_STRUCTURAL]);
    st->nan_count = m.nan_count;
    st->kinetic_energy = m.kinetic;
    st->gravitational_energy = m.gravitational;
    st->elastic_energy = m.elastic;
    st->energy = m.kinetic + m.gravitational + m.elastic;
    return CVK_SUCCESS;
}

cvk_result cvk_sim_get_stats(cvk_sim* s, cvk_sim_stats* st, cvk_error* error)
{
    if (!s || !st)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_get_stats needs a simulation and an output struct");
    cvk_sim_get_timing(s, st);
    const cvk_build* b = &s->build;
    cvk_result r = cvk_sim_read_internal(s, error);
    if (r != CVK_SUCCESS)
        return r;
    uint32_t* alive = NULL; /* the spring flags, when springs can tear */
    if (s->tear->count > 0) {
        alive = malloc((size_t)b->spring_count * sizeof *alive);
        if (!alive)
            return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the spring flags");
        r = cvk_tear_read_flags(s, alive, error);
        for (uint32_t i = 0; r == CVK_SUCCESS && i < b->spring_count; i++)
            st->torn_springs += alive[i] == 0;
    }
    if (r == CVK_SUCCESS)
        r = spring_stats(s, alive, st, error);
    free(alive);
    if (r != CVK_SUCCESS)
        return r;
    cvk_sim_watch_stats(s, st);
    cvk_implicit_stats(s, st);
    cvk_pd_stats(s, st);
    return cvk_sim_contact_stats(s, s->scratch, st, error);
}

/* ---- notes ------------------------------------------------------------------------------- */

uint32_t cvk_sim_note_count(const cvk_sim* s)
{
    return s ? s->note_count : 0;
}

const char* cvk_sim_note(const cvk_sim* s, uint32_t index)
{
    return s && index < s->note_count ? s->notes[index] : NULL;
}

/* ---- the printed plan ------------------------------------------------------------------ */

typedef struct text {
    char* at;
    size_t left;
    size_t needed;
} text;

static void put(text* t, const char* format, ...) __attribute__((format(printf, 2, 3)));
static void put(text* t, const char* format, ...)
{
    va_list args;
    va_start(args, format);
    int n = vsnprintf(t->at, t->left, format, args);
    va_end(args);
    if (n < 0)
        return;
    t->needed += (size_t)n;
    size_t used = (size_t)n < t->left ? (size_t)n : (t->left ? t->left - 1 : 0);
    t->at += used;
    t->left -= used;
}

/* One op: its pass, kind, what it runs, the family's note, its extent and its barrier. */
static void put_op(text* t, const cvk_plan* plan, const cvk_op* op)
{
    put(t, "  %-8s %-8s ", plan->pass_names[op->pass], cvk_op_kind_name(op->kind));
    switch (op->kind) {
    case CVK_OP_DISPATCH:
        put(t, "%-26s %s %u..%u, %u groups, %s", cvk_pipeline_label(op->pipeline),
            cvk_domain_name(op->domain), op->first, op->first + op->count - 1, op->groups,
            op->note);
        break;
    case CVK_OP_DISPATCH_INDIRECT:
        put(t, "%-26s %s, groups from the device (offset %llu), %s",
            cvk_pipeline_label(op->pipeline), cvk_domain_name(op->domain),
            (unsigned long long)op->offset, op->note);
        break;
    case CVK_OP_FILL:
        put(t, "%llu bytes at %llu = 0x%08x %s", (unsigned long long)op->size,
            (unsigned long long)op->offset, op->value, op->note);
        break;
    case CVK_OP_COPY:
        put(t, "%llu bytes from %llu to %llu %s", (unsigned long long)op->size,
            (unsigned long long)op->src_offset, (unsigned long long)op->offset, op->note);
        break;
    }
    put(t, "; then %s", cvk_barrier_name(op->barrier));
    if (op->every > 1)
        put(t, " (every %u substeps)", op->every);
    put(t, "\n");
}

/* The copies of an "instances" block: what each holds, and where. */
static void put_instances(text* t, const cvk_sim* s)
{
    uint32_t n = s->instance_count;
    if (n < 2)
        return;
    const cvk_build* b = &s->build;
    uint32_t cloths = b->cloth_count / n, colliders = s->collide->collider_count / n;
    const float* o = s->instance_offset1;
    put(t, "instances: %u copies of %u cloth%s (%u particles) and %u collider%s, "
        "stepped together in the dispatches below; copy k: cloths %u k.., particles %u k.. "
        "(output order), ", n, cloths,
        cloths == 1 ? "" : "s", b->particle_count / n, colliders, colliders == 1 ? "" : "s",
        cloths, b->particle_count / n);
    if (s->instances_listed)
        put(t, "offsets listed (copy 1 at [%g, %g, %g] m)\n", o[0], o[1], o[2]);
    else
        put(t, "offset k x [%g, %g, %g] m\n", o[0], o[1], o[2]);
}

/* "; detections asked for by moves at substeps N, 2N, 3N, ... only" where
   collision.detection_interval N holds them back, else "". */
typedef struct note_text {
    char text[112];
} note_text;
static note_text interval_note(const cvk_collide* c)
{
    note_text n = {""};
    uint32_t k = c->detection_interval;
    if (k > 1)
        snprintf(n.text, sizeof n.text,
                 "; detections asked for by moves at substeps %u, %u, %u, ... only", k, 2 * k,
                 3 * k);
    return n;
}

static void put_header(text* t, const cvk_sim* s)
{
    const cvk_build* b = &s->build;
    put(t, "scene %s: %u particles (%u pinned), springs: %llu structural, %llu shear, %llu bend\n",
        s->name, b->particle_count, b->particle_count - b->free_count,
        (unsigned long long)b->springs_by_type[0], (unsigned long long)b->springs_by_type[1],
        (unsigned long long)b->springs_by_type[2]);
    put(t, "colours: %u (%s), sizes", b->colour_count,
        b->colour_count == 2 ? "red-black" : "multi-colour");
    for (uint32_t c = 0; c < b->colour_count; c++)
        put(t, " %u", b->colour_start[c + 1] - b->colour_start[c]);
    if (s->solver.method == CVK_METHOD_IMPLICIT) /* its settings are in the family's note */
        put(t, "\nsolver: %s / %s%s\n", cvk_method_name(s->solver.method),
            cvk_linear_solver_name(s->solver.linear), s->plan.solver_note);
    else if (s->solver.method == CVK_METHOD_EXPLICIT) /* no linear solver; settings in the note */
        put(t, "\nsolver: %s%s\n", cvk_method_name(s->solver.method), s->plan.solver_note);
    else
        put(t, "\nsolver: %s / %s, %u outer x %u inner, omega %g%s\n",
            cvk_method_name(s->solver.method), cvk_linear_solver_name(s->solver.linear),
            s->solver.outer_iterations, s->solver.inner_iterations, s->solver.omega,
            s->plan.solver_note);
    const cvk_collide* c = s->collide;
    if (c->colliding) {
        put(t, "collision: thickness %.4g m, friction %g (static %g), self-contact %s",
            c->thickness, c->friction, c->static_friction,
            c->self ? "on" : "off");
        if (c->self)
            put(t, " (contact radius %.4g m, bounds %.2g of the nearest distance%s)",
                (double)c->radius, (double)CVK_BOUND_GAMMA, interval_note(c).text);
        put(t, ", %u colliders", c->collider_count);
        if (c->instance_count > 1)
            put(t, " (%u a copy, each particle testing its copy's)", c->instance_colliders);
        if (c->collider_count > CVK_UNIFORM_COLLIDERS)
            put(t, " read from storage buffers");
        for (uint32_t i = 0; i < c->instance_colliders; i++) /* one copy's */
            put(t, "%s%s%s", i ? ", " : ": ", cvk_collider_type_name(c->colliders[i].type),
                c->colliders[i].motion.keyframe_count ? " (moving)" : "");
        put(t, "\n");
    }
    put_instances(t, s);
}

size_t cvk_sim_describe_plan(const cvk_sim* s, char* out, size_t capacity)
{
    char dummy[1];
    text t = {capacity ? out : dummy, capacity ? capacity : 1, 0};
    const cvk_plan* plan = &s->plan;
    put_header(&t, s);
    if (plan->host) {
        put(&t, "per frame: %s\n", plan->host_note);
        return t.needed;
    }
    /* Only dispatches so far: "dispatches"; with fills or copies, "operations". */
    const char* kind = plan->has_transfer ? "operations" : "dispatches";
    uint32_t all = cvk_plan_frame_ops(plan, UINT32_MAX);
    const char* one = plan->has_transfer ? "operation" : "dispatch";
    put(&t, "per frame: %u substeps x %u %s ", plan->substeps, plan->op_count,
        plan->op_count == 1 ? one : kind);
    if (all == plan->substeps * plan->op_count)
        put(&t, "= %u %s", all, kind);
    else
        put(&t, "less those run every few substeps only = %u %s", all, kind);
    put(&t, ", workgroup size %u", plan->workgroup_size);
    if (plan->particle_workgroup_size != plan->workgroup_size)
        put(&t, " (%u for the passes over particles)", plan->particle_workgroup_size);
    put(&t, ", at most %u workgroups per dispatch", plan->max_groups);
    if (plan->particle_group_items > 1)
        put(&t, " (over particles, one per %u)", plan->particle_group_items);
    if (plan->walk_items > 1)
        put(&t, ", %u items an invocation in detection and contact", plan->walk_items);
    put(&t, "%s\n", s->timing ? ", timestamps per pass" : "");
    put(&t, "per substep:\n");
    for (uint32_t i = 0; i < plan->op_count; i++)
        put_op(&t, plan, &plan->ops[i]);
    return t.needed;
}
