#!/usr/bin/env python3
"""clothvk-bench as a person meets it: every experiment on a tiny grid, and bad input.

    python3 tests/tools/test_bench.py PATH/TO/clothvk-bench

Each run has a fresh temporary directory as its working directory and writes into -o out
(created by the tool). A good case must exit with status 0, say on its first line which
device it ran on, write out/EXPERIMENT.csv with exactly the expected columns and finite
numbers where numbers belong, and (when gnuplot is installed) out/EXPERIMENT.png, a PNG, and
the gnuplot script out/EXPERIMENT.gp. A bad-input case must exit with status 2, print exactly
one line on stderr (compared whole), nothing on stdout, and leave the directory as it was.
"""
import csv
import math
import os
import shutil
import sys
import tempfile

import tooltest

[BENCH] = tooltest.tool_paths("clothvk-bench")
ROOT = tooltest.ROOT
HAS_GNUPLOT = shutil.which("gnuplot") is not None


def asset(name):
    return os.path.join(ROOT, "assets", "scenes", name)


HANGING = asset("hanging.json")
ENLARGED = asset("enlarged.json")
# Tiny versions of the seed's two scenes; hanging keeps its two pinned corners.
TINY_ENLARGED = [ENLARGED, "--set", "cloths.0.grid=[8,8]"]
TINY_HANGING = [HANGING, "--set", "cloths.0.grid=[8,8]", "--set", "cloths.0.pins=[[0,0],[7,0]]"]
QUICK = ["--repeat", "1", "--warmup", "0"]

COLUMNS = {
    "convergence": ["label", "solver", "omega", "iterations", "outer", "inner", "residual",
                    "residual_relative", "solve_error", "distance_rms", "nan_count", "solve_ms",
                    "solve_ms_min", "solve_ms_max", "ms_per_iteration", "device"],
    "budget": ["label", "solver", "omega", "budget_ms", "iterations", "outer", "inner", "solve_ms",
               "solve_ms_min", "solve_ms_max", "fits", "residual", "residual_relative",
               "solve_error", "ms_per_iteration", "overhead_ms", "seed_002_gtx970", "device"],
    "pareto": ["label", "method", "solver", "omega", "tolerance", "substeps", "dt", "iterations",
               "outer", "inner", "frames", "time_s", "frame_ms", "frame_ms_min", "frame_ms_max", "residual",
               "trajectory_error", "max_stretch", "nan_count", "stable", "front_residual",
               "front_trajectory", "device"],
    "stability": ["kind", "case", "label", "solver", "omega", "iterations", "outer", "inner", "dt",
                  "dt_unstable", "substeps", "stiffness", "damping", "steps", "stable", "reason",
                  "failed_at_step", "max_stretch", "energy_growth", "nan_count", "device"],
    "scaling": ["label", "solver", "omega", "grid", "particles", "iterations", "outer", "inner",
                "substeps", "frame_ms", "frame_ms_min", "frame_ms_max", "predict_ms", "solve_ms",
                "finalize_ms", "colliders_ms", "hash_ms", "contacts_ms", "contact_ms", "ms_per_iteration", "ns_per_particle_iteration", "fps", "wall_ms",
                "dispatches_per_frame", "device"],
    "collide": ["points", "cell_size", "table_size", "clear_ms", "count_ms", "chunk_sums_ms",
                "scan_chunks_ms", "scan_ms", "scatter_ms", "hash_ms", "neighbours_ms",
                "total_ms", "total_ms_min", "total_ms_max", "ns_per_point", "neighbours_per_point",
                "dispatches", "device"],
    "contact-steps": ["dt", "steps", "max_penetration", "max_intersecting_pairs",
                      "end_intersecting_pairs", "end_max_stretch", "nan", "diverged_step",
                      "gpu_ms_per_step", "tunnelling_free", "device"],
    "explicit-stability": ["measure", "integrator", "damping_model", "dt", "kd", "measured",
                           "unstable_at", "predicted", "measured_over_predicted", "seed",
                           "lambda_d", "lambda_k", "runs", "steps", "device"],
    "contact-ensemble": ["scene", "variant", "settings", "frame_time", "frames", "frames_run",
                         "frames_with_pairs", "max_pairs", "end_pairs", "first_pair_frame",
                         "end_max_stretch", "held_fraction", "diverged_frame", "step_ms",
                         "count_ms", "error", "device"],
    "batch": ["count", "cloths", "particles", "substeps", "dispatches_per_frame", "frames",
              "wall_ms", "wall_ms_min", "wall_ms_max", "frame_ms", "ms_per_copy",
              "copy_steps_per_s", "particle_steps_per_s", "device"],
    "fused": ["round", "fuse", "frames", "dispatches_per_frame", "wall_ms_per_frame",
              "gpu_ms_per_frame", "same_bits", "device"],
}
TEXT = {"label", "method", "solver", "kind", "case", "reason", "device", "measure", "integrator",
        "damping_model", "seed", "scene", "variant", "settings", "error", "fuse"}


