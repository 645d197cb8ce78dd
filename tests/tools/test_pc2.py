#!/usr/bin/env python3
"""clothvk-sim --pc2 FILE [--every K]: the point cache a user hands to Blender, 3ds Max or Maya.

    python3 tests/tools/test_pc2.py PATH/TO/clothvk-sim

Good input: a scene of two grid cloths is run with --frames 6 --every 3 --pc2 out/anim.pc2. The
folder must then hold exactly anim.pc2 and anim.obj (no temporary file). The PC2 file is read
back by scripts/pc2.py: header "POINTCACHE2\\0", version 1, numPoints = every particle of both cloths,
startFrame 0, sampleRate 3, numSamples 3 (frames 0, 3 and 6: every 3·i <= 6, the rule of --obj),
and its size must be the header plus exactly those samples.

Sample 0 must equal the rest OBJ's v lines and the scene's initial grids; the last sample is the
state after all 6 frames, equal to the same run's --dump (one run, one last state). The cache
holds float32 and the text files print float32 with "%.9g", which round-trips exactly: each text
number is rounded to float32 and the comparison is exact equality, not a tolerance. A run with
both --obj and --pc2 must give sample i equal to frame_000i.obj, for every i (5 samples for 4
frames). --frames 0 writes one sample, the start.

Bad input: exit status 2, exactly one line on stderr (compared whole), nothing on stdout, and the
working directory as it was (no folder, no cache, no OBJ, no --dump file, no temporary file).
"""
import json
import os
import struct
import sys
import tempfile

import tooltest

sys.path.insert(0, os.path.join(tooltest.ROOT, "scripts"))
import pc2  # noqa: E402 (scripts/pc2.py, the one PC2 reader)

[SIM] = tooltest.tool_paths("clothvk-sim")

# The scene of test_obj.py: "flag" hangs from two corners, the second cloth lies flat.
CLOTHS = [
    {"name": "flag", "grid": [6, 5], "size": [0.5, 0.4], "origin": [0.0, 1.0, 0.0],
     "u_axis": [1, 0, 0], "v_axis": [0, -1, 0], "mass": 0.1,
     "stiffness": {"structural": 1e4, "shear": 1e3, "bend": 10}, "pins": [[0, 0], [5, 0]]},
    {"grid": [4, 3], "size": [0.3, 0.2], "origin": [1.0, 1.0, 0.0],
     "u_axis": [0, 0, 1], "v_axis": [1, 0, 0], "mass": 0.05,
     "stiffness": {"structural": 1e4, "shear": 0, "bend": 0}, "pins": [[0, 0]]},
]
POINTS = sum(c["grid"][0] * c["grid"][1] for c in CLOTHS)
SCENE_TEXT = json.dumps({"name": "two-cloths", "dt": 0.002, "substeps": 4, "frames": 10,
                         "solver": {"linear": "rbgs", "outer_iterations": 2, "inner_iterations": 2},
                         "cloths": CLOTHS}, indent=2)
DUMP = "out.csv"


def error(message):
    return tooltest.tool_line("clothvk-sim", message)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def grid_positions(cloth):
    """Particle [i, j] at origin + i·du·u + j·dv·v, row by row (i fastest)."""
    (nu, nv), (su, sv) = cloth["grid"], cloth["size"]
    du, dv = su / (nu - 1), sv / (nv - 1)
    return [[o + i * du * a + j * dv * b for o, a, b in zip(cloth["origin"], cloth["u_axis"], cloth["v_axis"])]
            for j in range(nv) for i in range(nu)]


# ---- reading the files ----


def read_pc2(path):
    """(header fields, samples as lists of [x, y, z], problems), by scripts/pc2.py."""
    try:
        header, flat = pc2.read(path)
    except pc2.Pc2Error as e:
        return None, [], [str(e)]
    return header, [[list(s[i:i + 3]) for i in range(0, len(s), 3)] for s in flat], []


def obj_positions(path):
    with open(path) as f:
        return [[f32(float(x)) for x in line.split()[1:]] for line in f if line.startswith("v ")]


