/* The divergence watch: the device records the first substep at which a particle's position
   stopped being finite or it ran away (shaders/solvers/finalize.comp, shaders/shared/layout.h); the
   host reads the record after the fence it waits on anyway. */
#include <string.h>

#include "core/error.h"
#include "shared/layout.h"
#include "sim/sim.h"

cvk_result cvk_sim_watch_create(cvk_sim* s, cvk_error* error)
{
    cvk_result r = cvk_buffer_create(s->device.context, sizeof(cvk_gpu_watch),
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     CVK_MEMORY_HOST,
                                     "divergence watch", &s->watch, error);
    if (r == CVK_SUCCESS)
        cvk_sim_watch_reset(s);
    return r;
}

void cvk_sim_watch_reset(cvk_sim* s)
{
    cvk_gpu_watch fresh = {.substep = 0, .diverged_at = CVK_WATCH_NONE,
                           .particle = CVK_WATCH_NONE, .reason = 0, .stretched = 0,
                           .contact_cut = 0, .sweeps_cut = 0};
    if (s->watch.mapped)
        memcpy(s->watch.mapped, &fresh, sizeof fresh);
    s->watch_frames = s->frames;
}

/* One copy of the mapped record, read once per query (with no mapping: no divergence, no cut). */
static cvk_gpu_watch read_watch(const cvk_sim* s)
{
    cvk_gpu_watch w = {.diverged_at = CVK_WATCH_NONE, .particle = CVK_WATCH_NONE};
    if (s->watch.mapped)
        memcpy(&w, s->watch.mapped, sizeof w);
    return w;
}

static void watch_stats(const cvk_sim* s, const cvk_gpu_watch* w, cvk_sim_stats* st)
{
    st->diverged = w->diverged_at != CVK_WATCH_NONE && w->particle < s->build.particle_count;
    if (!st->diverged)
        return;
    st->diverged_frame = s->watch_frames + (w->diverged_at - 1u) / s->params.substeps;
    st->diverged_cloth = cvk_build_cloth_of(&s->build, w->particle);
    st->diverged_nonfinite = (w->reason & CVK_WATCH_NONFINITE) != 0;
}

void cvk_sim_watch_stats(const cvk_sim* s, cvk_sim_stats* st)
{
    cvk_gpu_watch w = read_watch(s);
    watch_stats(s, &w, st);
}

/* A pass whose loops the device ended early (shaders/contact/bounds.glsl, loops_cut): `what`
   names it, `then` says what followed and what avoids it. */
static cvk_result loops_cut(const cvk_sim* s, const char* what, const char* then,
                            cvk_error* error)
{
    return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                    "%s cut short by frame %llu: %s ends a shader's loops after a fixed number of "
                    "iterations (lavapipe: 65,535 an invocation)%s", what,
                    (unsigned long long)s->frames, s->device.context->properties.deviceName, then);
}

cvk_result cvk_sim_watch_check(const cvk_sim* s, cvk_error* error)
{
    cvk_gpu_watch w = read_watch(s);
    cvk_sim_stats st = {0};
    watch_stats(s, &w, &st);
    /* Both flags are cleared with the watch (and the frame state's) when a state is written. */
    if (w.contact_cut)
        return loops_cut(s, "contact detection was",
                         " and the cloths lie too crowded for it, so pairs were missed and the "
                         "guarantee that no cloth passes through cloth no longer holds; a larger "
                         "cvk_sim_desc.max_workgroups (clothvk-sim --max-workgroups 65535) gives "
                         "detection one item an invocation", error);
    if (w.sweeps_cut)
        return loops_cut(s, "the fused sweeps were",
                         ", and an invocation's share of the sweeps (a colour's particles over "
                         "the workgroup size, times the colours and sweeps of a substep) passed "
                         "it, so particles were left unswept; a larger workgroup size (or the "
                         "library's choice, 0) or solver.fuse off avoids it", error);
    if (!st.diverged)
        return CVK_SUCCESS;
    const char* why = st.diverged_nonfinite
                          ? "a particle's position became NaN or infinite"
                          : "a particle moved faster than 10000 m/s or a spring stretched "
                            "past ten times its rest length";
    return cvk_fail(error, CVK_ERROR_DIVERGED,
                    "the simulation diverged in frame %llu: %s in cloth %u (\"%s\"); positions "
                    "stopped advancing there (a smaller dt, more substeps or "
                    "iterations, or softer springs)",
                    (unsigned long long)st.diverged_frame, why, st.diverged_cloth,
                    s->build.cloths[st.diverged_cloth].name);
}