def may_be_empty(experiment, row, column):
    """Cells that are empty or not a number by design."""
    if experiment == "budget" and column == "seed_002_gtx970":
        return True  # the seed measured RBGS, GS and Jacobi only, at 1, 2, 4 and 8 ms
    if experiment == "explicit-stability":
        # kd rows fix dt, h rows fix kd; the ratio row is no run of its own
        if column == "dt":
            return row["measure"] != "largest stable kd"
        if column == "kd":
            return row["measure"] == "largest stable kd"
        if column in ("runs", "steps"):
            return row["measure"] == "h ratio"
    if experiment == "pareto":
        # the settings of one family only; a setting that blew up is not timed
        if column in ("omega", "outer", "inner"):
            return row["method"] != "pd"
        if column == "tolerance":
            return row["method"] != "implicit"
        if column.startswith("frame_ms") or column in ("residual", "trajectory_error"):
            return row["stable"] == "0"
    if experiment == "contact-ensemble" and column in ("end_max_stretch", "held_fraction",
                                                       "step_ms", "count_ms"):
        return row["frames_run"] == "0"  # a run that never started measured nothing
    if experiment == "scaling" and column in CONTACT_COLUMNS:
        return True  # passes of a colliding scene, checked by contact_pass_columns
    if experiment == "stability":
        if row["kind"] == "limit":
            # the largest stable h and the smallest unstable one, where the sweep found them
            return column in ("dt", "dt_unstable", "steps", "stable", "failed_at_step",
                              "max_stretch", "energy_growth", "nan_count")
        if column == "dt_unstable" or (column == "failed_at_step" and row["stable"] == "1"):
            return True
        if row["stable"] == "0" and column in ("max_stretch", "energy_growth"):
            return True  # an exploded run may end in inf or NaN
    return False


def check_csv(workdir, experiment):
    """Problems with out/EXPERIMENT.csv; also returns its rows."""
    path = os.path.join(workdir, "out", experiment + ".csv")
    if not os.path.exists(path):
        return [f"{experiment}.csv was not written"], []
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, [])
        rows = [dict(zip(header, r)) for r in reader]
    problems = []
    if header != COLUMNS[experiment]:
        problems.append(f"{experiment}.csv columns: expected {COLUMNS[experiment]}, got {header}")
        return problems, rows
    if not rows:
        problems.append(f"{experiment}.csv has no rows")
    for n, row in enumerate(rows, 2):
        if not row.get("device"):
            problems.append(f"{experiment}.csv line {n}: no device")
        for column, value in row.items():
            if column in TEXT:
                continue
            try:
                number = float(value)
            except ValueError:
                number = None
            if (number is None or not math.isfinite(number)) and not may_be_empty(experiment, row, column):
                problems.append(f"{experiment}.csv line {n}: {column} is {value!r}, not a finite number")
    return problems[:10], rows


def check_plot(workdir, experiment):
    if not HAS_GNUPLOT:
        return []
    problems = []
    png = os.path.join(workdir, "out", experiment + ".png")
    if not os.path.exists(png):
        problems.append(f"{experiment}.png was not written")
    else:
        with open(png, "rb") as f:
            if f.read(8) != b"\x89PNG\r\n\x1a\n":
                problems.append(f"{experiment}.png is not a PNG")
    if not os.path.exists(os.path.join(workdir, "out", experiment + ".gp")):
        problems.append(f"{experiment}.gp was not written")
    left = [n for n in os.listdir(os.path.join(workdir, "out")) if ".tmp" in n]
    if left:
        problems.append(f"temporary files left: {left}")
    return problems


def rbgs_equals_gs_cpu(rows):
    """Seed 002's claim on the tool's own output: per iteration, rbgs and gs-cpu reach the same
    residual, to float rounding (positions within 5e-7 m move a residual of this size by far
    less than 1e-3 of itself)."""
    by = {}
    for r in rows:
        by.setdefault(r["label"], {})[int(r["iterations"])] = float(r["residual"])
    rbgs, gs = by.get("rbgs", {}), by.get("gs-cpu", {})
    common = sorted(set(rbgs) & set(gs))
    if len(common) < 5:
        return [f"only {len(common)} iteration counts of rbgs and gs-cpu to compare"]
    return [f"iteration {k}: residual {rbgs[k]} (rbgs) vs {gs[k]} (gs-cpu)" for k in common
            if abs(rbgs[k] - gs[k]) > 1e-3 * gs[k]][:3]


def fronts_hold_stable_settings(rows):
    """Some setting is on each Pareto front, and only stable ones are."""
    problems = []
    for front in ("front_residual", "front_trajectory"):
        on = [r for r in rows if r[front] == "1"]
        if not on:
            problems.append(f"no setting is on the {front} front")
        if any(r["stable"] != "1" for r in on):
            problems.append(f"an unstable setting is on the {front} front")
    return problems


def stability_kinds(rows):
    kinds = {r["kind"] for r in rows}
    cases = {r["case"] for r in rows if r["kind"] == "extreme"}
    problems = [f"no {k} rows" for k in ("grid", "limit", "extreme") if k not in kinds]
    expected = {"h = 1/30 s, 1 substep", "stiffness 1e8", "pin 1 m off its rest position",
                "coincident rows", "collapsed to a point"}
    if cases != expected:
        problems.append(f"extreme cases: expected {sorted(expected)}, got {sorted(cases)}")
    return problems


def every_family(rows):
    """Each family has its rows: projective dynamics per sweep count, implicit Euler per
    tolerance with the iterations it used (at least one, at most --max-iterations), the
    explicit integrator once per substep count; a converged explicit run is stable."""
    problems = fronts_hold_stable_settings(rows)
    methods = {(r["method"], r["solver"]) for r in rows}
    for m in (("pd", "rbgs"), ("implicit", "cg"), ("implicit", "jacobi"), ("explicit", "verlet")):
        if m not in methods:
            problems.append(f"no {m[0]} {m[1]} rows")
    for r in rows:
        if r["method"] == "implicit":
            if float(r["tolerance"]) not in (1e-2, 1e-4):
                problems.append(f"implicit row with tolerance {r['tolerance']}")
            if not 1 <= float(r["iterations"]) <= 40:
                problems.append(f"implicit {r['solver']} used {r['iterations']} iterations per substep")
        if r["method"] == "explicit" and (r["substeps"] != "1000" or r["stable"] != "1"):
            problems.append(f"explicit row: {r['substeps']} substeps, stable {r['stable']}")
    return problems


