#!/usr/bin/env python3
"""clothvk-sim --obj DIR [--every K]: the OBJ frames a user hands to another tool.

    python3 tests/tools/test_obj.py PATH/TO/clothvk-sim

Good input: a scene of two grid cloths (one named, one not) is run with --frames 6 --every 3.
The files must be DIR/frame_0000.obj to frame_0002.obj (file i holds the state after 3·i frames,
for every 3·i <= 6: the start, then every third simulated frame up to the last) and nothing else.
Every file must parse: one header comment, then per cloth "o NAME", one "v" and one "vn" line per
particle and one "f a//a b//b c//c" line per triangle, numbered from 1 over the whole file, the
triangles of a grid cell being (a, b, c), (b, d, c) with a = [i, j], b = [i+1, j], c = [i, j+1],
d = [i+1, j+1], row by row. Normals must be unit vectors and equal the area-weighted average of
the triangles' normals, computed here from the file's own positions. Frame 0 must be the scene's
initial grid.

The last file is the state after all 6 frames, the one --dump of the same run writes: one run has
one last state. Both files print the same float32 with "%.9g", which round-trips a float32
exactly, so the comparison is exact equality, not a tolerance. With --frames 7 --every 3 the files
are the same three (7 is not a multiple of 3) and --dump holds the state after 7: row for row the
--dump of a plain --frames 7 run. --frames 0 writes frame_0000.obj alone, the start.

Bad input: exit status 2, exactly one line on stderr (compared whole), nothing on stdout, and the
working directory as it was (no output folder, no OBJ file, no --dump file, no temporary file).
"""
import json
import math
import os
import re
import sys
import tempfile

import tooltest

[SIM] = tooltest.tool_paths("clothvk-sim")

# Two grid cloths: "flag" hangs from two corners in the x-y plane (its front, u × v, faces −z);
# the second has no name ("cloth1") and lies flat, pinned at one corner (its front faces +y).
CLOTHS = [
    {"name": "flag", "grid": [6, 5], "size": [0.5, 0.4], "origin": [0.0, 1.0, 0.0],
     "u_axis": [1, 0, 0], "v_axis": [0, -1, 0], "mass": 0.1,
     "stiffness": {"structural": 1e4, "shear": 1e3, "bend": 10}, "pins": [[0, 0], [5, 0]]},
    {"grid": [4, 3], "size": [0.3, 0.2], "origin": [1.0, 1.0, 0.0],
     "u_axis": [0, 0, 1], "v_axis": [1, 0, 0], "mass": 0.05,
     "stiffness": {"structural": 1e4, "shear": 0, "bend": 0}, "pins": [[0, 0]]},
]
NAMES = ["flag", "cloth1"]
FRONTS = [(0.0, 0.0, -1.0), (0.0, 1.0, 0.0)]
SCENE_TEXT = json.dumps({"name": "two-cloths", "dt": 0.002, "substeps": 4, "frames": 10,
                         "solver": {"linear": "rbgs", "outer_iterations": 2, "inner_iterations": 2},
                         "cloths": CLOTHS}, indent=2)

DUMP = "out.csv"
EVERY_MESSAGE = "--every: expected a whole number from 1 to 100000000, got "


def error(message):
    return tooltest.tool_line("clothvk-sim", message)


# ---- what the scene should give ----


def grid_positions(cloth):
    """Particle [i, j] at origin + i·du·u + j·dv·v, row by row (i fastest)."""
    (nu, nv), (su, sv) = cloth["grid"], cloth["size"]
    u, v = normalised(cloth["u_axis"]), normalised(cloth["v_axis"])
    du, dv = su / (nu - 1), sv / (nv - 1)
    return [[o + i * du * a + j * dv * b for o, a, b in zip(cloth["origin"], u, v)]
            for j in range(nv) for i in range(nu)]


def grid_triangles(cloth, first):
    """(a, b, c), (b, d, c) per cell, row by row, as 1-based file vertex numbers."""
    nu, nv = cloth["grid"]
    out = []
    for j in range(nv - 1):
        for i in range(nu - 1):
            a = first + 1 + j * nu + i
            b, c = a + 1, a + nu
            out += [(a, b, c), (b, c + 1, c)]
    return out


