#!/usr/bin/env python3
"""The contact scenes' figures (docs/figures/contact-baseline/, docs/figures/contact-ogc/): each
scene run whole on one lavapipe core with a given build's clothvk-sim, its `--json` turned into
one CSV row. Run two builds in one sitting to compare them:

    python3 scripts/contact_figures.py BUILD_DIR OUT.csv [--sizes 20,40,80]
    python3 scripts/contact_figures.py BUILD_DIR OUT.csv --sizes 20,40,80,160 --thicknesses default,0.0025
    python3 scripts/contact_figures.py BUILD_DIR OUT.csv --held

    python3 scripts/contact_figures.py BUILD_DIR OUT.csv --rest [--label NAME]
    python3 scripts/contact_figures.py BUILD_DIR OUT.csv --twist
    python3 scripts/contact_figures.py BUILD_DIR OUT.csv --intervals 1,2,4,8 [--rounds R]
    python3 scripts/contact_figures.py BUILD_DIR OUT.csv --pile-settings [--rounds R]

--thicknesses: the drape alone at each size and each cloth thickness (default: the scene's, half
the shortest spring's rest length, so thinner as the grid is finer; a number: collision.thickness in m,
the same cloth at every size), with the per-detection cost, in a first column "thickness"
(scaling.csv).
--held: how much the bounds hold the cloth back, by substep length (held.csv): the 40 x 40 drape
in 8, 4, 2 and 1 substeps a frame of 1/60 s, and the pile and the twist at their own settings.
--rest: how the drape and the pile come to rest (rest.csv): by window of frames, the detections
and how far the particles move a substep (the scene run a substep a frame, its positions after
every substep read from a PC2 point cache); --label names the build in a first column.
--twist: how far the twist's kinematics stretch it (twist.csv): its largest and 99th percentile
stretch as `--json` reports them after every 40 frames, with self-contact and without, and
without it under a strain limit or with four times the outer iterations.
--intervals: what collision.detection_interval trades (interval.csv): the 40 x 40 drape, the
pile and the twist whole at each interval, the intervals alternated in each of R rounds (default
2), the fastest round's ms per frame kept (the other columns do not change from round to round).
--pile-settings: what the pile's solver settings cost (pile-settings.csv): the pile of six cloths
at its own settings and at each of PILE_SETTINGS (substeps a frame of the scene's, outer and inner
iterations, strain limit), the settings alternated in each of R rounds (default 2), ms per frame from the
fastest and the slowest round, the passes' ms from the fastest.
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

import pc2

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
COLUMNS = ["scene", "particles", "ms per frame", "ms per frame without self-contact",
           "contacts group ms", "contact pass ms", "solve ms", "dispatches per frame",
           "detections", "intersecting pairs at the end", "largest stretch at the end %"]
# Passes of the contact's detection (the old build's: "contacts" and "hash").
GROUP = ("contacts", "hash", "detect faces", "detect edges", "bounds")


def run(sim, scene, sets, extra=()):
    argv = [sim, os.path.join(ROOT, "assets", "scenes", scene), "--json", *extra]
    for s in sets:
        argv += ["--set", s]
    env = dict(os.environ, LP_NUM_THREADS="0")
    out = subprocess.run(argv, env=env, capture_output=True, text=True, check=True).stdout
    return json.loads(out)


def passes(d, names):
    return sum(p["gpu_ms"] for p in d["passes"] if p["name"] in names)


def row(sim, name, scene, sets, alone):
    d = run(sim, scene, sets)
    without = run(sim, scene, sets + ["collision.self=false"]) if alone else None
    c = d["contacts"]
    return [name, d["particles"], round(d["gpu_ms_per_frame"], 1),
            round(without["gpu_ms_per_frame"], 1) if without else "",
            round(passes(d, GROUP), 1), round(passes(d, ("contact",)), 1),
            round(passes(d, ("solve",)), 1), d["dispatches_per_frame"], c.get("searches", ""),
            c["intersecting_pairs"], round(100 * d["max_stretch"], 1)]


HELD_COLUMNS = ["scene", "substeps a frame", "ms per frame", "detections",
                "particle-substeps held at a bound %", "largest stretch at the end %",
                "intersecting pairs at the end"]


def held_row(sim, name, scene, sets):
    d = run(sim, scene, sets)
    c = d["contacts"]
    return [name, d["substeps"], round(d["gpu_ms_per_frame"], 1), c["searches"],
            round(100.0 * c["held_fraction"], 2), round(100 * d["max_stretch"], 1),
            c["intersecting_pairs"]]


def measured(rows, r):
    """Appends row r and prints it, as each run ends."""
    rows.append(r)
    print(r, file=sys.stderr)


def held_rows(sim):
    rows = []
    for k in (8, 4, 2, 1):
        measured(rows, held_row(sim, "drape 40x40", "contact-drape.json",
                                [f"substeps={k}", f"dt={1.0 / 60.0 / k:.10g}"]))
    for name, scene in (("pile of six 20x20", "contact-pile.json"),
                        ("twist", "contact-twist.json")):
        measured(rows, held_row(sim, name, scene, []))
    return HELD_COLUMNS, rows


REST_COLUMNS = ["build", "scene", "frames", "detections", "substeps", "mean move a substep mm",
                "largest move a substep mm", "largest speed m/s",
                "particle-substeps faster than 0.5 m/s"]


def rest_rows(sim, label):
    rows = []
    for name, scene, window, windows in (("drape 40x40", "contact-drape.json", 20, 3),
                                         ("pile of six 20x20", "contact-pile.json", 60, 6)):
        d = run(sim, scene, [], ["--frames", "1"])
        k, dt = d["substeps"], d["dt"]
        searched = [0] + [run(sim, scene, [], ["--frames", str(window * (i + 1))])
                          ["contacts"]["searches"] for i in range(windows)]
        with tempfile.TemporaryDirectory() as tmp:
            cache = os.path.join(tmp, "run.pc2")
            run(sim, scene, ["substeps=1"],
                ["--frames", str(k * window * windows), "--pc2", cache])
            _, x = pc2.read(cache)
        for i in range(windows):
            moves = []
            for s in range(i * window * k, (i + 1) * window * k):
                a, b = x[s], x[s + 1]
                moves += [((b[j] - a[j]) ** 2 + (b[j + 1] - a[j + 1]) ** 2 +
                           (b[j + 2] - a[j + 2]) ** 2) ** 0.5 for j in range(0, len(a), 3)]
            top = max(moves)
            measured(rows, [label, name, f"{i * window + 1}-{(i + 1) * window}",
                            searched[i + 1] - searched[i], window * k,
                            round(1000 * sum(moves) / len(moves), 4), round(1000 * top, 2),
                            round(top / dt, 2), sum(1 for m in moves if m > 0.5 * dt)])
    return REST_COLUMNS, rows


TWIST_FRAMES = (40, 80, 120, 160, 200, 240)
TWIST_P99 = (40, 120, 240)
TWIST_COLUMNS = (["run"] + [f"largest stretch at frame {f} %" for f in TWIST_FRAMES] +
                 [f"p99 stretch at frame {f} %" for f in TWIST_P99])


def twist_rows(sim):
    """The twist's stretch as `--json` reports it (docs/library.md: max_stretch, p99_stretch)
    after each of TWIST_FRAMES, a run to each."""
    rows = []
    for name, sets in (("with self-contact (the scene)", []),
                       ("without self-contact", ["collision.self=false"]),
                       ("without self-contact, solver.strain_limit 0.05",
                        ["collision.self=false", "solver.strain_limit=0.05"]),
                       ("without self-contact, 16 outer iterations",
                        ["collision.self=false", "solver.outer_iterations=16"])):
        at = {f: run(sim, "contact-twist.json", sets, ["--frames", str(f)]) for f in TWIST_FRAMES}
        measured(rows, [name] + [round(100 * at[f]["max_stretch"], 1) for f in TWIST_FRAMES] +
                 [round(100 * at[f]["p99_stretch"], 1) for f in TWIST_P99])
    return TWIST_COLUMNS, rows


INTERVAL_COLUMNS = ["scene", "detection interval", "ms per frame", "contacts group ms",
                    "detections", "particle-substeps held at a bound %",
                    "largest stretch at the end %", "p99 stretch at the end %",
                    "intersecting pairs at the end"]


def alternated(sim, jobs, rounds):
    """Runs each job, (scene, --set items), once in each of `rounds` rounds, the jobs in order
    within a round; returns each job's --json outputs, the fastest round's first."""
    runs = [[] for _ in jobs]
    for _ in range(rounds):
        for i, (scene, sets) in enumerate(jobs):
            d = run(sim, scene, sets)
            print(scene, " ".join(sets), round(d["gpu_ms_per_frame"], 1), file=sys.stderr)
            runs[i].append(d)
    # sorted() is stable: among equally fast rounds the earliest comes first
    return [sorted(ds, key=lambda d: d["gpu_ms_per_frame"]) for ds in runs]


def end_columns(d):
    """The particle-substeps held at a bound %, the largest and the p99 stretch at the end %,
    and the intersecting pairs at the end."""
    c = d["contacts"]
    return [round(100.0 * c["held_fraction"], 2), round(100 * d["max_stretch"], 1),
            round(100 * d["p99_stretch"], 1), c["intersecting_pairs"]]


def interval_rows(sim, intervals, rounds):
    """The three scenes at each interval, alternated in each round; each row from the fastest
    round (only the times differ between rounds)."""
    jobs = [(name, scene, int(k)) for name, scene in (("drape 40x40", "contact-drape.json"),
                                                       ("pile of six 20x20", "contact-pile.json"),
                                                       ("twist", "contact-twist.json"))
            for k in intervals.split(",")]
    runs = alternated(sim, [(scene, [f"collision.detection_interval={k}"])
                            for _, scene, k in jobs], rounds)
    rows = []
    for (name, _, k), (d, *_) in zip(jobs, runs):
        rows.append([name, k, round(d["gpu_ms_per_frame"], 1), round(passes(d, GROUP), 1),
                     d["contacts"]["searches"]] + end_columns(d))
    return INTERVAL_COLUMNS, rows


PILE_SETTINGS = ((8, 2, 4, 0.045), (6, 2, 4, 0.04), (4, 4, 4, 0.05), (4, 4, 4, 0.04),
                 (4, 3, 4, 0.04), (4, 2, 8, 0.04), (8, 1, 8, 0.05))
PILE_COLUMNS = ["substeps a frame", "outer iterations", "inner iterations", "strain limit %",
                "ms per frame min", "ms per frame max", "contacts group ms", "contact pass ms",
                "solve ms", "detections", "particle-substeps held at a bound %",
                "largest stretch at the end %", "p99 stretch at the end %",
                "intersecting pairs at the end"]


def pile_settings_rows(sim, rounds):
    """The pile at its own settings and at each of PILE_SETTINGS, alternated in each of `rounds`
    rounds: ms per frame from the fastest and the slowest round, the passes' ms from the fastest
    (the other columns do not change from round to round)."""
    with open(os.path.join(ROOT, "assets", "scenes", "contact-pile.json")) as f:
        scene = json.load(f)
    solver = scene["solver"]
    own = (scene["substeps"], solver["outer_iterations"], solver["inner_iterations"],
           solver["strain_limit"])
    frame = scene["dt"] * scene["substeps"]  # kept: each setting splits the same frame
    settings = (own,) + PILE_SETTINGS
    runs = alternated(sim, [("contact-pile.json",
                             [f"substeps={k}", f"dt={frame / k:.10g}",
                              f"solver.outer_iterations={outer}",
                              f"solver.inner_iterations={inner}",
                              f"solver.strain_limit={limit}"])
                            for k, outer, inner, limit in settings], rounds)
    rows = []
    for (k, outer, inner, limit), ds in zip(settings, runs):
        d = ds[0]
        rows.append([k, outer, inner, round(100 * limit, 1), round(d["gpu_ms_per_frame"], 1),
                     round(ds[-1]["gpu_ms_per_frame"], 1), round(passes(d, GROUP), 1),
                     round(passes(d, ("contact",)), 1), round(passes(d, ("solve",)), 1),
                     d["contacts"]["searches"]] + end_columns(d))
    return PILE_COLUMNS, rows


def scene_rows(sim, sizes):
    rows = []
    for n in (int(s) for s in sizes.split(",")):
        measured(rows, row(sim, f"drape {n}x{n}", "contact-drape.json",
                           [f"cloths.0.grid=[{n},{n}]"], True))
    measured(rows, row(sim, "drape 40x40, one substep", "contact-drape.json",
                       ["substeps=1", "dt=0.0166666667"], False))
    measured(rows, row(sim, "pile of six 20x20", "contact-pile.json", [], False))
    measured(rows, row(sim, "twist", "contact-twist.json", [], False))
    return COLUMNS, rows


SCALING_COLUMNS = (["thickness"] + COLUMNS[:8] + ["detections", "detection ms per detection"] +
                   COLUMNS[9:])


def scaling_rows(sim, sizes, thicknesses):
    """The drape at each size and thickness: row()'s columns, led by the thickness, with the
    detection group's GPU ms per detection (its ms a frame times the frames over the
    detections)."""
    rows = []
    with open(os.path.join(ROOT, "assets", "scenes", "contact-drape.json")) as f:
        frames = json.load(f)["frames"]
    for t in thicknesses.split(","):
        sets = [] if t == "default" else [f"collision.thickness={t}"]
        for n in (int(s) for s in sizes.split(",")):
            r = row(sim, f"drape {n}x{n}", "contact-drape.json",
                    [f"cloths.0.grid=[{n},{n}]"] + sets, True)
            per = round(r[4] * frames / r[8], 2) if r[8] else ""
            measured(rows, [t] + r[:9] + [per] + r[9:])
    return SCALING_COLUMNS, rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("build")
    parser.add_argument("out")
    parser.add_argument("--sizes", default="20,40,80")
    parser.add_argument("--thicknesses", default="",
                        help="with --sizes: the drape alone at each thickness, e.g. "
                             "default,0.0025")
    parser.add_argument("--held", action="store_true",
                        help="the particles held at their bounds, by substep length")
    parser.add_argument("--rest", action="store_true",
                        help="how the drape and the pile come to rest")
    parser.add_argument("--twist", action="store_true",
                        help="how far the twist's kinematics stretch it")
    parser.add_argument("--label", default="", help="with --rest: the build's name in the rows")
    parser.add_argument("--intervals", default="",
                        help="collision.detection_interval values to compare, e.g. 1,2,4,8")
    parser.add_argument("--pile-settings", action="store_true",
                        help="the pile at its own and at other solver settings")
    parser.add_argument("--rounds", type=int, default=2,
                        help="with --intervals or --pile-settings: rounds")
    a = parser.parse_args()
    sim = os.path.join(os.path.abspath(a.build), "apps", "clothvk-sim")
    columns, rows = (held_rows(sim) if a.held else
                     rest_rows(sim, a.label) if a.rest else
                     twist_rows(sim) if a.twist else
                     interval_rows(sim, a.intervals, a.rounds) if a.intervals else
                     pile_settings_rows(sim, a.rounds) if a.pile_settings else
                     scaling_rows(sim, a.sizes, a.thicknesses) if a.thicknesses else
                     scene_rows(sim, a.sizes))
    with open(a.out, "w", newline="") as f:
        out = csv.writer(f, lineterminator="\n")
        out.writerow(columns)
        out.writerows(rows)


if __name__ == "__main__":
    main()
