#!/usr/bin/env python3
"""CPU time a frame on the standard hanging cloth: Bullet's soft body against clothvk.

    python3 peers/bullet/cpu.py [--rounds N] [--frames F] [[LABEL=]SIM ...]

Runs peers/bullet's harness (bullet-hanging: 256 iterations, one step a frame, one thread) and
each clothvk-sim given (default build/apps/clothvk-sim; another build's binary to compare before
and after; LABEL names its row) on assets/scenes/peer-hanging.json with lavapipe on one thread (LP_NUM_THREADS=0),
alternated, N rounds (default 5). A run's CPU time a frame is the user and system time of a run
of F + 20 frames less that of a run of 20, over F (default 200): what the run itself computed,
without start-up, which a loaded machine inflates far less than wall time. Prints a CSV — one row
per engine with a column per round, then Bullet's time over each clothvk's — in the form of
docs/figures/peer-hanging/frame-cpu.csv, and the CPU's model name on stderr.
"""
import argparse
import os
import resource
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
SCENE = ROOT / "assets" / "scenes" / "peer-hanging.json"
BULLET = ROOT / "build" / "peers" / "bullet" / "bullet-hanging"
BASE_FRAMES = 20


def cpu_seconds(argv, env):
    """User and system seconds of one run of argv (its output discarded); exits on failure."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                          text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        sys.exit(f"cpu.py: {' '.join(map(str, argv))} failed ({done.returncode}): "
                 f"{done.stderr.strip()}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def ms_per_frame(command, frames, env):
    """CPU ms a frame of command(n), a run of n frames: (F + 20 frames) less 20, over F."""
    long = cpu_seconds(command(frames + BASE_FRAMES), env)
    short = cpu_seconds(command(BASE_FRAMES), env)
    return 1000.0 * (long - short) / frames


def cpu_model():
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    except OSError:
        return "unknown"
    for line in out.splitlines():
        if line.startswith("Model name:"):
            return line.split(":", 1)[1].strip()
    return "unknown"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--frames", type=int, default=200)
    parser.add_argument("sims", nargs="*", default=[str(ROOT / "build" / "apps" / "clothvk-sim")])
    args = parser.parse_args()
    if args.rounds < 1 or args.frames < 1:
        sys.exit("cpu.py: --rounds and --frames take a positive whole number")
    sims = [s.split("=", 1) if "=" in s else [s, s] for s in args.sims]
    for path in [BULLET] + [sim for _, sim in sims]:
        if not os.access(path, os.X_OK):
            sys.exit(f"cpu.py: {path}: no such program (build first: bash scripts/build.sh)")
    env = dict(os.environ, LP_NUM_THREADS="0")
    engines = [("Bullet 3.24 soft body, 256 iterations, one step a frame (peers/bullet)",
                lambda n: [BULLET, "--frames", str(n)])]
    for label, sim in sims:
        engines.append((f"clothvk, peer-hanging.json, {label}",
                        lambda n, sim=sim: [sim, SCENE, "--frames", str(n)]))
    times = {name: [] for name, _ in engines}
    for _ in range(args.rounds):
        for name, command in engines:
            times[name].append(ms_per_frame(command, args.frames, env))
    print(f"cpu: {cpu_model()}", file=sys.stderr)
    header = ["run (CPU ms per frame; one thread each)"] + \
             [f"round {r + 1}" for r in range(args.rounds)]
    print(",".join(header))
    for name, _ in engines:
        print(",".join([f'"{name}"'] + [f"{t:.1f}" for t in times[name]]))
    bullet = times[engines[0][0]]
    for name, _ in engines[1:]:
        print(",".join([f'"Bullet / clothvk {name.split(", ", 2)[-1]}"'] +
                       [f"{b / c:.2f}" for b, c in zip(bullet, times[name])]))


if __name__ == "__main__":
    main()
