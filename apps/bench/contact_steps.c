/* contact-steps: how contact holds as the time step grows (seed 002 §9: its collisions failed
   at large steps). For each h of --dt the scene runs with one substep of h for --time seconds;
   after every step the deepest a particle is inside any collider and the number of
   intersecting cloth triangle pairs (exact, on the host) are measured, and their maxima over
   the run are reported with the end state's stretch and the GPU time per step. The largest h
   with no penetration beyond the thickness and no intersecting pair is the step the scene
   can take without tunnelling. An h at which the scene runs away is reported as such (the
   step it diverged at, the maxima until then) and the sweep goes on to the next h. */
#include <math.h>
#include <stdio.h>

#include "bench.h"
#include "plot.h"

static const char* const columns[] = {
    "dt", "steps", "max_penetration", "max_intersecting_pairs", "end_intersecting_pairs",
    "end_max_stretch", "nan", "diverged_step", "gpu_ms_per_step", "tunnelling_free",
};

typedef struct outcome {
    double penetration, stretch, gpu_ms;
    uint64_t pairs, end_pairs, nan;
    uint32_t steps;
    uint32_t diverged; /* the step (from 1) at which the scene ran away; 0: it did not */
} outcome;

static bool run_step(bench* b, double dt, outcome* out)
{
    cvk_scene_desc scene = *b->scene;
    scene.dt = (float)dt;
    scene.substeps = 1;
    cvk_sim* sim = bench_sim_create(b, &scene);
    if (!sim)
        return false;
    *out = (outcome){0};
    out->steps = (uint32_t)ceil(b->o->time / dt);
    cvk_error err;
    bool ok = true;
    for (uint32_t s = 0; ok && s < out->steps; s++) {
        cvk_sim_stats st;
        cvk_result r = cvk_sim_step(sim, 1, &err);
        if (r == CVK_ERROR_DIVERGED) {
            out->diverged = s + 1; /* not tunnelling-free; the next h is run all the same */
            break;
        }
        ok = r == CVK_SUCCESS && cvk_sim_get_stats(sim, &st, &err) == CVK_SUCCESS;
        if (!ok)
            break;
        out->penetration = fmax(out->penetration, st.max_penetration);
        out->pairs = st.intersecting_pairs > out->pairs ? st.intersecting_pairs : out->pairs;
        out->end_pairs = st.intersecting_pairs;
        out->stretch = st.max_stretch;
        out->nan = st.nan_count;
        out->gpu_ms += st.gpu_ms_per_frame;
    }
    if (!ok)
        bench_fail(&err);
    uint32_t timed = out->diverged ? out->diverged - 1 : out->steps;
    out->gpu_ms = timed ? out->gpu_ms / timed : NAN;
    cvk_sim_destroy(sim);
    return ok;
}

int bench_contact_steps(bench* b)
{
    bench_table_init(&b->table, columns, sizeof columns / sizeof columns[0]);
    if (b->scene->collider_count == 0 && !b->scene->collision.self) {
        fprintf(stderr, "clothvk-bench: contact-steps: %s has no colliders and no self-contact\n",
                b->scene_name);
        return APP_EXIT_BAD_INPUT;
    }
    printf("%s, one substep of h for %g s; maxima over the run\n%10s %6s %14s %10s %10s %9s %9s\n",
           b->scene_name, b->o->time, "h (s)", "steps", "penetration", "pairs max", "pairs end",
           "stretch", "ms/step");
    double largest = 0.0;
    for (uint32_t i = 0; i < b->o->dt_count; i++) {
        outcome o;
        if (!run_step(b, b->o->dts[i], &o))
            return APP_EXIT_FAILURE;
        bool clean = o.penetration <= 1e-4 && o.pairs == 0 && o.nan == 0 && !o.diverged;
        if (clean && b->o->dts[i] > largest)
            largest = b->o->dts[i];
        bench_table_row(&b->table);
        bench_table_num(&b->table, "dt", b->o->dts[i]);
        bench_table_int(&b->table, "steps", o.steps);
        bench_table_num(&b->table, "max_penetration", o.penetration);
        bench_table_int(&b->table, "max_intersecting_pairs", o.pairs);
        bench_table_int(&b->table, "end_intersecting_pairs", o.end_pairs);
        bench_table_num(&b->table, "end_max_stretch", o.stretch);
        bench_table_int(&b->table, "nan", o.nan);
        bench_table_int(&b->table, "diverged_step", o.diverged);
        bench_table_num(&b->table, "gpu_ms_per_step", o.gpu_ms);
        bench_table_int(&b->table, "tunnelling_free", clean ? 1 : 0);
        printf("%10.6f %6u %14.3g %10llu %10llu %9.3f %9.3f", b->o->dts[i], o.steps,
               o.penetration, (unsigned long long)o.pairs, (unsigned long long)o.end_pairs,
               o.stretch, o.gpu_ms);
        if (o.diverged)
            printf("  diverged at step %u (maxima until then)", o.diverged);
        printf("\n");
    }
    if (largest > 0.0)
        printf("largest h with no penetration (beyond 0.1 mm) and no intersecting pair: %g s\n",
               largest);
    else
        printf("no h tried was free of penetration and intersecting pairs\n");
    bench_plot_styles(&b->plot);
    bench_text_add(&b->plot,
                   "set title \"%s: contact against the time step, on %s\"\nset logscale x\n"
                   "set xlabel \"h (s), one substep\"\nset ylabel \"intersecting pairs (max)\"\n"
                   "set y2label \"deepest penetration (m)\"\nset y2tics\nset ytics nomirror\n"
                   "plot \"contact-steps.csv\" using \"dt\":\"max_intersecting_pairs\" with "
                   "linespoints linestyle 1 title \"intersecting pairs\", \\\n"
                   "     \"contact-steps.csv\" using \"dt\":\"max_penetration\" axes x1y2 with "
                   "linespoints linestyle 2 title \"penetration\"\n",
                   b->scene_name, b->device);
    return APP_EXIT_OK;
}
