#!/usr/bin/env python3
"""Mutation run: copies of the scenes in assets/scenes with one to three values changed (a
number made 0, negative, tiny, huge or 2^32 - 1; a string, array or object swapped for another
type; a key deleted; an array emptied or grown), each run through clothvk-sim for a few frames
with every output asked for (--dump, --pc2, --bake) in a folder of its own. Counts the outcomes
by exit status; a crash (death by a signal), a hang (past the timeout) or an exit 1 (a failure
while running, which bad input should not cause: it should be refused with exit 2 up front) is
kept under OUT with its stderr, and so is a breach of the tools' contract: a refusal (exit 2)
that wrote anything or said more or less than one line on stderr, or a run that exited 0
without its outputs. The script exits 1 when any crash, hang or breach occurred.

    python3 scripts/mutate.py build/apps/clothvk-sim --count 2000 --seed 2 --out build/mutate
"""
import argparse
import collections
import copy
import glob
import json
import os
import random
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NUMBERS = [0, -1, 1e-30, 1e30, 4294967295, 1.5, -1e9, 3, 1e6]
OTHERS = [None, True, "x", [], {}, [0, 0, 0], [[0, 0]], "rbgs"]
SLOW = {"contact-pile-large.json"}


def paths(value, prefix=()):
    """Every (path, value) inside a JSON value."""
    yield prefix, value
    if isinstance(value, dict):
        for k, v in value.items():
            yield from paths(v, prefix + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from paths(v, prefix + (i,))


def mutate_once(scene, rng):
    candidates = [(p, v) for p, v in paths(scene) if p]
    path, value = rng.choice(candidates)
    parent = scene
    for key in path[:-1]:
        parent = parent[key]
    key = path[-1]
    kind = rng.random()
    if isinstance(value, (int, float)) and not isinstance(value, bool) and kind < 0.6:
        parent[key] = rng.choice(NUMBERS)
    elif kind < 0.75 and isinstance(parent, dict):
        del parent[key]
    elif kind < 0.85 and isinstance(value, list):
        parent[key] = [] if value and rng.random() < 0.5 else value + value
    else:
        parent[key] = copy.deepcopy(rng.choice(OTHERS + NUMBERS))
    return "/".join(str(k) for k in path)


def absolute_files(value, folder):
    """Mesh and texture paths made absolute, so a mutant runs from any folder."""
    if isinstance(value, dict):
        for k, v in value.items():
            if k in ("mesh", "file", "texture") and isinstance(v, str) and not os.path.isabs(v):
                value[k] = os.path.join(folder, v)
            else:
                absolute_files(v, folder)
    elif isinstance(value, list):
        for v in value:
            absolute_files(v, folder)
    return value


# Every output clothvk-sim writes, into the mutant's own folder.
OUTPUTS = ["--dump", "final.csv", "--pc2", "anim.pc2", "--bake", "bake"]
WRITTEN = {"final.csv", "anim.pc2", "anim.obj", "bake"}


def breach(outcome, stderr, work):
    """What a run broke of the tools' contract (docs/tools.md), or None: a refusal writes
    nothing and says one line; a run that succeeds writes every output it was asked for."""
    written = set(os.listdir(work)) - {"scene.json"}
    if outcome == "exit 2":
        if written:
            return "refusal wrote " + ",".join(sorted(written))
        if stderr.count("\n") != 1 or not stderr.startswith("clothvk-sim: "):
            return "refusal not one line"
    if outcome == "exit 0" and written != WRITTEN:
        return "success without " + ",".join(sorted(WRITTEN - written))
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sim", help="path to clothvk-sim")
    ap.add_argument("--count", type=int, default=400)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--frames", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=60)
    ap.add_argument("--out", default="build/mutate")
    args = ap.parse_args()
    args.sim = os.path.abspath(args.sim)
    rng = random.Random(args.seed)
    # Not the pile made for a GPU (250,000 particles): its two frames take 40-57 s on one lavapipe
    # core, so its mutants passed the timeout as "hangs" that finished (seed 3: three of 400,
    # one of them 54 s when run alone); its keys are contact-pile.json's.
    sources = sorted(p for p in glob.glob(os.path.join(ROOT, "assets", "scenes", "*.json"))
                     if os.path.basename(p) not in SLOW)
    scenes = {os.path.basename(p): absolute_files(json.load(open(p)), os.path.dirname(p))
              for p in sources}
    os.makedirs(args.out, exist_ok=True)
    outcomes = collections.Counter()
    kept = []
    for i in range(args.count):
        name = rng.choice(sorted(scenes))
        scene = copy.deepcopy(scenes[name])
        changed = [mutate_once(scene, rng) for _ in range(rng.randint(1, 3))]
        with tempfile.TemporaryDirectory(prefix="clothvk-mutate-") as work:
            path = os.path.join(work, "scene.json")
            with open(path, "w") as f:
                json.dump(scene, f)
            try:
                p = subprocess.run([args.sim, path, "--frames", str(args.frames), *OUTPUTS],
                                   cwd=work, capture_output=True, text=True,
                                   timeout=args.timeout)
                outcome = f"exit {p.returncode}" if p.returncode >= 0 else f"signal {-p.returncode}"
                stderr = p.stderr
                outcome = breach(outcome, stderr, work) or outcome
            except subprocess.TimeoutExpired:
                outcome, stderr = "hang", ""
        outcomes[outcome] += 1
        if outcome not in ("exit 0", "exit 2", "exit 3"):
            tag = "".join(c if c.isalnum() else "-" for c in outcome)[:40]
            keep = os.path.join(args.out, f"mutant-{i:05d}-{tag}.json")
            with open(keep, "w") as f:
                json.dump(scene, f, indent=1)
            kept.append((keep, name, changed, outcome, stderr.strip()[:300]))
    print(f"{args.count} mutants (seed {args.seed}): " +
          ", ".join(f"{n} x {o}" for o, n in sorted(outcomes.items())))
    for keep, name, changed, outcome, stderr in kept:
        print(f"  {outcome}: {keep} (from {name}, changed {', '.join(changed)}): {stderr}")
    bad = sum(n for o, n in outcomes.items() if not o.startswith("exit"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