CONTACT_COLUMNS = ("colliders_ms", "hash_ms", "contacts_ms", "contact_ms")


def rows_for(key, expected, name):
    """A check that the CSV has exactly the rows `expected` of the columns `key` (a tuple each),
    in any order: the experiment ran what its options asked for, once each."""
    def check(rows):
        got = sorted(tuple(r[c] for c in key) for r in rows)
        want = sorted(expected)
        return [] if got == want else [f"{name}: rows {key} {got}, expected {want}"]
    return check


def convergence_solvers(rows):
    """--solvers jacobi,chebyshev,rbgs:1.5 and --max-iterations 12: each label once at each of
    the same iteration counts (log-spaced) from 1 to 12, rbgs at ω 1.5, every residual
    finite."""
    counts = {}
    for r in rows:
        counts.setdefault(r["label"], []).append(int(r["iterations"]))
    problems = [] if sorted(counts) == ["chebyshev", "jacobi", "rbgs:1.5"] else [
        f"convergence.csv: labels {sorted(counts)}, expected chebyshev, jacobi, rbgs:1.5"]
    first = next(iter(counts.values()), [])
    for label, ks in counts.items():
        rising = ks == sorted(set(ks)) and len(ks) >= 8 and ks[0] == 1 and ks[-1] == 12
        if not rising or ks != first:
            problems.append(f"convergence.csv: {label} at iterations {ks}, expected the same "
                            f"rising counts from 1 to 12 for every label")
    problems += [f"convergence.csv: {r['label']} at {r['iterations']}: residual {r['residual']!r}"
                 for r in rows if not math.isfinite(float(r["residual"]))][:3]
    problems += [f"convergence.csv: rbgs:1.5 has omega {r['omega']!r}" for r in rows
                 if r["label"] == "rbgs:1.5" and float(r["omega"]) != 1.5][:1]
    return problems


BUDGET_ROWS = rows_for(("label", "budget_ms"),
                       [(label, ms) for label in ("jacobi", "chebyshev", "rbgs", "rbgs:1.7", "gs-cpu")
                        for ms in ("0.2", "0.4")], "budget.csv")
TEMPLATE_ROWS = rows_for(("label", "solver", "grid", "particles", "iterations"),
                         [("jacobi", "jacobi", "6", "36", "2")], "scaling.csv")
IMPLICIT_ROWS = rows_for(("label", "solver", "grid", "particles", "iterations"),
                         [("cg", "cg", "6", "36", "2"), ("implicit-jacobi", "jacobi", "6", "36", "2")],
                         "scaling.csv")


def no_contact_columns(rows):
    """A scene without colliders or self-contact records no collision pass."""
    return [f"scaling.csv: {c} is {r[c]!r} in a scene without contact"
            for r in rows for c in CONTACT_COLUMNS if r[c] != "nan"][:5]


def diverged_point_left_out(rows):
    """At dt = 1 s one sweep lets the cloth run away and 200 do not: the run goes on past the
    point that diverged, which has no row, and times the other from the scene's first state."""
    sweeps = sorted(int(r["iterations"]) for r in rows)
    return [] if sweeps == [200] else [f"scaling.csv: rows for {sweeps} sweeps, expected only 200"]


def self_contact_columns(rows):
    """Self-contact without colliders: hash, contacts and contact timed, no colliders pass."""
    problems = []
    for r in rows:
        if r["colliders_ms"] != "nan":
            problems.append(f"scaling.csv: colliders_ms is {r['colliders_ms']!r} with no collider")
        for c in ("hash_ms", "contacts_ms", "contact_ms"):
            if not (math.isfinite(float(r[c])) and float(r[c]) > 0):
                problems.append(f"scaling.csv: {c} is {r[c]!r} with self-contact on")
    return problems[:5] or ([] if rows else ["scaling.csv has no rows"])


def collide_rows(rows):
    """One row per point count; a power-of-two table of at least twice the points; the build's
    6 dispatches plus the query; about 4 neighbours a point at one point per cell."""
    problems = []
    if [r["points"] for r in rows] != ["10", "2000"]:
        problems.append(f"collide.csv points: expected 10, 2000, got {[r['points'] for r in rows]}")
    for r in rows:
        n, table = int(r["points"]), int(r["table_size"])
        if table < 2 * n or table & (table - 1):
            problems.append(f"collide.csv: table of {table} slots for {n} points")
        if r["dispatches"] != "7":
            problems.append(f"collide.csv: {r['dispatches']} operations for {n} points, expected 7")
    big = [r for r in rows if r["points"] == "2000"]
    if big and not 2.0 <= float(big[0]["neighbours_per_point"]) <= 6.0:
        problems.append(f"collide.csv: {big[0]['neighbours_per_point']} neighbours per point at "
                        "2000 points, expected about 4 (4π/3 points within one cell size)")
    return problems


