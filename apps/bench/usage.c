/* clothvk-bench --help: the experiments and their options. */
#include <stdio.h>

#include "bench.h"

/* The experiments, the options of all, and those of the frozen-substep and Pareto ones. */
static void usage_first(FILE* out)
{
    fprintf(out,
        "usage: clothvk-bench EXPERIMENT [SCENE] [options] [-o DIR]\n"
        "Writes DIR/EXPERIMENT.csv, DIR/EXPERIMENT.png (and the gnuplot script EXPERIMENT.gp)\n"
        "and prints a summary with the device it ran on. --version prints the version.\n"
        "experiments:\n"
        "  convergence SCENE  residual and solve error against iterations on one frozen substep\n"
        "  budget SCENE       iterations, residual and solve error within GPU-time budgets\n"
        "  pareto SCENE       error against GPU time per frame over solver x iterations x substeps\n"
        "  stability SCENE    stable region over h x stiffness (x damping), largest stable h, extremes\n"
        "  scaling [SCENE]    ms per frame and per pass against particle and iteration counts\n"
        "  collide            spatial hash build and neighbour query: ms per pass against points\n"
        "  contact-steps SCENE  penetration and intersecting pairs against the time step\n"
        "  explicit-stability SCENE  seed 001 §3: largest stable kd and h of the explicit\n"
        "                      integrators, measured and predicted from the stiffest mode\n"
        "  contact-ensemble [SCENE]  intersecting cloth triangle pairs after every frame of\n"
        "                      each scene with self-contact x 9 variants of its settings\n"
        "  batch [SCENE]       N copies of the scene (instances.count; default a 16 x 16\n"
        "                      napkin): ms per frame, steps and particle steps per second\n"
        "options (all experiments):\n"
        "  -o DIR              output folder, created if missing (default: .)\n"
        "  --set k=v           override a scene key by its dotted JSON path (repeatable)\n"
        "  --solvers LIST      NAME[:OMEGA],... of jacobi, chebyshev, rbgs, gs-cpu\n"
        "                      (scaling also: cg, implicit-jacobi: implicit Euler, --iterations\n"
        "                      CG iterations or Jacobi sweeps per step, all run)\n"
        "  --inner N           linear sweeps per local step (default 1); iterations count sweeps\n"
        "  --repeat R          timed runs per point: median and min-max (default 3)\n"
        "  --warmup W          untimed runs before them (default 1)\n"
        "  --no-plot           write the CSV only\n"
        "convergence, budget:\n"
        "  --frame F           freeze the first substep of frame F (default 0 without integration,\n"
        "                      5 with), reached with the scene's own solver\n"
        "  --max-iterations K  convergence: iterations up to K (default 1000)\n"
        "  --ms LIST           budget: budgets in ms (default 1,2,4,8)\n"
        "  --reference-tolerance M, --reference-max-iterations K\n"
        "                      x*, the converged solution of the substep, by Newton's method:\n"
        "                      until a step is below M m (default 1e-10), K steps at most (200)\n"
        "pareto:\n"
        "  --iterations LIST   sweeps per substep (default 1,2,4,8,16,32)\n"
        "  --substeps LIST     substeps per frame (default 2,4,8); h = frame time / substeps\n"
        "  --time T            simulated seconds before the errors are taken (default 0.25)\n"
        "  --target E          name the cheapest setting within E m of the reference (default 1e-3)\n"
        "  --target-residual R the same for the residual, m^2 (default: twice the reference's)\n"
        "  --reference-tolerance M, --reference-max-iterations K  as for convergence (default\n"
        "                      1e-8 m, 200); the reference is the converged solve at h / 4\n"
        "  --stretch-bound S   settings that stretch a spring by more than S are unstable and on\n"
        "                      no front (default 10 = 1000%%)\n"
        "  --solvers           also cg and implicit-jacobi (implicit Euler: each --substeps x\n"
        "                      --tolerances, at most --max-iterations per substep, default 1000)\n"
        "                      and euler, rk2, adams-bashforth, verlet (explicit, the scene's\n"
        "                      solver.kd: each of --explicit-substeps, which they need)\n"
        "  --tolerances LIST   implicit: relative residuals where the solve stops (default\n"
        "                      0.01,0.001)\n"
        "  --explicit-substeps LIST  explicit: substeps per frame (1 to 10000)\n"
        "  --reference-substeps N  the reference's substeps per frame (default 4 x the largest\n"
        "                      of --substeps)\n");
}

void bench_usage(FILE* out)
{
    usage_first(out);
    fprintf(out,
        "stability:\n"
        "  --dt LIST           time steps, s (default 0.0005,0.001,0.002,0.004,0.008,0.016,0.0333333)\n"
        "  --stiffness LIST    structural N/m (default 1e3,1e4,1e5,1e6,1e7,1e8)\n"
        "  --damping LIST      (default 0)\n"
        "  --iterations LIST   sweeps per substep (default: the scene's outer x inner)\n"
        "  --time T            simulated seconds per run (default 0.5), at least --min-steps\n"
        "                      steps (default 50)\n"
        "  --energy-bound G    unstable when the energy grows by G energy scales (default 1)\n"
        "  --stretch-bound S   unstable when a spring stretches by S (default 10 = 1000%%)\n"
        "  --limit-ratio Q     bisection precision of the largest stable h (default 1.05)\n"
        "explicit-stability (also --time, default 1, --min-steps, --energy-bound,\n"
        "                    --stretch-bound, --limit-ratio (default 1.02) as for stability):\n"
        "  --kd KD             damping for the largest stable h, N s/m (default 10)\n"
        "scaling:\n");
    fprintf(out,
        "  --grids LIST        N for N x N grids (default 32,64,...,2048 and the largest that fits)\n"
        "  --iterations LIST   sweeps per substep (default 10,30,50,70)\n"
        "collide:\n"
        "  --points LIST       point counts (default 1000,10000,100000; 1000000 fits lavapipe)\n"
        "contact-ensemble (--set applies to every scene):\n"
        "  --scenes LIST       scene files a.json,b.json (default: SCENE, or the twelve showcases\n"
        "                      with contact under assets/scenes/, from the repository root)\n"
        "  --frames N          frames per run (default: each scene's own frame count)\n"
        "  --variants N        the first N variants of each scene (default: all 9)\n"
        "  --require-clean     exit 1 when any run had an intersecting pair or stopped early\n"
        "batch (--set applies to every count; --warmup frames before the timed ones):\n"
        "  --counts LIST       copies N (default 1,2,4,...,8192)\n"
        "  --frames F          timed frames per count (default 10)\n"
        "environment: CLOTHVK_DEVICE, CLOTHVK_VALIDATION=1, CLOTHVK_GNUPLOT, LP_NUM_THREADS (lavapipe)\n");
}
