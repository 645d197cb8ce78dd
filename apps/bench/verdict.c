/* The stability verdict: is a run still a cloth, or has it blown up? */
#include <math.h>

#include "bench.h"

/* Steps between two looks at a running simulation: each look reads the state back. */
#define CHECK_EVERY 10u

const char* bench_verdict_name(bench_verdict v)
{
    switch (v) {
    case BENCH_STABLE: return "stable";
    case BENCH_NAN: return "nan";
    case BENCH_ENERGY: return "energy";
    case BENCH_STRETCH: return "stretch";
    case BENCH_DIVERGED: return "diverged";
    }
    return "?";
}

/* Kinetic plus gravitational: the energy a stable run may not gain. The elastic part is left
   out because a truncated solve holds springs at stretches its nominal stiffness never would:
   hanging.json on 16 x 16 with rbgs 4 x 4 at k = 1e6 stretches 4.7%, which counts as 60 J of
   spring energy against the 0.5 J its fall releases. That cloth is rubbery, not exploding;
   an exploding one turns its springs into motion, and the motion is what is watched. */
static double mechanical(const cvk_sim_stats* st)
{
    return st->kinetic_energy + st->gravitational_energy;
}

bench_watch bench_watch_start(const cvk_sim_stats* start, double total_mass, const float gravity[3],
                              double extent)
{
    double g = 0.0;
    if (gravity)
        g = sqrt((double)gravity[0] * gravity[0] + (double)gravity[1] * gravity[1] +
                 (double)gravity[2] * gravity[2]);
    /* What the cloth may turn into motion: the springs' energy at the start (a pin moved far
       away releases it), what it moves with, and lifting it by its own extent under (at
       least) Earth's gravity, so a resting cloth without gravity has a scale too. */
    double scale = fabs(start->kinetic_energy) + fabs(start->elastic_energy) +
                   total_mass * fmax(g, 9.81) * extent;
    return (bench_watch){
        .energy0 = mechanical(start),
        .scale = scale > 0.0 ? scale : 1.0,
        .stretch0 = isfinite(start->max_stretch) ? start->max_stretch : 0.0,
    };
}

bench_verdict bench_classify(const bench_watch* w, const cvk_sim_stats* now, double energy_bound,
                             double stretch_bound, double* growth)
{
    *growth = (mechanical(now) - w->energy0) / w->scale;
    if (now->diverged)
        return now->diverged_nonfinite ? BENCH_NAN : BENCH_DIVERGED;
    if (now->nan_count > 0 || !isfinite(now->energy) || !isfinite(now->max_stretch))
        return BENCH_NAN;
    if (*growth > energy_bound)
        return BENCH_ENERGY;
    if (now->max_stretch > fmax(stretch_bound, w->stretch0))
        return BENCH_STRETCH;
    return BENCH_STABLE;
}

static void scene_mass_and_extent(const cvk_scene_desc* scene, double* mass, double* extent)
{
    *mass = 0.0;
    *extent = 0.0;
    for (uint32_t c = 0; c < scene->cloth_count; c++) {
        const cvk_cloth_desc* cloth = &scene->cloths[c];
        *mass += cloth->mass;
        *extent = fmax(*extent, hypot(cloth->size[0], cloth->size[1]));
    }
}

bool bench_run_stability(cvk_sim* sim, const cvk_scene_desc* scene, uint64_t steps,
                         double energy_bound, double stretch_bound, bench_stability_run* out,
                         cvk_error* error)
{
    cvk_sim_stats st;
    if (cvk_sim_get_stats(sim, &st, error) != CVK_SUCCESS)
        return false;
    double mass, extent;
    scene_mass_and_extent(scene, &mass, &extent);
    bench_watch w = bench_watch_start(&st, mass, scene->integrate ? scene->gravity : NULL, extent);
    *out = (bench_stability_run){.verdict = BENCH_STABLE, .max_stretch = st.max_stretch};
    uint64_t per_frame = scene->substeps;
    while (out->steps_done < steps) {
        uint64_t frames = (steps - out->steps_done + per_frame - 1) / per_frame;
        if (frames > CHECK_EVERY)
            frames = CHECK_EVERY;
        /* A divergence the library's watch found is a verdict, read from the statistics. */
        cvk_result r = cvk_sim_step(sim, (uint32_t)frames, error);
        if ((r != CVK_SUCCESS && r != CVK_ERROR_DIVERGED) ||
            cvk_sim_get_stats(sim, &st, error) != CVK_SUCCESS)
            return false;
        out->steps_done += frames * per_frame;
        out->verdict = bench_classify(&w, &st, energy_bound, stretch_bound, &out->growth);
        out->max_stretch = st.max_stretch;
        out->nan_count = st.nan_count;
        if (out->verdict != BENCH_STABLE)
            break;
    }
    return true;
}