def normalised(x):
    n = math.sqrt(sum(c * c for c in x))
    return [c / n for c in x]


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def area_weighted_normals(positions, faces):
    """The plain sum of (v1 − v0) × (v2 − v0) over each vertex's triangles, normalised."""
    total = [[0.0, 0.0, 0.0] for _ in positions]
    for face in faces:
        p = [positions[k - 1] for k in face]
        n = cross(sub(p[1], p[0]), sub(p[2], p[0]))
        for k in face:
            total[k - 1] = [s + c for s, c in zip(total[k - 1], n)]
    return [normalised(n) if any(n) else [0.0, 0.0, 0.0] for n in total]


# ---- reading the files ----


def parse_obj(path):
    """(header, objects, positions, normals, problems); objects: [name, v, vn, faces] each, where
    v and vn count that object's lines and faces are 1-based vertex triples."""
    problems, objects, positions, normals = [], [], [], []
    with open(path) as f:
        lines = f.read().splitlines()
    header = lines[0] if lines else ""
    if not header.startswith("# "):
        problems.append(f"the first line is not a comment: {header!r}")
    for n, line in enumerate(lines[1:], 2):
        words = line.split(" ")
        kind, rest = words[0], words[1:]
        if kind == "o" and len(rest) == 1:
            objects.append([rest[0], 0, 0, []])
        elif not objects:
            problems.append(f"line {n} comes before the first object: {line!r}")
            break
        elif kind in ("v", "vn") and len(rest) == 3:
            try:
                xyz = [float(x) for x in rest]
            except ValueError:
                xyz = [math.nan]
            if not all(math.isfinite(x) for x in xyz):
                problems.append(f"line {n} is not three finite numbers: {line!r}")
            (positions if kind == "v" else normals).append(xyz)
            objects[-1][1 if kind == "v" else 2] += 1
        elif kind == "f" and len(rest) == 3 and all(re.fullmatch(r"([0-9]+)//\1", w) for w in rest):
            objects[-1][3].append(tuple(int(w.split("//")[0]) for w in rest))
        else:
            problems.append(f"line {n} is not an o, v, vn or f line of the expected form: {line!r}")
    return header, objects, positions, normals, problems


def read_positions(path):
    """The v lines of an OBJ file, as floats."""
    return parse_obj(path)[2]


def check_frame(path, frame):
    """Problems with one OBJ file of the two-cloth scene at `frame` frames."""
    name = os.path.basename(path)
    header, objects, positions, normals, problems = parse_obj(path)
    problems = [f"{name}: {p}" for p in problems]
    if problems:
        return problems, positions
    expected_header = f"# clothvk-sim: scene two-cloths, frame {frame} "
    if not header.startswith(expected_header):
        problems.append(f"{name}: header {header!r} does not start with {expected_header!r}")
    if [o[0] for o in objects] != NAMES:
        problems.append(f"{name}: objects {[o[0] for o in objects]}, expected {NAMES}")
        return problems, positions
    first = 0
    for cloth, (obj, verts, vns, faces) in zip(CLOTHS, objects):
        count = cloth["grid"][0] * cloth["grid"][1]
        if (verts, vns) != (count, count):
            problems.append(f"{name}: {obj} has {verts} v and {vns} vn lines, expected {count} of each")
        expected = grid_triangles(cloth, first)
        if faces != expected:
            problems.append(f"{name}: {obj} has {len(faces)} faces, expected the {len(expected)} grid "
                            f"triangles; first faces {faces[:3]}, expected {expected[:3]}")
        first += count
    if problems:
        return problems, positions
    faces = [f for o in objects for f in o[3]]
    lengths = [math.sqrt(sum(c * c for c in n)) for n in normals]
    off = max(abs(x - 1.0) for x in lengths)
    if off > 1e-6:
        problems.append(f"{name}: a normal's length is off 1 by {off:.3g}")
    gap = tooltest.worst(normals, area_weighted_normals(positions, faces))
    if gap > 1e-5:
        problems.append(f"{name}: normals differ from the area-weighted triangle normals by {gap:.3g}")
    return problems, positions