def read_csv(path):
    return tooltest.read_csv(path, f32)


def check_header(header, samples, rate):
    expected = (b"POINTCACHE2\0", 1, POINTS, 0.0, float(rate), samples)
    return [] if header == expected else [f"header {header}, expected {expected}"]


# ---- runs ----


def run(argv, cwd):
    return tooltest.run_tool(SIM, argv, cwd, timeout=120)


def good_run(scene):
    """--frames 6 --every 3: samples 0, 3 and 6; the last equal to the same run's --dump."""
    with tempfile.TemporaryDirectory(prefix="clothvk-pc2-") as workdir:
        p = run([scene, "--frames", "6", "--every", "3", "--pc2", "out/anim.pc2", "--dump", DUMP], workdir)
        if p.returncode != 0 or p.stderr:
            return [f"exit status {p.returncode}, stderr: {p.stderr.strip()}"]
        problems = []
        summary = (f"  PC2 out/anim.pc2: 3 samples of {POINTS} points (frames 0 to 6 of 6, every 3), "
                   "rest mesh out/anim.obj")
        if summary not in p.stdout.splitlines():
            problems.append(f"no summary line {summary!r} in:\n{p.stdout}")
        found = sorted(os.listdir(os.path.join(workdir, "out")))
        if found != ["anim.obj", "anim.pc2"]:
            return problems + [f"out holds {found}, expected anim.obj and anim.pc2"]
        header, samples, more = read_pc2(os.path.join(workdir, "out", "anim.pc2"))
        problems += more + check_header(header, 3, 3)
        if problems:
            return problems
        rest = obj_positions(os.path.join(workdir, "out", "anim.obj"))
        if rest != samples[0]:
            problems.append(f"sample 0 differs from anim.obj's v lines by {tooltest.worst(rest, samples[0]):.3g} m "
                            f"({len(samples[0])} and {len(rest)} positions)")
        gap = tooltest.worst(samples[0], [p for c in CLOTHS for p in grid_positions(c)])
        if gap > 1e-6:
            problems.append(f"sample 0 differs from the initial grids by {gap:.3g} m")
        if samples[0] == samples[2]:
            problems.append("samples 0 and 2 are equal: the cloths did not move")
        dumped = read_csv(os.path.join(workdir, DUMP))
        if dumped != samples[2]:
            gap = tooltest.worst(dumped, samples[2])
            problems.append(f"sample 2 differs from the same run's --dump by {gap:.3g} m "
                            f"({len(samples[2])} and {len(dumped)} positions)")
        return problems


def with_obj(scene):
    """--frames 4 with --obj and --pc2, --every left out: sample i equals frame_000i.obj."""
    with tempfile.TemporaryDirectory(prefix="clothvk-pc2-") as workdir:
        p = run([scene, "--frames", "4", "--obj", "frames", "--pc2", "anim.pc2"], workdir)
        if p.returncode != 0 or p.stderr:
            return [f"exit status {p.returncode}, stderr: {p.stderr.strip()}"]
        header, samples, problems = read_pc2(os.path.join(workdir, "anim.pc2"))
        problems += check_header(header, 5, 1)
        for i, sample in enumerate(samples):
            frame = obj_positions(os.path.join(workdir, "frames", f"frame_{i:04d}.obj"))
            if frame != sample:
                problems.append(f"sample {i} differs from frame_{i:04d}.obj by {tooltest.worst(frame, sample):.3g} m")
        return problems


