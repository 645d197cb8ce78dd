#!/usr/bin/python3
"""Particle-scale roughness ("orange peel") of a grid cloth's surface.

    /usr/bin/python3 scripts/peel.py SCENE [--frames N] [--set key=value ...] [--sim PATH] [--spectrum]
    /usr/bin/python3 scripts/peel.py --dump FILE.csv --grid NIxNJ [--cloth-offset K]
    /usr/bin/python3 scripts/peel.py --obj FILE.obj [--grid NIxNJ]

The measure, per interior particle (i, j) of cloth 0 (a grid): the normal component of the
umbrella Laplacian, h = n . ((x[i-1,j] + x[i+1,j] + x[i,j-1] + x[i,j+1]) / 4 - x[i,j]) with n the
unit normal from the central differences, is the discrete mean curvature times a quarter of the
spacing squared; its high-pass part h - mean3x3(h) keeps what changes from one particle to the
next and drops folds and drapes many particles wide. The figure is its RMS in mm over the
particles whose 3 x 3 mean lies inside the grid (i, j from 2 to n - 3).

With --spectrum it also prints the share of the high-pass energy in the checkerboard
(-1)^(i+j) and the two stripe patterns (-1)^i, (-1)^j: the pattern a red-black over-relaxed
sweep excites, or the zig-zag that skip-one bend springs do not see.

SCENE runs through clothvk-sim (--dump) in a temporary folder; the grid of cloth 0 comes from
the scene (and a --set of cloths.0.grid). Prints one line: `peel_mm=0.357 frames=90 grid=100x100`.
Exit 2 on bad input, with one line naming the problem.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def fail(message):
    print(f"peel.py: {message}", file=sys.stderr)
    sys.exit(2)


def grid_field(points, ni, nj):
    """points (ni * nj, 3), i fastest -> (nj, ni, 3)."""
    return points.reshape(nj, ni, 3)


def laplacian_normal(x):
    """h (nj-2, ni-2) in metres: the umbrella Laplacian's normal component at interior points."""
    c = x[1:-1, 1:-1]
    lap = (x[1:-1, :-2] + x[1:-1, 2:] + x[:-2, 1:-1] + x[2:, 1:-1]) / 4.0 - c
    du = x[1:-1, 2:] - x[1:-1, :-2]
    dv = x[2:, 1:-1] - x[:-2, 1:-1]
    n = np.cross(du, dv)
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    n = n / np.where(length > 0, length, 1.0)
    return np.sum(lap * n, axis=-1)


def high_pass(h):
    """h minus its 3 x 3 mean, at the points whose 3 x 3 neighbourhood lies in h."""
    mean = sum(h[1 + a:h.shape[0] - 1 + a, 1 + b:h.shape[1] - 1 + b]
               for a in (-1, 0, 1) for b in (-1, 0, 1)) / 9.0
    return h[1:-1, 1:-1] - mean


def peel(points, ni, nj):
    hp = high_pass(laplacian_normal(grid_field(points, ni, nj)))
    return float(np.sqrt(np.mean(hp ** 2))) * 1e3, hp


def spectrum(hp):
    """Shares of hp's energy in the checkerboard and the two stripes (their projections)."""
    jj, ii = np.indices(hp.shape)
    total = float(np.sum(hp ** 2))
    shares = {}
    for name, pattern in (("checkerboard", (-1.0) ** (ii + jj)), ("stripes_i", (-1.0) ** ii),
                          ("stripes_j", (-1.0) ** jj)):
        # Local amplitude of the pattern: the 2 x 2 block mean of hp times the pattern, so a
        # checkerboard whose sign flips between regions still counts.
        demod = hp * pattern
        block = (demod[:-1, :-1] + demod[1:, :-1] + demod[:-1, 1:] + demod[1:, 1:]) / 4.0
        shares[name] = float(np.sum(block ** 2) / (total * (block.size / hp.size))) if total else 0.0
    return shares


def read_dump(path):
    try:
        return np.loadtxt(path, delimiter=",", ndmin=2)
    except (OSError, ValueError) as e:
        fail(f"{path}: {e}")


def read_obj(path):
    """The first object's vertices."""
    vs = []
    objects = 0
    try:
        with open(path) as f:
            for line in f:
                if line.startswith("o "):
                    objects += 1
                    if objects > 1:
                        break
                elif line.startswith("v "):
                    vs.append([float(t) for t in line.split()[1:4]])
    except (OSError, ValueError) as e:
        fail(f"{path}: {e}")
    return np.array(vs)


def parse_grid(text):
    try:
        ni, nj = (int(t) for t in text.lower().split("x"))
    except ValueError:
        fail(f"--grid {text}: expected NIxNJ, such as 100x100")
    return ni, nj


def scene_grid(scene, sets):
    try:
        with open(scene) as f:
            data = json.load(f)
        grid = data["cloths"][0]["grid"]
    except (OSError, ValueError, KeyError, IndexError, TypeError) as e:
        fail(f"{scene}: cloths.0.grid: {e}")
    for s in sets:
        key, _, value = s.partition("=")
        if key == "cloths.0.grid":
            grid = json.loads(value)
    return int(grid[0]), int(grid[1])


def run_scene(a):
    ni, nj = scene_grid(a.scene, a.set)
    with tempfile.TemporaryDirectory() as tmp:
        dump = os.path.join(tmp, "dump.csv")
        cmd = [a.sim, a.scene, "--dump", dump]
        if a.frames is not None:
            cmd += ["--frames", str(a.frames)]
        for s in a.set:
            cmd += ["--set", s]
        r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            print(r.stderr, end="", file=sys.stderr)
            sys.exit(1)
        points = read_dump(dump)
    return points[:ni * nj], ni, nj


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene", nargs="?")
    ap.add_argument("--frames", type=int)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--sim", default=os.path.join(ROOT, "build", "apps", "clothvk-sim"))
    ap.add_argument("--dump")
    ap.add_argument("--obj")
    ap.add_argument("--grid")
    ap.add_argument("--spectrum", action="store_true")
    a = ap.parse_args()
    if sum(x is not None for x in (a.scene, a.dump, a.obj)) != 1:
        fail("give one of SCENE, --dump FILE or --obj FILE")
    if a.scene:
        points, ni, nj = run_scene(a)
    else:
        if a.dump and not a.grid:
            fail("--dump needs --grid NIxNJ")
        points = read_dump(a.dump) if a.dump else read_obj(a.obj)
        if a.grid:
            ni, nj = parse_grid(a.grid)
        else:
            ni = nj = int(round(np.sqrt(len(points))))
        points = points[:ni * nj]
    if points.shape != (ni * nj, 3) or min(ni, nj) < 7:
        fail(f"expected {ni} x {nj} (at least 7 x 7) points of cloth 0, got {points.shape[0]}")
    value, hp = peel(points, ni, nj)
    line = f"peel_mm={value:.4f} grid={ni}x{nj}"
    if a.frames is not None:
        line += f" frames={a.frames}"
    if a.spectrum:
        line += " " + " ".join(f"{k}={v:.3f}" for k, v in spectrum(hp).items())
    print(line)


if __name__ == "__main__":
    main()