def contact_step_rows(rows):
    """One row per h with the step count the time asks for; a small cloth falling on a ball
    stays out of it at both steps."""
    problems = []
    got = [(r["dt"], r["steps"]) for r in rows]
    if got != [("0.004", "10"), ("0.008", "5")]:
        problems.append(f"contact-steps.csv (dt, steps): expected [(0.004, 10), (0.008, 5)], got {got}")
    for r in rows:
        if float(r["max_penetration"]) > 1e-4 or r["nan"] != "0":
            problems.append(f"contact-steps.csv at h = {r['dt']}: penetration "
                            f"{r['max_penetration']} m, {r['nan']} NaN")
        # tunnelling_free: 1 where the step kept the cloth out (penetration at most 0.1 mm),
        # untangled, finite and not diverged (apps/bench/contact_steps.c), else 0
        clean = (float(r["max_penetration"]) <= 1e-4 and r["max_intersecting_pairs"] == "0"
                 and r["nan"] == "0" and r["diverged_step"] == "0")
        if r["tunnelling_free"] != ("1" if clean else "0") or r["diverged_step"] != "0":
            problems.append(f"contact-steps.csv at h = {r['dt']}: tunnelling_free is "
                            f"{r['tunnelling_free']!r} for penetration {r['max_penetration']}, "
                            f"{r['max_intersecting_pairs']} pairs, diverged_step "
                            f"{r['diverged_step']!r}")
    return problems


def contact_step_diverged(rows):
    """A small hanging cloth with one sweep above a ground plane runs away at h = 1 s in its
    second step and holds at h = 0.01 s: the sweep reports the first with the step it diverged
    at and goes on to the other (the h are run in increasing order). Without self-contact
    (whose bounds keep such a solve from running away) it folds through itself at 0.01 s: not
    tunnelling-free either."""
    got = [(r["dt"], r["steps"], r["diverged_step"], r["tunnelling_free"]) for r in rows]
    want = [("0.01", "200", "0", "0"), ("1", "2", "2", "0")]
    return [] if got == want else [f"contact-steps.csv (dt, steps, diverged_step, "
                                   f"tunnelling_free): expected {want}, got {got}"]


def fused_rows(rows):
    """Two rounds of the small hanging cloth (8 substeps of 4 x 4 sweeps over its 2 colours):
    unfused, fused with its iterate in shared memory and fused in global memory each round, the
    same bits every way; per substep 32 sweep dispatches unfused (the first sweep predicting,
    the last finalizing: 256 a frame) or one for the whole substep fused (8)."""
    got = [(r["round"], r["fuse"], r["frames"], r["same_bits"]) for r in rows]
    want = [(str(k), fuse, "2", "1") for k in (1, 2) for fuse in ("off", "shared", "global")]
    if got != want:
        return [f"fused.csv (round, fuse, frames, same_bits): expected {want}, got {got}"]
    got = [r["dispatches_per_frame"] for r in rows]
    want = ["256", "8", "8"] * 2
    return [] if got == want else [f"fused.csv dispatches_per_frame: expected {want}, got {got}"]


def explicit_limits(rows):
    """Seed 001 §3 on a small cloth: every limit the bisection brackets lies within 10 % of
    the one predicted from the stiffest mode, and Adams-Bashforth's h is 0.3 / 2 of Euler's."""
    problems = []
    got = [(r["measure"], r["integrator"]) for r in rows]
    want = [("largest stable kd", "euler"), ("largest stable kd", "rk2")] + \
        [("largest stable h", i) for i in ("euler", "rk2", "adams-bashforth", "verlet")] + \
        [("h ratio", "euler / adams-bashforth")]
    if got != want:
        problems.append(f"explicit-stability.csv rows: expected {want}, got {got}")
    for r in rows:
        ratio = float(r["measured_over_predicted"])
        if not 0.9 <= ratio <= 1.1:
            problems.append(f"explicit-stability.csv: {r['integrator']} {r['measure']}: "
                            f"measured {r['measured']}, predicted {r['predicted']}")
    if rows and rows[-1]["measure"] == "h ratio" and \
            abs(float(rows[-1]["predicted"]) - 20.0 / 3.0) > 0.1:
        problems.append(f"explicit-stability.csv: predicted ratio {rows[-1]['predicted']}, "
                        "expected 2 / 0.3 = 6.67")
    return problems


ENSEMBLE_VARIANTS = ["scene", "omega-low", "omega-high", "damping+0.01", "damping-x2",
                     "friction-0", "friction-0.6", "dt-x2", "dt-x4"]


def batch_rows(counts, per_copy):
    """One row per count with count x per_copy particles, the same dispatches per frame for
    every count, and throughputs that agree with the wall time."""
    def check(rows):
        got = [(int(r["count"]), int(r["particles"])) for r in rows]
        want = [(n, n * per_copy) for n in counts]
        if got != want:
            return [f"batch.csv (count, particles): {got}, expected {want}"]
        problems = []
        if len({r["dispatches_per_frame"] for r in rows}) != 1:
            problems.append("batch.csv: dispatches_per_frame differ: "
                            f"{[r['dispatches_per_frame'] for r in rows]}")
        for r in rows:
            steps = int(r["count"]) * int(r["substeps"]) * 1000.0 / float(r["wall_ms"])
            if abs(float(r["copy_steps_per_s"]) - steps) > 1e-4 * steps:
                problems.append(f"batch.csv: copy_steps_per_s {r['copy_steps_per_s']} for "
                                f"{r['count']} copies at {r['wall_ms']} ms, expected {steps:.6g}")
        return problems
    return check


