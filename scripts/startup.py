#!/usr/bin/env python3
"""Start-up: milliseconds to create a simulation of a scene (cvk_sim_create: buffers, uploads,
pipelines), first on a fresh context and then again on the same context, which keeps the
pipelines and layouts the first made (docs/library.md, "Pipelines"). Each library given is
measured in its own process, alternately, ROUNDS times, so a noisy machine loads them alike; the
CSV has one row per library, scene and kind of creation, with the median and range over rounds.

    python3 scripts/startup.py [--rounds N] [--out CSV] [LABEL=LIBRARY ...]

LIBRARY is a libclothvk.so (default: this tree's build/lib/libclothvk.so, labelled "this
tree"); compare two builds with, e.g., before=/tmp/old/build/lib/libclothvk.so
after=build/lib/libclothvk.so. Run it with LP_NUM_THREADS=0 for one lavapipe thread."""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENES = ["assets/scenes/contact-drape.json", "assets/scenes/contact-pile.json",
          "assets/scenes/funnel.json", "assets/scenes/peer-hanging.json"]
AGAIN = 3  # creations again on the same context, per round

MEASURE = r"""
import json, sys, time
import clothvk
out = {}
for path in sys.argv[1:]:
    scene = clothvk.Scene.load(path)
    with clothvk.Context() as ctx:
        times = []
        for i in range(1 + %d):
            t0 = time.perf_counter()
            sim = clothvk.Simulation(ctx, scene)
            times.append(1000.0 * (time.perf_counter() - t0))
            sim.close()
    scene.close()
    out[path] = times
print(json.dumps(out))
""" % AGAIN


def measure(library):
    env = dict(os.environ, CLOTHVK_LIBRARY=str(library), PYTHONPATH=str(ROOT / "python"))
    done = subprocess.run([sys.executable, "-c", MEASURE, *SCENES], cwd=ROOT, env=env,
                          capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"startup.py: {library}: {done.stderr.strip()}")
    return json.loads(done.stdout)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--out", default="startup.csv")
    parser.add_argument("libraries", nargs="*", metavar="LABEL=LIBRARY")
    args = parser.parse_args()
    libraries = [tuple(a.split("=", 1)) for a in args.libraries] or [
        ("this tree", ROOT / "build" / "lib" / "libclothvk.so")]
    first = {(label, s): [] for label, _ in libraries for s in SCENES}
    again = {(label, s): [] for label, _ in libraries for s in SCENES}
    for r in range(args.rounds):
        for label, library in libraries:
            for scene, times in measure(library).items():
                first[(label, scene)].append(times[0])
                again[(label, scene)].extend(times[1:])
                print(f"round {r + 1}, {label}, {scene}: first {times[0]:.0f} ms, again "
                      + ", ".join(f"{t:.0f}" for t in times[1:]) + " ms", flush=True)
    with open(args.out, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(["library", "scene", "creation", "median ms", "ms min", "ms max"])
        for label, _ in libraries:
            for scene in SCENES:
                for kind, table in (("first on a context", first), ("again on it", again)):
                    t = table[(label, scene)]
                    w.writerow([label, Path(scene).name, kind, f"{statistics.median(t):.0f}",
                                f"{min(t):.0f}", f"{max(t):.0f}"])
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
