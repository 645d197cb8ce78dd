#!/usr/bin/env python3
"""Two builds of clothvk-sim side by side on the scenes with colliders
(docs/figures/collider-runs/): each scene run by each build in turn, ROUNDS times, on one
lavapipe core (LP_NUM_THREADS=0, pinned with taskset to core 0), and the start-up (a run of one
frame, wall seconds) measured the same way. One CSV row a scene and build: the range over the
rounds of ms a frame and of the contact pass's ms a frame (`--json`: gpu_ms_per_frame and the
pass "contact"), the start-up's range, and whether every round of both builds ended with the
same residual, stretch and contact figures (the same bits).

    python3 scripts/collider_runs.py BEFORE=PATH/clothvk-sim AFTER=PATH/clothvk-sim OUT.csv \\
        [--rounds 2]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# scene, frames, extra --set arguments, its label
SCENES = [
    ("contact-drape.json", 60, ["collision.self=false"], "contact-drape.json without self-contact"),
    ("contact-drape.json", 60, [], "contact-drape.json"),
    ("drape.json", 60, [], "drape.json"),
    ("box-stack.json", 60, [], "box-stack.json"),
    ("table.json", 60, [], "table.json"),
    ("chair.json", 60, [], "chair.json"),
    ("poncho.json", 60, [], "poncho.json"),
    ("funnel.json", 60, [], "funnel.json"),
    ("sphere-hit.json", 30, [], "sphere-hit.json"),
    ("demo.json", 30, [], "demo.json"),
]
SAME = ("residual", "max_stretch", "p99_stretch", "nan_count")
COLUMNS = ["scene", "frames", "build", "colliders", "ms per frame", "contact pass ms per frame",
           "start-up s", "same bits"]


def run(sim, scene, frames, sets):
    argv = ["taskset", "-c", "0", sim, os.path.join(ROOT, "assets", "scenes", scene),
            "--frames", str(frames), "--json"]
    for s in sets:
        argv += ["--set", s]
    env = dict(os.environ, LP_NUM_THREADS="0")
    start = time.monotonic()
    done = subprocess.run(argv, env=env, capture_output=True, text=True)
    wall = time.monotonic() - start
    if done.returncode != 0:
        sys.exit(f"collider_runs.py: {' '.join(argv)} failed: {done.stderr.strip()}")
    return json.loads(done.stdout), wall


def span(values, digits):
    lo, hi = min(values), max(values)
    return f"{lo:.{digits}f}" if round(lo, digits) == round(hi, digits) else \
        f"{lo:.{digits}f}-{hi:.{digits}f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("out")
    parser.add_argument("--rounds", type=int, default=2)
    args = parser.parse_args()
    builds = [b.split("=", 1) for b in (args.before, args.after)]
    rows = []
    for scene, frames, sets, label in SCENES:
        seen = {name: {"ms": [], "contact": [], "start": [], "bits": set()} for name, _ in builds}
        colliders = len(json.load(open(os.path.join(ROOT, "assets", "scenes", scene)))
                        .get("colliders", []))
        for _ in range(args.rounds):
            for name, sim in builds:
                out, _ = run(sim, scene, frames, sets)
                _, wall = run(sim, scene, 1, sets)
                passes = {p["name"]: p["gpu_ms"] for p in out["passes"]}
                seen[name]["ms"].append(out["gpu_ms_per_frame"])
                seen[name]["contact"].append(passes.get("contact", 0.0))
                seen[name]["start"].append(wall)
                seen[name]["bits"].add(json.dumps([out[k] for k in SAME] + [out["contacts"]],
                                                  sort_keys=True))
        bits = set().union(*(s["bits"] for s in seen.values()))
        for name, _ in builds:
            s = seen[name]
            rows.append([label, frames, name, colliders, span(s["ms"], 1), span(s["contact"], 1),
                         span(s["start"], 2), "yes" if len(bits) == 1 else "no"])
        print(f"{label}: done", file=sys.stderr)
    with open(args.out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        w.writerows(rows)


if __name__ == "__main__":
    main()