def ensemble_rows(scenes, variants, frames, overridden=True):
    """One row per scene x variant, in order, each run through all its frames without an error,
    the first variant's settings naming the --set overrides where the run gave some. The pairs
    are not checked: they are what the experiment measures."""
    base = "(the scene with the --set overrides)" if overridden else "(the scene's own settings)"

    def check(rows):
        want = [(s, v, str(frames)) for s in scenes for v in ENSEMBLE_VARIANTS[:variants]]
        got = [(r["scene"], r["variant"], r["frames_run"]) for r in rows]
        problems = [] if got == want else [f"contact-ensemble.csv (scene, variant, frames_run): "
                                           f"expected {want}, got {got}"]
        for r in rows:
            if r["error"] or r["diverged_frame"] != "-1":
                problems.append(f"contact-ensemble.csv: {r['scene']} {r['variant']} stopped: "
                                f"{r['error']}")
            if int(r["frames_with_pairs"]) > frames or \
                    (r["first_pair_frame"] == "-1") != (r["frames_with_pairs"] == "0"):
                problems.append(f"contact-ensemble.csv: {r['variant']}: frames_with_pairs "
                                f"{r['frames_with_pairs']}, first_pair_frame {r['first_pair_frame']}")
        return problems[:5]
    return check


# A small cloth over the drape's ball and the four cloths of sphere-hit, each 8 x 8.
TINY_CONTACT = ["--set", "cloths.0.grid=[8,8]"]

GOOD = [
    {"name": "convergence on enlarged.json",
     "argv": ["convergence"] + TINY_ENLARGED + ["--max-iterations", "30"] + QUICK,
     "experiment": "convergence", "check": rbgs_equals_gs_cpu},
    {"name": "convergence on hanging.json, frame 2",
     "argv": ["convergence"] + TINY_HANGING + ["--frame", "2", "--max-iterations", "12",
                                               "--solvers", "jacobi,chebyshev,rbgs:1.5"] + QUICK,
     "experiment": "convergence", "check": convergence_solvers},
    {"name": "budget",
     "argv": ["budget"] + TINY_ENLARGED + ["--ms", "0.2,0.4"] + QUICK, "experiment": "budget",
     "check": BUDGET_ROWS},
    {"name": "pareto",
     "argv": ["pareto"] + TINY_HANGING + ["--iterations", "1,4", "--substeps", "1,2",
                                          "--time", "0.05", "--solvers", "jacobi,rbgs"] + QUICK,
     "experiment": "pareto", "check": fronts_hold_stable_settings},
    {"name": "pareto, every family",
     "argv": ["pareto"] + TINY_HANGING + ["--iterations", "1,4", "--substeps", "2",
                                          "--time", "0.05", "--solvers", "rbgs,cg,implicit-jacobi,verlet",
                                          "--tolerances", "1e-2,1e-4", "--max-iterations", "40",
                                          "--explicit-substeps", "1000"] + QUICK,
     "experiment": "pareto", "check": every_family},
    {"name": "stability",
     "argv": ["stability"] + TINY_HANGING + ["--dt", "0.002,0.0333", "--stiffness", "1e4,1e6",
                                             "--time", "0.04", "--min-steps", "4",
                                             "--solvers", "rbgs,jacobi", "--limit-ratio", "2"] + QUICK,
     "experiment": "stability", "check": stability_kinds},
    {"name": "scaling, built-in scene",
     "argv": ["scaling", "--grids", "4,8", "--iterations", "2,3"] + QUICK, "experiment": "scaling",
     "check": no_contact_columns},
    {"name": "scaling, a point that diverges",
     "argv": ["scaling", HANGING, "--set", "dt=1", "--set", "substeps=1", "--grids", "6",
              "--iterations", "1,200", "--solvers", "rbgs", "--repeat", "2", "--warmup", "0"],
     "experiment": "scaling", "check": diverged_point_left_out},
    {"name": "scaling, self-contact",
     "argv": ["scaling", HANGING, "--set", "collision.self=true", "--grids", "6,8", "--iterations", "2",
              "--solvers", "rbgs"] + QUICK,
     "experiment": "scaling", "check": self_contact_columns},
    {"name": "scaling, a scene as template",
     "argv": ["scaling", HANGING, "--grids", "6", "--iterations", "2", "--solvers", "jacobi"] + QUICK,
     "experiment": "scaling", "check": TEMPLATE_ROWS},
    {"name": "scaling, implicit Euler",
     "argv": ["scaling", HANGING, "--grids", "6", "--iterations", "2", "--solvers",
              "cg,implicit-jacobi"] + QUICK,
     "experiment": "scaling", "check": IMPLICIT_ROWS},
    {"name": "collide",
     "argv": ["collide", "--points", "2000,10"] + QUICK, "experiment": "collide", "check": collide_rows},
    {"name": "collide, values after =",
     "argv": ["collide", "--points=2000,10", "--repeat=1", "--warmup=0"], "experiment": "collide",
     "check": collide_rows},
    {"name": "contact-steps",
     "argv": ["contact-steps", asset("drape.json"), "--set", "cloths.0.grid=[8,8]",
              "--set", "cloths.0.origin=[-0.5,0.62,-0.5]", "--dt", "0.004,0.008",
              "--time", "0.04"] + QUICK,
     "experiment": "contact-steps", "check": contact_step_rows},
    {"name": "contact-steps, an h that diverges",
     "argv": ["contact-steps"] + TINY_HANGING + [
              "--set", 'colliders=[{"type":"plane","point":[0,-5,0],"normal":[0,1,0]}]',
              "--set", "solver.outer_iterations=1", "--set", "solver.inner_iterations=1",
              "--dt", "1,0.01", "--time", "2"] + QUICK,
     "experiment": "contact-steps", "check": contact_step_diverged},
    {"name": "fused",
     "argv": ["fused"] + TINY_HANGING + ["--frames", "2", "--repeat", "2", "--warmup", "0"],
     "experiment": "fused", "check": fused_rows},
    {"name": "explicit-stability",
     "argv": ["explicit-stability", asset("seed001.json"), "--set", "cloths.0.grid=[6,6]",
              "--set", "cloths.0.mass=1", "--set", "cloths.0.pins=[[0,0],[1,0],[2,0],[3,0],[4,0],[5,0]]",
              "--time", "0.3", "--limit-ratio", "1.1"],
     "experiment": "explicit-stability", "check": explicit_limits},
    {"name": "batch, built-in napkin",
     "argv": ["batch", "--counts", "3,1", "--frames", "1", "--warmup", "0"],
     "experiment": "batch", "check": batch_rows([1, 3], 256)},
    {"name": "batch, a scene with a collider",
     "argv": ["batch", HANGING, "--set", "cloths.0.grid=[6,6]", "--set", "cloths.0.pins=[[0,0],[5,0]]",
              "--set",
              'colliders=[{"type": "sphere", "center": [0, 0.5, 0], "radius": 0.2}]',
              "--set", "instances.spacing=[2, 0, 0]", "--counts", "1,2", "--frames", "1"],
     "experiment": "batch", "check": batch_rows([1, 2], 36)},
    {"name": "contact-ensemble, every variant",
     "argv": ["contact-ensemble", asset("drape.json")] + TINY_CONTACT + ["--frames", "3"],
     "experiment": "contact-ensemble", "check": ensemble_rows(["drape.json"], 9, 3)},
    {"name": "contact-ensemble, two scenes, three variants",
     "argv": ["contact-ensemble", "--scenes", asset("drape.json") + "," + asset("ribbons.json"),
              "--frames", "2", "--variants", "3"] + TINY_CONTACT,
     "experiment": "contact-ensemble",
     "check": ensemble_rows(["drape.json", "ribbons.json"], 3, 2)},
    {"name": "contact-ensemble, the scene's own settings",
     "argv": ["contact-ensemble", asset("ribbons.json"), "--frames", "1", "--variants", "1"],
     "experiment": "contact-ensemble", "check": ensemble_rows(["ribbons.json"], 1, 1, False)},
]