def check_frame_zero(positions, normals_path):
    """Frame 0 is the scene's grid, its normals the grids' front sides."""
    problems = []
    expected = [p for c in CLOTHS for p in grid_positions(c)]
    gap = tooltest.worst(positions, expected)
    if len(positions) != len(expected) or gap > 1e-6:
        problems.append(f"frame_0000.obj: positions differ from the initial grids by {gap:.3g} m")
    _, _, _, normals, _ = parse_obj(normals_path)
    fronts = [FRONTS[k] for k, c in enumerate(CLOTHS) for _ in range(c["grid"][0] * c["grid"][1])]
    gap = tooltest.worst(normals, fronts)
    if gap > 1e-6:
        problems.append(f"frame_0000.obj: normals differ from the cloths' front sides u × v by {gap:.3g}")
    return problems


# ---- runs ----


def run(argv, cwd):
    return tooltest.run_tool(SIM, argv, cwd, timeout=120)


def good_run(scene):
    """--frames 6 --every 3: three files, the last equal to the same run's --dump; --frames 7
    --every 3: the same three, and the --dump of a plain --frames 7 run."""
    with tempfile.TemporaryDirectory(prefix="clothvk-obj-") as workdir:
        p = run([scene, "--frames", "6", "--every", "3", "--obj", "out/frames", "--dump", DUMP], workdir)
        if p.returncode != 0 or p.stderr:
            return [f"exit status {p.returncode}, stderr: {p.stderr.strip()}"]
        problems = []
        summary = "  3 OBJ files in out/frames (frames 0 to 6 of 6, every 3)"
        if summary not in p.stdout.splitlines():
            problems.append(f"no summary line {summary!r} in:\n{p.stdout}")
        folder = os.path.join(workdir, "out", "frames")
        names = [f"frame_{i:04d}.obj" for i in range(3)]
        found = sorted(os.listdir(folder))
        if found != names:
            return problems + [f"out/frames holds {found}, expected {names}"]
        frames = []
        for i, name in enumerate(names):
            more, positions = check_frame(os.path.join(folder, name), 3 * i)
            problems += more
            frames.append(positions)
        if problems:
            return problems
        problems += check_frame_zero(frames[0], os.path.join(folder, names[0]))
        if frames[0] == frames[2]:
            problems.append("frames 0 and 6 have the same positions: the cloths did not move")
        dumped = tooltest.read_csv(os.path.join(workdir, DUMP))
        if dumped != frames[2]:
            gap = tooltest.worst(dumped, frames[2])
            problems.append(f"frame_0002.obj differs from the same run's --dump by {gap:.3g} m "
                            f"({len(frames[2])} and {len(dumped)} positions)")
        p = run([scene, "--frames", "7", "--every", "3", "--obj", "seven", "--dump", "seven.csv"], workdir)
        if p.returncode != 0 or p.stderr:
            return problems + [f"the 7-frame run failed ({p.returncode}): {p.stderr.strip()}"]
        found = sorted(os.listdir(os.path.join(workdir, "seven")))
        if found != names:
            problems.append(f"--frames 7 --every 3 wrote {found}, expected {names}")
        elif read_positions(os.path.join(workdir, "seven", names[2])) != frames[2]:
            problems.append("--frames 7 --every 3: frame_0002.obj is not the state after 6 frames")
        seven = tooltest.read_csv(os.path.join(workdir, "seven.csv"))
        if seven == frames[2]:
            problems.append("the 7-frame --dump equals frame 6: --obj changed how far the run went")
        p = run([scene, "--frames", "7", "--dump", "plain.csv"], workdir)
        if p.returncode != 0 or p.stderr:
            return problems + [f"the plain 7-frame run failed ({p.returncode}): {p.stderr.strip()}"]
        rows = []
        for name in ("seven.csv", "plain.csv"):
            with open(os.path.join(workdir, name)) as f:
                rows.append(f.read().splitlines())
        if rows[0] != rows[1]:
            plain = tooltest.read_csv(os.path.join(workdir, "plain.csv"))
            gap = tooltest.worst(seven, plain)
            problems.append(f"the 7-frame --dump with --obj differs from a plain --frames 7 --dump "
                            f"by {gap:.3g} m ({len(seven)} and {len(plain)} positions)")
        return problems