def no_frames(scene):
    """--frames 0 and a name without an extension: a cache of one sample (the start, equal to
    NAME.obj's v lines), and NAME.obj."""
    with tempfile.TemporaryDirectory(prefix="clothvk-pc2-") as workdir:
        p = run([scene, "--frames", "0", "--pc2", "cache"], workdir)
        if p.returncode != 0 or p.stderr:
            return [f"exit status {p.returncode}, stderr: {p.stderr.strip()}"]
        found = tooltest.listing(workdir)
        if found != ["cache", "cache.obj"]:
            return [f"expected cache and cache.obj, found {found}"]
        header, samples, problems = read_pc2(os.path.join(workdir, "cache"))
        problems += check_header(header, 1, 1)
        if not problems and samples[0] != obj_positions(os.path.join(workdir, "cache.obj")):
            problems.append("the one sample of --frames 0 differs from cache.obj")
        line = f"  PC2 cache: 1 sample of {POINTS} points (frames 0 to 0 of 0, every 1), rest mesh cache.obj"
        return problems + ([] if line in p.stdout.splitlines() else [f"no line {line!r} in:\n{p.stdout}"])


def bad_cases(scene):
    cases = [
        ("--pc2 without a name", [scene, "--pc2"], [], error("--pc2: expected a file name")),
        ("--pc2 with an empty name", [scene, "--pc2", ""], [], error("--pc2: expected a file name")),
        ("--every without --obj or --pc2", [scene, "--every", "2"], [],
         error("--every needs --obj DIR, --pc2 FILE or --bake DIR (it says which frames go out)")),
        ("--every 0", [scene, "--pc2", "a.pc2", "--every", "0"], [],
         error("--every: expected a whole number from 1 to 100000000, got 0")),
        ("name ending in .obj", [scene, "--pc2", "anim.obj"], [],
         error("--pc2 anim.obj: the rest mesh goes to the same name with .obj, so the cache needs "
               "another extension (.pc2)")),
        ("name of a folder", [scene, "--pc2", "taken"], ["taken/"],
         error("--pc2 taken: is a folder; expected a file name (FILE.pc2)")),
        ("name ending in /", [scene, "--pc2", "out/"], [],
         error("--pc2 out/: is a folder; expected a file name (FILE.pc2)")),
        ("rest mesh name of a folder", [scene, "--pc2", "anim.pc2"], ["anim.obj/"],
         error("--pc2 anim.pc2: the rest mesh anim.obj is a folder")),
        ("folder is a file", [scene, "--pc2", "taken/anim.pc2"], ["taken"],
         error("taken: exists and is not a folder")),
        ("--dump to a device", [scene, "--dump", "/dev/null"], [],
         error("--dump /dev/null: exists and is not a regular file (a device or socket); it is "
               "not replaced")),
        ("--pc2 with --resume", [scene, "--pc2", "a.pc2", "--resume", "bake"], [],
         error("--pc2 and --resume: a point cache holds a whole run; write it with --bake or a "
               "plain run")),
        ("bad scene", [scene, "--pc2", "out/anim.pc2", "--set", "cloths.0.mass=0"], [],
         error(f"{scene}: cloths.0.mass (from --set): must be greater than 0, got 0")),
    ]
    locked = tooltest.locked_folder()
    if locked:
        folder, files, reason = locked
        cases.append(("folder not writable", [scene, "--pc2", f"{folder}/anim.pc2"], files,
                      error(f"{folder}: cannot write into the output folder: {reason}")))
    return cases


def run_bad(argv, files, expected):
    """files: see tooltest.make_files."""
    # --dump goes before the options under test: some of them take the last argument.
    return tooltest.refused_run(SIM, argv[:1] + ["--dump", DUMP] + argv[1:], expected, files, "clothvk-pc2-")


def main():
    cases = tooltest.Cases("pc2")
    with tempfile.TemporaryDirectory(prefix="clothvk-pc2-scene-") as scene_dir:
        scene = os.path.join(scene_dir, "two-cloths.json")
        with open(scene, "w") as f:
            f.write(SCENE_TEXT)
        checks = [("samples 0, 3 and 6 of 6, every 3", lambda: good_run(scene)),
                  ("--obj and --pc2 together", lambda: with_obj(scene)),
                  ("--frames 0", lambda: no_frames(scene))]
        checks += [(name, (lambda a=argv, fs=files, e=expected: run_bad(a, fs, e)))
                   for name, argv, files, expected in bad_cases(scene)]
        return cases.run(checks)


if __name__ == "__main__":
    sys.exit(main())