SOLVERS = ("a comma-separated list of jacobi, chebyshev, rbgs or gs-cpu, each optionally with "
           ":OMEGA (0 < OMEGA < 2), or of cg, implicit-jacobi, euler, rk2, adams-bashforth or verlet")

BAD = [
    {"name": "no experiment", "argv": [], "usage": True, "stderr": "clothvk-bench: no experiment given"},
    {"name": "unknown experiment", "argv": ["speed", HANGING],
     "stderr": 'clothvk-bench: unknown experiment "speed" (expected convergence, budget, pareto, '
               'stability, scaling, collide, contact-steps, explicit-stability, contact-ensemble, '
               'batch or fused)'},
    {"name": "missing scene", "argv": ["convergence"],
     "stderr": "clothvk-bench: convergence needs a scene file"},
    {"name": "scene file missing", "argv": ["budget", os.path.join(ROOT, "tests", "scenes", "nope.json")],
     "stderr": "clothvk-bench: " + os.path.join(ROOT, "tests", "scenes", "nope.json") +
               ": cannot open: No such file or directory"},
    {"name": "malformed scene", "argv": ["stability", os.path.join(ROOT, "tests", "scenes", "malformed.json")],
     "stderr": "clothvk-bench: " + os.path.join(ROOT, "tests", "scenes", "malformed.json") +
               ":4:10: malformed JSON: '}' expected near '\"cloths\"'"},
    {"name": "bad scene via --set", "argv": ["pareto", HANGING, "--set", "cloths.0.mass=-1"],
     "stderr": f"clothvk-bench: {HANGING}: cloths.0.mass (from --set): must be greater than 0, got -1"},
    {"name": "scene too large for the device", "env": {"CLOTHVK_DEVICE": "llvmpipe"},
     "argv": ["convergence", HANGING, "--set", "cloths.0.grid=[20000,20000]"],
     "stderr_start": f"clothvk-bench: {HANGING}: cloths.0.grid: 400000000 particles are too many for llvmpipe"},
    {"name": "unknown option", "argv": ["budget", HANGING, "--fast"],
     "stderr": "clothvk-bench: unknown option --fast (see --help)"},
    {"name": "option of another experiment", "argv": ["convergence", HANGING, "--ms", "1"],
     "stderr": "clothvk-bench: --ms is not an option of convergence (see --help)"},
    {"name": "budget of 0 ms", "argv": ["budget", HANGING, "--ms", "1,0"],
     "stderr": "clothvk-bench: --ms: expected a comma-separated list of numbers greater than 0, got 1,0"},
    {"name": "budget not a number", "argv": ["budget", HANGING, "--ms", "fast"],
     "stderr": "clothvk-bench: --ms: expected a comma-separated list of numbers greater than 0, got fast"},
    {"name": "--repeat 0", "argv": ["scaling", "--repeat", "0"],
     "stderr": "clothvk-bench: --repeat: expected a whole number from 1 to 1000, got 0"},
    {"name": "--repeat=0", "argv": ["scaling", "--repeat=0"],
     "stderr": "clothvk-bench: --repeat: expected a whole number from 1 to 1000, got 0"},
    {"name": "--ms= of another experiment", "argv": ["convergence", HANGING, "--ms=1"],
     "stderr": "clothvk-bench: --ms is not an option of convergence (see --help)"},
    {"name": "a flag with a value", "argv": ["scaling", "--no-plot=yes"],
     "stderr": "clothvk-bench: --no-plot takes no value, got --no-plot=yes"},
    {"name": "unknown option with a value", "argv": ["scaling", "--fast=1"],
     "stderr": "clothvk-bench: unknown option --fast=1 (see --help)"},
    {"name": "iterations not whole", "argv": ["pareto", HANGING, "--iterations", "1,2.5"],
     "stderr": "clothvk-bench: --iterations: expected a comma-separated list of whole numbers from 1 to 100000, got 1,2.5"},
    {"name": "negative time step", "argv": ["stability", HANGING, "--dt", "0.001,-0.002"],
     "stderr": "clothvk-bench: --dt: expected a comma-separated list of time steps greater than 0 and at most 10 s, got 0.001,-0.002"},
    {"name": "unknown solver", "argv": ["convergence", HANGING, "--solvers", "rbgs,sor"],
     "stderr": "clothvk-bench: --solvers: expected " + SOLVERS + ", got rbgs,sor"},
    {"name": "omega out of range", "argv": ["convergence", HANGING, "--solvers", "rbgs:2"],
     "stderr": "clothvk-bench: --solvers: expected " + SOLVERS + ", got rbgs:2"},
    {"name": "implicit outside scaling and pareto", "argv": ["convergence", HANGING, "--solvers", "rbgs,cg"],
     "stderr": "clothvk-bench: --solvers: cg (implicit Euler) is measured by scaling and pareto only"},
    {"name": "explicit outside pareto", "argv": ["scaling", HANGING, "--solvers", "verlet"],
     "stderr": "clothvk-bench: --solvers: verlet (explicit) is measured by pareto only (and by "
               "explicit-stability, which takes no --solvers)"},
    {"name": "explicit without its substeps", "argv": ["pareto", HANGING, "--solvers", "rbgs,rk2"],
     "stderr": "clothvk-bench: pareto: explicit integrators need --explicit-substeps (their steps "
               "are far shorter than the others')"},
    {"name": "explicit substeps without explicit",
     "argv": ["pareto", HANGING, "--explicit-substeps", "100"],
     "stderr": "clothvk-bench: pareto: --explicit-substeps without an explicit integrator in --solvers"},
    {"name": "explicit substeps past the bound",
     "argv": ["pareto", HANGING, "--solvers", "euler", "--explicit-substeps", "100,10001"],
     "stderr": "clothvk-bench: --explicit-substeps: expected a comma-separated list of whole numbers from 1 to 10000, got 100,10001"},
    {"name": "tolerance of 0", "argv": ["pareto", HANGING, "--solvers", "cg", "--tolerances", "0.01,0"],
     "stderr": "clothvk-bench: --tolerances: expected a comma-separated list of numbers greater than 0 and at most 1, got 0.01,0"},
    {"name": "no points", "argv": ["collide", "--points", "0,10"],
     "stderr": "clothvk-bench: --points: expected a comma-separated list of whole numbers from 1 to 16777216, got 0,10"},
    {"name": "--points of scaling", "argv": ["scaling", "--points", "10"],
     "stderr": "clothvk-bench: --points is not an option of scaling (see --help)"},
    {"name": "grid of 1", "argv": ["scaling", "--grids", "1"],
     "stderr": "clothvk-bench: --grids: expected a comma-separated list of whole numbers from 2 to 65535, got 1"},
    {"name": "-o is a file", "argv": ["scaling", "-o", "afile"], "files": ["afile"],
     "stderr": "clothvk-bench: -o afile: not a folder"},
    {"name": "-o inside a file", "argv": ["scaling", "-o", "afile/out"], "files": ["afile"],
     "stderr": "clothvk-bench: -o afile/out: cannot use it as a folder: Not a directory"},
    {"name": "-o under a missing folder", "argv": ["scaling", "-o", "missing/out"],
     "stderr": "clothvk-bench: -o missing/out: cannot create the folder: missing is not a folder"},
    {"name": "contact-ensemble, a scene missing",
     "argv": ["contact-ensemble", "--scenes", asset("drape.json") + ",nope.json"],
     "stderr": "clothvk-bench: nope.json: cannot open: No such file or directory"},
    {"name": "contact-ensemble, an empty item in --scenes",
     "argv": ["contact-ensemble", "--scenes", "a.json,,b.json"],
     "stderr": "clothvk-bench: --scenes: expected a comma-separated list of scene files, got a.json,,b.json"},
    {"name": "contact-ensemble, SCENE and --scenes",
     "argv": ["contact-ensemble", HANGING, "--scenes", HANGING],
     "stderr": "clothvk-bench: contact-ensemble: a SCENE or --scenes, not both"},
    {"name": "batch, a count of 0", "argv": ["batch", "--counts", "0,4"],
     "stderr": "clothvk-bench: --counts: expected a comma-separated list of whole numbers from 1 "
               "to 1048576, got 0,4"},
    {"name": "batch, past the device",
     "argv": ["batch", "--counts", "1,65536", "--set", "cloths.0.grid=[16,16]"],
     "stderr_start": "clothvk-bench: built-in napkin: instances.count: 16777216 particles are "
                     "too many for "},
    {"name": "batch, offsets against the counts",
     "argv": ["batch", "--counts", "2", "--set", "instances.offsets=[[0, 0, 0]]"],
     "stderr": "clothvk-bench: built-in napkin: instances.offsets (from --set): has 1 offsets "
               "for 2 copies (instances.count); give one per copy"},
    {"name": "-o without a value", "argv": ["scaling", "-o"], "stderr": "clothvk-bench: -o: expected a value"},
]

