#!/usr/bin/env python3
"""Large steps: hanging.json's cloth at N x N, h = 1/30 s, one substep per frame, implicit Euler
with CG to 1e-3 ("cg MAX_ITERATIONS"), or PD rbgs 4 x 4 at SUBSTEPS substeps of 1/30/SUBSTEPS s
("pd SUBSTEPS"); prints one JSON line: NaN count, breakdowns, the largest stretch and energy seen
(statistics read every 10 frames and every frame of the first 100), and the end state.

    PYTHONPATH=python python3 scripts/large-steps.py FRAMES GRID cg|pd N
"""
import json
import sys
import time

import clothvk


def main():
    frames, grid, method, n = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
    overrides = {"dt": 1 / 30, "substeps": 1, "cloths.0.grid": [grid, grid],
                 "cloths.0.pins": [[0, 0], [grid - 1, 0]]}
    if method == "cg":
        overrides.update({"solver.method": "implicit", "solver.linear": "cg",
                          "solver.tolerance": 1e-3, "solver.max_iterations": n})
    else:
        overrides.update({"dt": 1 / 30 / n, "substeps": n})
    with clothvk.Context() as ctx:
        scene = clothvk.Scene.load("assets/scenes/hanging.json", overrides=overrides)
        sim = clothvk.Simulation(ctx, scene)
        start = sim.stats()["energy"]
        energy, stretch, nan, t0 = start, 0.0, 0, time.time()
        for f in range(frames):
            sim.step(1)
            if f % 10 == 9 or f < 100:
                st = sim.stats()
                energy = max(energy, st["energy"])
                stretch = max(stretch, st["max_stretch"])
                nan += st["nan_count"]
        st = sim.stats()
        print(json.dumps({
            "frames": frames, "grid": grid, "method": method, "energy_start": start,
            "energy_max": energy, "energy_end": st["energy"], "max_stretch_seen": stretch,
            "max_stretch_end": st["max_stretch"], "nan": nan,
            "iterations_per_substep": st["solver_iterations_total"] / max(1, frames),
            "breakdowns": st["solver_breakdowns"], "gpu_ms_per_frame": st["gpu_ms_per_frame"],
            "wall_s": time.time() - t0}))


if __name__ == "__main__":
    main()
