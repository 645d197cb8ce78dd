#!/usr/bin/env python3
"""Lavapipe on one core against its default threading, scene by scene, the two alternated.

    python3 scripts/threads_figures.py build OUT.csv [--rounds 3] [--frames 30]

Runs clothvk-sim SCENE --frames N --json with LP_NUM_THREADS=0 (one core, no hand-off) and
without it (lavapipe's default: a thread per core), in turns, ROUNDS times, and writes per scene
and setting the fastest and slowest round's GPU ms a frame and, from the same runs, the ms a
frame of three groups of passes: detection (the hash, the faces' and edges' detection, the
bounds and the decision), the contact pass (cloths and colliders) and the rest (prediction,
sweeps, strain limit, tethers, finalize). Standard library only.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

# (label, scene, --set overrides)
SCENES = [
    ("peer-hanging.json (no contact)", "peer-hanging.json", []),
    ("contact-drape.json (40 x 40)", "contact-drape.json", []),
    ("contact-drape.json at 80 x 80", "contact-drape.json", ["cloths.0.grid=[80,80]"]),
    ("contact-pile.json (six 20 x 20)", "contact-pile.json", []),
    ("demo.json (100 x 100)", "demo.json", []),
]
DETECTION = {"contacts", "hash", "detect faces", "detect edges", "bounds"}
CONTACT = {"contact", "colliders"}


def run(sim, scene, sets, frames, one_core):
    env = dict(os.environ)
    env.pop("LP_NUM_THREADS", None)
    if one_core:
        env["LP_NUM_THREADS"] = "0"
    args = [sim, scene, "--frames", str(frames), "--json"]
    for s in sets:
        args += ["--set", s]
    out = subprocess.run(args, env=env, check=True, capture_output=True, text=True).stdout
    d = json.loads(out)
    groups = {"detection": 0.0, "contact": 0.0, "rest": 0.0}
    for p in d["passes"]:
        key = "detection" if p["name"] in DETECTION else "contact" if p["name"] in CONTACT else "rest"
        groups[key] += p["gpu_ms"]
    return d["particles"], d["gpu_ms_per_frame"], groups


def span(values):
    """The fastest and the slowest round, as figures.py's "X min", "X max" columns."""
    return [f"{min(values):.1f}", f"{max(values):.1f}"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build")
    ap.add_argument("out")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--frames", type=int, default=30)
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    sim = os.path.join(a.build, "apps", "clothvk-sim")
    results = {}
    for r in range(a.rounds):
        for label, scene, sets in SCENES:
            # alternate which setting goes first from round to round
            for one_core in ((True, False) if r % 2 == 0 else (False, True)):
                particles, ms, groups = run(sim, os.path.join(root, "assets", "scenes", scene), sets,
                                            a.frames, one_core)
                entry = results.setdefault((label, one_core), {"particles": particles, "ms": [],
                                                               "detection": [], "contact": [], "rest": []})
                entry["ms"].append(ms)
                for k, v in groups.items():
                    entry[k].append(v)
                print(f"round {r + 1}: {label}, {'one core' if one_core else 'default threading'}: "
                      f"{ms:.1f} ms a frame", file=sys.stderr)
    with open(a.out, "w", newline="") as f:
        w = csv.writer(f)
        head = ["scene", "particles", "lavapipe threads"]
        for name in ("ms per frame", "detection ms", "contact pass ms", "other passes ms"):
            head += [f"{name} min", f"{name} max"]
        w.writerow(head)
        for label, _, _ in SCENES:
            for one_core in (True, False):
                e = results[(label, one_core)]
                w.writerow([label, e["particles"], "one (LP_NUM_THREADS=0)" if one_core else "default"] +
                           span(e["ms"]) + span(e["detection"]) + span(e["contact"]) + span(e["rest"]))


if __name__ == "__main__":
    main()
