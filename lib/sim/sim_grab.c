/* Dragging a particle, the public calls: cvk_sim_grab, cvk_sim_grab_within, cvk_sim_release
   (features/grab.h has the buffer and the pass they drive). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "features/grab.h"
#include "sim/sim.h"

cvk_result cvk_sim_particle_internal(const cvk_sim* s, cvk_particle particle, const char* call,
                                     uint32_t* out, cvk_error* error)
{
    const cvk_build* b = &s->build;
    if (particle.cloth >= b->cloth_count)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: cloth %u does not exist (the scene has %u cloth%s)", call,
                        particle.cloth, b->cloth_count, b->cloth_count == 1 ? "" : "s");
    const cvk_cloth_range* c = &b->cloths[particle.cloth];
    if (particle.index >= c->particle_count)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: particle %u of cloth %u (\"%s\") does not exist (it has %u)", call,
                        particle.index, particle.cloth, c->name, c->particle_count);
    *out = b->internal_of[c->first_user + particle.index];
    return CVK_SUCCESS;
}

/* The checks every grab call makes, and the grab pass added at the first: p is the grabbed
   particle's internal index. */
static cvk_result grab_start(cvk_sim* s, cvk_particle particle, const float target[3],
                             const char* call, uint32_t* p, cvk_error* error)
{
    *p = UINT32_MAX; /* no particle until the checks pass: *p is defined on every return */
    if (!s || !target)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s needs a simulation and a target",
                        call);
    const char* unsupported = cvk_grab_unsupported(&s->solver);
    if (unsupported)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "%s: %s cannot hold a grabbed particle; use the pd method with "
                        "rbgs, jacobi or chebyshev", call, unsupported);
    if (!isfinite(target[0]) || !isfinite(target[1]) || !isfinite(target[2]))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: the target must be finite, got [%g, %g, %g]", call,
                        (double)target[0], (double)target[1], (double)target[2]);
    cvk_result r = cvk_sim_particle_internal(s, particle, call, p, error);
    if (r != CVK_SUCCESS)
        return r;
    if (*p >= s->build.free_count)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: particle %u of cloth %u (\"%s\") is pinned; only free "
                        "particles can be grabbed", call, particle.index, particle.cloth,
                        s->build.cloths[particle.cloth].name);
    if (!s->grab->planned) {
        r = cvk_grab_enable(s, error);
        if (r == CVK_SUCCESS)
            r = cvk_sim_replan(s, error);
        if (r != CVK_SUCCESS) {
            if (cvk_plan_find_pass(&s->plan, "grab") == UINT32_MAX)
                cvk_grab_destroy(s); /* the old plan was kept: nothing uses the pass's set */
            return r;
        }
    }
    return CVK_SUCCESS;
}

/* Writes the header of the grab buffer (its members are already in place). */
static void grab_write(cvk_sim* s, const float target[3])
{
    cvk_grab* g = s->grab;
    cvk_gpu_grab grab = {{target[0], target[1], target[2], 0.0f}, g->particle, 1u, g->count, 0};
    memcpy(g->state.mapped, &grab, sizeof grab);
}

static float* grab_members(cvk_sim* s)
{
    return (float*)((unsigned char*)s->grab->state.mapped + sizeof(cvk_gpu_grab));
}

static void set_member(float* member, const float offset[3], uint32_t particle)
{
    memcpy(member, offset, 3 * sizeof(float));
    memcpy(member + 3, &particle, sizeof particle); /* the index as float bits */
}

cvk_result cvk_sim_grab(cvk_sim* s, cvk_particle particle, const float target[3],
                        cvk_error* error)
{
    uint32_t p;
    cvk_result r = grab_start(s, particle, target, "cvk_sim_grab", &p, error);
    if (r != CVK_SUCCESS)
        return r;
    const float zero[3] = {0.0f, 0.0f, 0.0f};
    set_member(grab_members(s), zero, p);
    cvk_grab* g = s->grab;
    g->held = true;
    g->particle = p;
    g->radius = 0.0f;
    g->count = 1;
    grab_write(s, target);
    return CVK_SUCCESS;
}

typedef struct grab_candidate {
    float distance;
    uint32_t user; /* user index: ties go to the smaller */
    uint32_t internal;
} grab_candidate;

static int compare_candidates(const void* a, const void* b)
{
    const grab_candidate *x = a, *y = b;
    if (x->distance != y->distance)
        return x->distance < y->distance ? -1 : 1;
    return (x->user > y->user) - (x->user < y->user);
}

cvk_result cvk_sim_grab_within(cvk_sim* s, cvk_particle particle, float radius,
                               const float target[3], cvk_error* error)
{
    static const char call[] = "cvk_sim_grab_within";
    if (!(radius >= 0.0f) || !isfinite(radius))
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: the radius must be a finite number of metres, at least 0; got %g",
                        call, (double)radius);
    uint32_t p;
    cvk_result r = grab_start(s, particle, target, call, &p, error);
    if (r != CVK_SUCCESS)
        return r;
    cvk_grab* g = s->grab;
    if (g->held && g->particle == p && g->radius == radius) {
        grab_write(s, target); /* the same hand: it only moves */
        return CVK_SUCCESS;
    }
    /* A new hand: the free particles of the cloth within the radius, where they are now. */
    r = cvk_sim_read_internal(s, error);
    if (r != CVK_SUCCESS)
        return r;
    const cvk_build* b = &s->build;
    const cvk_cloth_range* c = &b->cloths[particle.cloth];
    grab_candidate* found = malloc((size_t)c->particle_count * sizeof *found);
    if (!found)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "%s: out of host memory", call);
    const float* xp = s->scratch + 3 * (size_t)p;
    uint32_t n = 0;
    for (uint32_t k = 0; k < c->particle_count; k++) {
        uint32_t q = b->internal_of[c->first_user + k];
        if (q >= b->free_count || q == p)
            continue; /* pinned, or the grabbed particle itself (member 0) */
        const float* xq = s->scratch + 3 * (size_t)q;
        float d[3] = {xq[0] - xp[0], xq[1] - xp[1], xq[2] - xp[2]};
        float distance = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (distance <= radius)
            found[n++] = (grab_candidate){distance, c->first_user + k, q};
    }
    qsort(found, n, sizeof *found, compare_candidates);
    float* members = grab_members(s);
    const float zero[3] = {0.0f, 0.0f, 0.0f};
    set_member(members, zero, p);
    uint32_t count = 1;
    for (uint32_t i = 0; i < n && count < CVK_GRAB_MAX; i++, count++) {
        const float* xq = s->scratch + 3 * (size_t)found[i].internal;
        const float offset[3] = {xq[0] - xp[0], xq[1] - xp[1], xq[2] - xp[2]};
        set_member(members + 4 * count, offset, found[i].internal);
    }
    free(found);
    g->held = true;
    g->particle = p;
    g->radius = radius;
    g->count = count;
    grab_write(s, target);
    return CVK_SUCCESS;
}

void cvk_sim_release(cvk_sim* s)
{
    if (!s || !s->grab->planned)
        return;
    memset(s->grab->state.mapped, 0, sizeof(cvk_gpu_grab));
    s->grab->held = false;
}