if os.geteuid() != 0:  # root writes anywhere
    BAD.append({"name": "-o read-only", "argv": ["scaling", "-o", "locked/out"], "locked": "locked",
                "stderr": "clothvk-bench: -o locked/out: cannot create the folder: Permission denied"})


def run(argv, workdir, env=None):
    e = dict(os.environ, **(env or {}))
    return tooltest.run_tool(BENCH, argv, workdir, e, timeout=300)


def good_case(case):
    with tempfile.TemporaryDirectory(prefix="clothvk-bench-") as workdir:
        p = run(case["argv"] + ["-o", "out"], workdir)
        problems = []
        if p.returncode != 0:
            problems.append(f"exit status {p.returncode}; stderr: {p.stderr.strip()[:500]}")
            return problems
        if p.stderr:
            problems.append(f"expected nothing on stderr, got: {p.stderr.strip()[:500]}")
        first = p.stdout.splitlines()[0] if p.stdout else ""
        if " on " not in first:
            problems.append(f"the first line does not name the device: {first!r}")
        csv_problems, rows = check_csv(workdir, case["experiment"])
        problems += csv_problems + check_plot(workdir, case["experiment"])
        if "check" in case and rows and not csv_problems:
            problems += case["check"](rows)
        return problems


def bad_stderr_ok(case):
    """The test of a bad case's stderr: one line starting with stderr_start, or the line stderr
    (followed by the usage text where the case says so)."""
    def ok(lines):
        if "stderr_start" in case:
            return len(lines) == 1 and lines[0].startswith(case["stderr_start"])
        return bool(lines) and lines[0] == case["stderr"] and (len(lines) == 1 or bool(case.get("usage")))
    return ok


