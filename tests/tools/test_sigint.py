#!/usr/bin/env python3
"""Ctrl-C in the middle of a run leaves only complete files: clothvk-sim writing OBJ frames and
a dump, and clothvk-render writing PNGs, each get SIGINT once a few frames are on disk. Each
must exit with status 1 and one line on stderr ("interrupted after N of M ..."), every OBJ file
must hold all its vertices and faces, every PNG must decode, no temporary file may remain, and
the dump (written only by a finished run) must not exist.

    python3 tests/tools/test_sigint.py PATH/TO/clothvk-sim PATH/TO/clothvk-render
"""
import glob
import os
import re
import signal
import subprocess
import sys
import tempfile
import time

import tooltest

SIM, RENDER = tooltest.tool_paths("clothvk-sim", "clothvk-render")
SMALL = os.path.join(tooltest.ROOT, "tests", "scenes", "small.json")
# 40 x 40 particles, 2000 frames: long enough to be interrupted on any machine.
GRID = ["--set", "cloths.0.grid=[40,40]", "--set", "cloths.0.pins=[[0,0],[39,0]]",
        "--frames", "2000"]


def interrupt(argv, cwd, pattern, wanted):
    """Starts argv, sends SIGINT once `wanted` files match `pattern`; the problems with how it
    ended."""
    p = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while len(glob.glob(os.path.join(cwd, pattern))) < wanted and p.poll() is None:
        if time.monotonic() > deadline:
            p.kill()
            return ["no files appeared within 120 s"]
        time.sleep(0.05)
    if p.poll() is not None:
        return [f"ended before it could be interrupted: {p.returncode}, {p.stderr.read()}"]
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=120)
    problems = []
    if p.returncode != 1:
        problems.append(f"exit status {p.returncode} after SIGINT, expected 1")
    lines = err.splitlines()
    if len(lines) != 1 or not re.fullmatch(
            r"clothvk-(sim: interrupted after [0-9]+ of 2000 frames; the files written are "
            r"complete|render: interrupted after [0-9]+ of 2001 images)", lines[0]):
        problems.append(f"stderr: {err.strip()!r}")
    leftovers = [n for n in os.listdir(cwd) if ".tmp" in n] + \
                [n for n in glob.glob(os.path.join(cwd, "*", "*")) if ".tmp" in n]
    if leftovers:
        problems.append(f"temporary files left: {leftovers}")
    return problems


def obj_problems(path, particles=1600):
    with open(path) as f:
        lines = f.read().splitlines()
    vertices = sum(1 for line in lines if line.startswith("v "))
    faces = sum(1 for line in lines if line.startswith("f "))
    if vertices != particles or faces != 2 * 39 * 39:
        return [f"{os.path.basename(path)}: {vertices} vertices, {faces} faces (incomplete)"]
    return []


def sim_case():
    with tempfile.TemporaryDirectory(prefix="clothvk-sigint-") as workdir:
        argv = [SIM, SMALL, "--obj", "frames", "--dump", "out.csv"] + GRID
        problems = interrupt(argv, workdir, "frames/*.obj", 3)
        objs = sorted(glob.glob(os.path.join(workdir, "frames", "*.obj")))
        for path in objs:
            problems += obj_problems(path)
        if os.path.exists(os.path.join(workdir, "out.csv")):
            problems.append("out.csv was written by an interrupted run")
        return problems, len(objs)


def render_case():
    with tempfile.TemporaryDirectory(prefix="clothvk-sigint-") as workdir:
        argv = [RENDER, SMALL, "-o", "frames", "--size", "160x90", "--quiet"] + GRID
        problems = interrupt(argv, workdir, "frames/*.png", 3)
        pngs = sorted(glob.glob(os.path.join(workdir, "frames", "*.png")))
        for path in pngs:
            try:
                tooltest.png_info(path)
            except ValueError as e:
                problems.append(f"{os.path.basename(path)}: {e}")
        return problems, len(pngs)


def main():
    failed = 0
    for name, case in (("clothvk-sim --obj --dump", sim_case), ("clothvk-render", render_case)):
        problems, files = case()
        print(f"{'FAIL' if problems else 'ok  '} {name}: {files} complete files")
        for problem in problems:
            print(f"     {problem}")
        failed += bool(problems)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