def no_frames(scene):
    """--frames 0: the folder is made and holds the start, frame_0000.obj, equal to --dump."""
    with tempfile.TemporaryDirectory(prefix="clothvk-obj-") as workdir:
        p = run([scene, "--frames", "0", "--obj", "none", "--dump", "zero.csv"], workdir)
        if p.returncode != 0 or p.stderr:
            return [f"exit status {p.returncode}, stderr: {p.stderr.strip()}"]
        found = tooltest.listing(workdir)
        expected = ["none", "none/frame_0000.obj", "zero.csv"]
        if found != expected:
            return [f"expected {expected}, found {found}"]
        problems = []
        if read_positions(os.path.join(workdir, "none", "frame_0000.obj")) != \
                tooltest.read_csv(os.path.join(workdir, "zero.csv")):
            problems.append("frame_0000.obj of --frames 0 differs from its --dump")
        line = "  1 OBJ file in none (frames 0 to 0 of 0, every 1)"
        return problems + ([] if line in p.stdout.splitlines() else [f"no line {line!r} in:\n{p.stdout}"])


def bad_cases(scene):
    cases = [
        ("--obj without a folder", [scene, "--obj"], [], error("--obj: expected an output folder")),
        ("--obj with an empty name", [scene, "--obj", ""], [], error("--obj: expected an output folder")),
        ("--every 0", [scene, "--obj", "out", "--every", "0"], [], error(EVERY_MESSAGE + "0")),
        ("--every not a number", [scene, "--obj", "out", "--every", "often"], [], error(EVERY_MESSAGE + "often")),
        ("--every negative", [scene, "--obj", "out", "--every", "-2"], [], error(EVERY_MESSAGE + "-2")),
        ("--every without a value", [scene, "--obj", "out", "--every"], [], error(EVERY_MESSAGE + "nothing")),
        ("--every without --obj", [scene, "--every", "2"], [],
         error("--every needs --obj DIR, --pc2 FILE or --bake DIR (it says which frames go out)")),
        ("folder is a file", [scene, "--obj", "taken"], ["taken"], error("taken: exists and is not a folder")),
        ("folder under a file", [scene, "--obj", "taken/frames"], ["taken"],
         error("taken/frames: cannot create the output folder: Not a directory")),
        ("bad scene", [scene, "--obj", "out", "--set", "cloths.0.mass=0"], [],
         error(f"{scene}: cloths.0.mass (from --set): must be greater than 0, got 0")),
    ]
    locked = tooltest.locked_folder()
    if locked:
        folder, files, reason = locked
        cases.append(("folder not writable", [scene, "--obj", folder], files,
                      error(f"{folder}: cannot write into the output folder: {reason}")))
    return cases


def run_bad(argv, files, expected):
    """files: see tooltest.make_files."""
    # --dump goes before the options under test: some of them take the last argument.
    return tooltest.refused_run(SIM, argv[:1] + ["--dump", DUMP] + argv[1:], expected, files, "clothvk-obj-")


def main():
    cases = tooltest.Cases("obj")
    with tempfile.TemporaryDirectory(prefix="clothvk-obj-scene-") as scene_dir:
        scene = os.path.join(scene_dir, "two-cloths.json")
        with open(scene, "w") as f:
            f.write(SCENE_TEXT)
        checks = [("frames 0, 3 and 6 of 6, every 3", lambda: good_run(scene)),
                  ("--frames 0", lambda: no_frames(scene))]
        checks += [(name, (lambda a=argv, fs=files, e=expected: run_bad(a, fs, e)))
                   for name, argv, files, expected in bad_cases(scene)]
        return cases.run(checks)


if __name__ == "__main__":
    sys.exit(main())