def bad_case(case):
    with tempfile.TemporaryDirectory(prefix="clothvk-bench-") as workdir:
        for name in case.get("files", []):
            open(os.path.join(workdir, name), "w").close()
        if "locked" in case:
            os.mkdir(os.path.join(workdir, case["locked"]), 0o500)
        before = sorted(os.listdir(workdir))
        p = run(case["argv"], workdir, case.get("env"))
        expected = case["stderr_start"] + "..." if "stderr_start" in case else case["stderr"]
        problems = tooltest.refusal_problems(p, expected, before, sorted(os.listdir(workdir)), 2,
                                             bad_stderr_ok(case))
        if "locked" in case:
            os.chmod(os.path.join(workdir, case["locked"]), 0o700)
        return problems


def no_gnuplot():
    """Without gnuplot the CSV is still written, the run succeeds, and stderr says why there
    is no plot."""
    with tempfile.TemporaryDirectory(prefix="clothvk-bench-") as workdir:
        p = run(["scaling", "--grids", "4", "--iterations", "2", "-o", "out"] + QUICK, workdir,
                {"CLOTHVK_GNUPLOT": os.path.join(workdir, "no-gnuplot-here")})
        problems = []
        if p.returncode != 0:
            problems.append(f"exit status {p.returncode}")
        expected = "clothvk-bench: no plot: gnuplot could not be run (install gnuplot-nox); the CSV is complete"
        if p.stderr.strip() != expected:
            problems.append(f"expected stderr: {expected}\n    got: {p.stderr.strip()}")
        csv_problems, _ = check_csv(workdir, "scaling")
        problems += csv_problems
        if os.path.exists(os.path.join(workdir, "out", "scaling.png")):
            problems.append("a PNG was written without gnuplot")
        return problems


def require_clean():
    """--require-clean: a run with an intersecting pair is no clean run (here two cloths that
    cross at the start, simulated with collision.allow_intersecting_start: contact keeps pairs
    apart that start apart, and leaves these crossed): the CSV is written all the same, then one
    line on stderr and exit status 1."""
    with tempfile.TemporaryDirectory(prefix="clothvk-bench-") as workdir:
        p = run(["contact-ensemble", os.path.join(ROOT, "tests", "scenes", "crossing.json"),
                 "--set", "collision.allow_intersecting_start=true", "--frames", "2",
                 "--variants", "2", "--require-clean", "--no-plot", "-o", "out"], workdir)
        problems = [] if p.returncode == 1 else [f"exit status {p.returncode}, expected 1"]
        expected = "clothvk-bench: --require-clean: 2 of 2 runs had an intersecting pair, 0 stopped early"
        if p.stderr.strip() != expected:
            problems.append(f"expected stderr: {expected}\n    got: {p.stderr.strip()}")
        csv_problems, rows = check_csv(workdir, "contact-ensemble")
        problems += csv_problems
        if [r["first_pair_frame"] for r in rows] != ["0", "0"]:
            problems.append(f"first_pair_frame: expected 0 and 0, got {[r['first_pair_frame'] for r in rows]}")
        return problems


def main():
    report = tooltest.Cases("bench")
    cases = [(c["name"], lambda c=c: good_case(c)) for c in GOOD]
    cases += [(c["name"], lambda c=c: bad_case(c)) for c in BAD]
    cases.append(("no gnuplot", no_gnuplot))
    cases.append(("contact-ensemble --require-clean", require_clean))
    for name, check in cases:
        report.add(name, check())
    return report.finish(before_closing=None if HAS_GNUPLOT else "gnuplot is not installed: plots were not checked")


if __name__ == "__main__":
    sys.exit(main())
