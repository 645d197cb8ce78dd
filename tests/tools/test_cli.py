#!/usr/bin/env python3
"""clothvk-sim as a person meets it: exact messages and exit statuses for bad input, and the
output of --plan, --json and --dump for good input.

    python3 tests/tools/test_cli.py PATH/TO/clothvk-sim

Every run has a fresh temporary directory as its working directory. A bad-input case is run
with "--dump out.csv" added; it must exit with status 2, print exactly one line on stderr
(compared whole), print nothing on stdout, and leave the directory empty (no out.csv, no
out.csv.tmp-XXXXXX). A good case must exit with status 0, print nothing on stderr (validation
messages included) and pass its own check of stdout and of the files it wrote.

The scene files the cases need are in tests/scenes/, one problem each. Messages start with the
scene path exactly as it was passed, so the expected lines are built from that path plus the
literal text of the message.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

import tooltest

[SIM] = tooltest.tool_paths("clothvk-sim")
ROOT = tooltest.ROOT


def scene(name):
    return os.path.join(ROOT, "tests", "scenes", name)


def asset(name):
    return os.path.join(ROOT, "assets", "scenes", name)


def error(path, message):
    """The line clothvk-sim prints for a problem in the scene at path."""
    return tooltest.tool_line("clothvk-sim", f"{path}: {message}")


SMALL = scene("small.json")  # valid: 4 x 3 grid, pins [0,0] and [3,0], u_axis [0,0,2]
CROSSING = scene("crossing.json")  # two 11 x 11 cloths crossing each other, with self-contact
EDGES_NOTE = "clothvk-sim: note: collision.edges has no effect: edge-edge contact is always on"
ROPE = scene("rope.json")    # valid: 1 x 20 grid, pinned at [0,0]
HANGING = asset("hanging.json")
STENCIL = asset("hanging-stencil.json")
DUMP = "out.csv"

# Stands for lavapipe's device name in an expected line (see tooltest.line_matches).
LLVMPIPE = tooltest.LLVMPIPE

# ---- checks of the good cases' output: each returns a list of problems ----


def output_lines(stdout):
    return stdout.splitlines()


def plan_has(*starts):
    def check(stdout, workdir):
        lines = output_lines(stdout)
        return [f"no line of the plan starts with {s!r}" for s in starts
                if not any(line.startswith(s) for line in lines)]
    return check


def json_contacts(stdout, workdir):
    """--json of a colliding scene: the contact figures, each a count or a length."""
    try:
        c = json.loads(stdout)["contacts"]
    except (ValueError, KeyError, TypeError) as e:
        return [f"no contacts object in the JSON: {e!r}"]
    problems = [f"contacts.{k} is {c.get(k)!r}"
                for k in ("colliders", "self", "intersecting_pairs", "searches")
                if not is_int(c.get(k)) or c.get(k) < 0]
    if not is_number(c.get("max_penetration")) or c["max_penetration"] < 0:
        problems.append(f"contacts.max_penetration is {c.get('max_penetration')!r}")
    if not problems and c["colliders"] == 0:
        problems.append("the cloth lies on the ground after 40 frames, yet no collider contact")
    if not problems and not 1 <= c["searches"] < 40 * 8:
        problems.append(f"{c['searches']} detections in 40 frames of 8 substeps: the cloth "
                        "comes to rest on the ground, so fewer than one a substep, at least one")
    return problems


def json_pairs(ok, what):
    """--json: contacts.intersecting_pairs passes ok(n)."""
    def check(stdout, workdir):
        try:
            n = json.loads(stdout)["contacts"]["intersecting_pairs"]
        except (ValueError, KeyError, TypeError) as e:
            return [f"no contacts.intersecting_pairs in the JSON: {e!r}"]
        return [] if is_int(n) and ok(n) else [f"contacts.intersecting_pairs is {n!r}; expected {what}"]
    return check


def json_notes(expected):
    """--json: "notes" is exactly `expected`."""
    def check(stdout, workdir):
        problems = []
        stats = parse_json(stdout, problems)
        if stats is not None and stats.get("notes") != expected:
            problems.append(f"notes is {stats.get('notes')!r}, expected {expected!r}")
        return problems
    return check


def json_every_pass(*names):
    """--json lists every pass of the frame: the named ones among them, the passes' dispatches
    summing to the frame's and (where timed) their GPU times to the frame's."""
    def check(stdout, workdir):
        problems = []
        stats = parse_json(stdout, problems)
        if problems:
            return problems
        listed = [p["name"] for p in stats["passes"]]
        problems += [f"passes: no {n!r} in {listed}" for n in names if n not in listed]
        dispatches = sum(p["dispatches"] for p in stats["passes"])
        if dispatches != stats["dispatches_per_frame"]:
            problems.append(f"passes: {dispatches} dispatches listed, the frame has "
                            f"{stats['dispatches_per_frame']} ({listed})")
        frame = stats["gpu_ms_per_frame"]
        if frame is not None:
            timed = sum(p["gpu_ms"] for p in stats["passes"])
            if abs(timed - frame) > 1e-6 * frame + 1e-9:
                problems.append(f"passes: {timed} GPU ms listed, the frame took {frame}")
        return problems
    return check


def json_all(*checks):
    return lambda stdout, workdir: [p for c in checks for p in c(stdout, workdir)]


def is_int(v):
    return isinstance(v, int) and not isinstance(v, bool)


def is_number(v):
    return (isinstance(v, (int, float)) and not isinstance(v, bool)) and math.isfinite(v)


def is_time(v):
    """GPU times are null on a device without timestamp queries."""
    return v is None or is_number(v)


def check_types(where, obj, types, problems):
    if not isinstance(obj, dict):
        problems.append(f"{where or 'the output'} is not a JSON object")
        return
    for key, kind in types.items():
        name = f"{where}.{key}" if where else key
        if key not in obj:
            problems.append(f"{name} is missing")
        elif not kind(obj[key]):
            problems.append(f"{name} has the wrong type: {obj[key]!r}")


def parse_json(stdout, problems):
    try:
        return json.loads(stdout)
    except ValueError as e:
        problems.append(f"stdout is not one JSON object: {e}")
        return None


def json_stats(particles, structural, frames, linear=None):
    def check(stdout, workdir):
        problems = []
        stats = parse_json(stdout, problems)
        if stats is None:
            return problems
        check_types("", stats, {
            "scene": lambda v: isinstance(v, str), "particles": is_int, "springs": lambda v: True,
            "frames": is_int, "substeps": is_int, "solver": lambda v: True, "residual": is_number,
            "max_stretch": is_number, "p99_stretch": is_number, "torn_springs": is_int,
            "nan_count": is_int, "gpu_ms_per_frame": is_time,
            "wall_ms_per_frame": is_number, "dispatches_per_frame": is_int,
            "passes": lambda v: isinstance(v, list) and len(v) > 0}, problems)
        if problems:
            return problems
        check_types("springs", stats["springs"], {"structural": is_int, "shear": is_int, "bend": is_int},
                    problems)
        check_types("solver", stats["solver"], {
            "method": lambda v: isinstance(v, str), "linear": lambda v: isinstance(v, str),
            "outer_iterations": is_int, "inner_iterations": is_int, "omega": is_number}, problems)
        for i, p in enumerate(stats["passes"]):
            check_types(f"passes.{i}", p, {"name": lambda v: isinstance(v, str), "gpu_ms": is_time}, problems)
        if problems:
            return problems
        expected = {"particles": (stats["particles"], particles),
                    "springs.structural": (stats["springs"]["structural"], structural),
                    "frames": (stats["frames"], frames), "nan_count": (stats["nan_count"], 0),
                    "torn_springs": (stats["torn_springs"], 0),
                    "diverged": (stats.get("diverged"), False)}
        if linear:
            expected["solver.linear"] = (stats["solver"]["linear"], linear)
        for key, (got, want) in expected.items():
            if got != want:
                problems.append(f"{key}: expected {want!r}, got {got!r}")
        return problems
    return check


def json_torn(least, most):
    """--json of a tearing run: torn_springs within [least, most] and a tear pass timed."""
    def check(stdout, workdir):
        problems = []
        stats = parse_json(stdout, problems)
        if stats is None:
            return problems
        torn = stats.get("torn_springs")
        if not is_int(torn) or not least <= torn <= most:
            problems.append(f"torn_springs: expected {least} to {most}, got {torn!r}")
        if "tear" not in [p.get("name") for p in stats.get("passes", [])]:
            problems.append("no \"tear\" pass in passes")
        return problems
    return check


def read_dump(workdir, problems):
    """The dump's rows as float triples; problems for anything else in workdir or in the file."""
    names = sorted(os.listdir(workdir))
    if names != [DUMP]:
        problems.append(f"expected only {DUMP} in the working directory, found {names}")
    path = os.path.join(workdir, DUMP)
    if not os.path.exists(path):
        return []
    rows = []
    with open(path) as f:
        for n, line in enumerate(f.read().splitlines(), 1):
            try:
                row = [float(x) for x in line.split(",")]
            except ValueError:
                row = []
            if len(row) != 3 or not all(math.isfinite(x) for x in row):
                problems.append(f"{DUMP} line {n} is not three finite numbers: {line!r}")
            rows.append(row)
    return rows


def close(a, b):
    return len(a) == len(b) and all(abs(x - y) <= 1e-5 * (1 + abs(y)) for x, y in zip(a, b))


def dump_grid(scene_path, first_two_at_rest, grid=None):
    """--dump of a one-cloth scene: one row per particle in grid order (i along u fastest). The
    first row is particle [0,0]: at the origin before any step, and also later when it is pinned.
    With first_two_at_rest, the second row is particle [1,0], one spacing along u from it. grid:
    the grid a --set gave in place of the scene file's."""
    with open(scene_path) as f:
        cloth = json.load(f)["cloths"][0]
    grid = grid or cloth["grid"]
    size, origin, u = cloth["size"], cloth["origin"], cloth.get("u_axis", [1, 0, 0])
    length = math.sqrt(sum(c * c for c in u))
    spacing = size[0] / (grid[0] - 1) if grid[0] > 1 else 0.0
    second = [o + spacing * c / length for o, c in zip(origin, u)]

    def check(stdout, workdir):
        problems = []
        rows = read_dump(workdir, problems)
        if len(rows) != grid[0] * grid[1]:
            problems.append(f"{DUMP}: expected {grid[0] * grid[1]} lines, got {len(rows)}")
        if rows and not close(rows[0], origin):
            problems.append(f"{DUMP} line 1: expected the origin {origin}, got {rows[0]}")
        if first_two_at_rest and len(rows) > 1 and not close(rows[1], second):
            problems.append(f"{DUMP} line 2: expected {second} (one spacing along u), got {rows[1]}")
        return problems
    return check


# ---- the cases ----
# status 2: stderr is the exact line; the runner adds --dump out.csv and checks nothing is written.
# status 0: stderr must be empty; check (if any) looks at stdout and the working directory.

CASES = [
    # The scene file itself.
    {"name": "missing file", "argv": [scene("no-such-file.json")], "status": 2,
     "stderr": error(scene("no-such-file.json"), "cannot open: No such file or directory")},
    {"name": "malformed JSON", "argv": [scene("malformed.json")], "status": 2,
     # line 4, column 10: the end of the token after which jansson gave up
     "stderr": "clothvk-sim: " + scene("malformed.json") + ":4:10: malformed JSON: '}' expected near '\"cloths\"'"},
    {"name": "unknown top-level key", "argv": [scene("unknown-key.json")], "status": 2,
     "stderr": error(scene("unknown-key.json"), "gravityy: unknown key (expected one of: name, dt, substeps, "
                     "frames, integrate, gravity, damping, solver, cloths, render, collision, colliders, attachments, wind, air_density, instances)")},
    {"name": "unknown nested key", "argv": [scene("unknown-nested-key.json")], "status": 2,
     "stderr": error(scene("unknown-nested-key.json"), "solver.iterationz: unknown key (expected one of: method, "
                     "linear, outer_iterations, inner_iterations, omega, chebyshev_rho, chebyshev_delay, tolerance, max_iterations, kd, integrator, damping_model, tether_every, strain_limit, fuse)")},
    {"name": "unknown nested key via --set", "argv": [SMALL, "--set", "solver.iterationz=8"], "status": 2,
     "stderr": error(SMALL, "solver.iterationz (from --set): unknown key (expected one of: method, "
                     "linear, outer_iterations, inner_iterations, omega, chebyshev_rho, chebyshev_delay, tolerance, max_iterations, kd, integrator, damping_model, tether_every, strain_limit, fuse)")},
    # Fused sweeps: a mode that does not exist.
    {"name": "unknown fuse mode", "argv": [SMALL, "--set", 'solver.fuse="maybe"'],
     "status": 2,
     "stderr": error(SMALL, 'solver.fuse (from --set): unknown fuse mode "maybe" (expected auto, '
                     'on or off)')},
    {"name": "fuse mode not a string", "argv": [SMALL, "--set", "solver.fuse=1"],
     "status": 2,
     "stderr": error(SMALL, "solver.fuse (from --set): expected a string, got the number 1")},
    # Strain limiting: out of range, and with a solver that does not limit strain.
    {"name": "strain limit out of range", "argv": [SMALL, "--set", "solver.strain_limit=11"],
     "status": 2,
     "stderr": error(SMALL, "solver.strain_limit (from --set): must be between 0 and 10, got 11")},
    {"name": "strain limit with gs-cpu",
     "argv": [SMALL, "--set", "solver.strain_limit=0.05", "--set", "solver.linear=\"gs-cpu\""],
     "status": 2,
     "stderr": error(SMALL, "solver.strain_limit (from --set): only the pd solvers on the device "
                     "(rbgs, jacobi, chebyshev) limit strain; this scene uses gs-cpu")},
    # The contact radius against a given thickness (read), and against the default thickness
    # (half of small.json's shortest spring, 0.2 m: known once the simulation is built).
    {"name": "contact radius within the thickness",
     "argv": [SMALL, "--set", "collision.radius=0.001", "--set", "collision.thickness=0.005"],
     "status": 2,
     "stderr": error(SMALL, "collision.radius (from --set): 0.001 is not more than the thickness "
                     "0.005 (contact acts between the thickness and the radius)")},
    {"name": "contact radius within the default thickness",
     "argv": [SMALL, "--set", "collision.radius=0.05", "--set", "collision.self=true"], "status": 2,
     "stderr": error(SMALL, "collision.radius: 0.05 is not more than the thickness 0.1, half the "
                     "shortest structural rest length (contact acts between the thickness and the "
                     "radius)")},
    # Every kind of pass in one plan (the demo with wind, tearing and a convergence check):
    # --json lists all of them, the last ones too.
    {"name": "every pass listed",
     "argv": [asset("demo.json"), "--frames", "1", "--json", "--set", "cloths.0.tethers=0",
              "--set", 'cloths.0.tearing={"max_stretch": 0.5}', "--set",
              'wind={"velocity": [1, 0, 0]}', "--set", "solver.tolerance=0.01"],
     "status": 0,
     "check": json_every_pass("wind", "tear", "convergence", "finalize", "detect faces")},
    {"name": "wrong type", "argv": [scene("wrong-type.json")], "status": 2,
     "stderr": error(scene("wrong-type.json"), "dt: expected a number, got the string \"fast\"")},
    {"name": "negative mass", "argv": [scene("negative-mass.json")], "status": 2,
     "stderr": error(scene("negative-mass.json"), "cloths.0.mass: must be greater than 0, got -0.1")},
    {"name": "zero mass", "argv": [scene("zero-mass.json")], "status": 2,
     "stderr": error(scene("zero-mass.json"), "cloths.0.mass: must be greater than 0, got 0")},
    {"name": "zero mass via --set", "argv": [SMALL, "--set", "cloths.0.mass=0"], "status": 2,
     "stderr": error(SMALL, "cloths.0.mass (from --set): must be greater than 0, got 0")},
    {"name": "grid with a 0 dimension", "argv": [scene("zero-grid.json")], "status": 2,
     "stderr": error(scene("zero-grid.json"), "cloths.0.grid: each dimension must be at least 1, got [0, 10]")},
    {"name": "too many particles for the device",
     "argv": [SMALL, "--set", "cloths.0.grid=[20000,20000]"], "status": 2,
     # lavapipe: maxStorageBufferRange 134217728 bytes / 16 bytes per particle = 8388608.
     "env": {"CLOTHVK_DEVICE": "llvmpipe"},
     "stderr": error(SMALL, f"cloths.0.grid: 400000000 particles are too many for {LLVMPIPE}, which holds at "
                     "most 8388608 (maxStorageBufferRange 134217728 bytes, 16 bytes per particle)")},
    {"name": "pin outside the grid", "argv": [scene("bad-pin.json")], "status": 2,
     "stderr": error(scene("bad-pin.json"), "cloths.0.pins.1: [4, 0] is outside the 4 x 4 grid")},
    {"name": "dt = 0", "argv": [scene("zero-dt.json")], "status": 2,
     "stderr": error(scene("zero-dt.json"), "dt: must be greater than 0, got 0")},
    {"name": "dt < 0", "argv": [scene("negative-dt.json")], "status": 2,
     "stderr": error(scene("negative-dt.json"), "dt: must be greater than 0, got -0.002")},
    # Counts whose products size the plan and the recorded frame, and a dt whose 1/dt² would
    # overflow: refused up front (substeps=1431655765 once overflowed the query count: SIGSEGV).
    # Control characters a user wrote never reach the terminal raw: names refuse them, and
    # messages print them as \xNN (an ESC sequence or a line break forging a line).
    {"name": "control character in the scene name", "argv": [SMALL, "--set", "name=ab\x1b[2Jc"],
     "status": 2,
     "stderr": error(SMALL, "name (from --set): contains the control character \\x1b at byte 2")},
    {"name": "line break in a cloth name", "argv": [SMALL, "--set", "cloths.0.name=x\ny"],
     "status": 2,
     "stderr": error(SMALL, "cloths.0.name (from --set): contains the control character \\x0a "
                            "at byte 1")},
    {"name": "control character in an unknown key",
     "argv": [SMALL, "--set", "cloths.0.\x1b[31mbad=1"], "status": 2,
     "stderr": error(SMALL, "cloths.0.\\x1b[31mbad (from --set): unknown key (expected one of: "
                            "name, grid, size, origin, u_axis, v_axis, mesh, transform, rest_scale, "
                            "mass, density, stiffness, pins, pin_box, color, texture, texture_scale, velocity, tethers, aero, tearing, material)")},
    # A device or a FIFO would be read forever or block: only regular files are scenes.
    {"name": "a device as the scene", "argv": ["/dev/zero"], "status": 2,
     "stderr": error("/dev/zero", "cannot read: it is not a regular file")},
    # Outputs are renamed over their target: a device node (or FIFO, folder, link) is refused.
    # (--dump is checked the same way before any work; this table adds its own --dump to
    # every case, so --pc2 stands for both here.)
    {"name": "--pc2 to a device", "argv": [SMALL, "--pc2", "/dev/null"], "status": 2,
     "stderr": tooltest.tool_line("clothvk-sim", "--pc2 /dev/null: exists and is not a regular "
                                  "file (a device or socket); it is not replaced")},
    {"name": "dt too small", "argv": [SMALL, "--set", "dt=1e-30"], "status": 2,
     "stderr": error(SMALL, "dt (from --set): must be at least 1e-06 s (1/dt² must fit single "
                            "precision with room for masses and stiffnesses), got 1e-30")},
    {"name": "dt = 1e-6, the least allowed", "argv": [SMALL, "--set", "dt=1e-6", "--frames", "1"],
     "status": 0},
    # Numbers as written: sizes and positions past 1e5 m (a sphere of radius 1e38 once made NaN
    # of its cloth, exit status 3), integers past any bound, values that round to 0 in single
    # precision.
    {"name": "sphere radius 1e38", "argv": [SMALL, "--set",
                                            'colliders=[{"type": "sphere", "radius": 1e38}]'],
     "status": 2,
     "stderr": error(SMALL, "colliders.0.radius (from --set): must be at most 100000 m "
                            "(single-precision metres), got 1e+38")},
    {"name": "frames past any integer", "argv": [SMALL, "--set", "frames=99999999999999999999"],
     "status": 2,
     "stderr": error(SMALL, "frames (from --set): must be at most 4294967295, got 1e+20")},
    {"name": "keyframe time 1e-300",
     "argv": [SMALL, "--set", 'colliders=[{"type": "sphere", "keyframes": [{"time": 0}, {"time": 1e-300}]}]'],
     "status": 2,
     "stderr": error(SMALL, "colliders.0.keyframes.1.time (from --set): is too near 0 for single "
                            "precision, which reads it as 0 (the least magnitude is 1.4013e-45), "
                            "got 1e-300")},
    {"name": "substeps past the bound", "argv": [SMALL, "--set", "substeps=1431655765"], "status": 2,
     "stderr": error(SMALL, "substeps (from --set): must be at most 10000, got 1431655765")},
    {"name": "outer iterations past the bound",
     "argv": [SMALL, "--set", "solver.outer_iterations=4294967295"], "status": 2,
     "stderr": error(SMALL, "solver.outer_iterations (from --set): must be at most 10000, got "
                            "4294967295")},
    {"name": "sweeps past the bound",
     "argv": [SMALL, "--set", "solver.outer_iterations=200", "--set", "solver.inner_iterations=100"],
     "status": 2,
     "stderr": error(SMALL, "solver (from --set): 200 outer × 100 inner iterations are 20000 sweeps "
                            "per substep; at most 10000")},
    {"name": "operations per frame past the bound",
     "argv": [SMALL, "--set", "substeps=10000", "--set", "solver.outer_iterations=100",
              "--set", "solver.inner_iterations=100"], "status": 2,
     "stderr": error(SMALL, "substeps: 10000 substeps × 20000 operations per substep are 200000000 "
                            "operations per frame; a frame records at most 1000000 (fewer "
                            "substeps, sweeps or colours)")},
    # Derived quantities of the solve: m/h² and m/h² + Σk must fit single precision.
    {"name": "mass whose m/h² overflows", "argv": [SMALL, "--set", "cloths.0.mass=1e30"],
     "status": 2,
     "stderr": error(SMALL, "cloths.0.mass: a particle of 8.33333e+28 kg with a step of 0.002 s "
                            "has m/h² = 2.08333e+34 kg/s², outside [1e-30, 1e+30] where "
                            "single-precision solves hold it")},
    {"name": "stiffness whose diagonal overflows",
     "argv": [SMALL, "--set", "cloths.0.stiffness.structural=3e38"], "status": 2,
     "stderr": error(SMALL, "cloths.0.stiffness: a particle's springs sum to 9e+38 N/m; with "
                            "m/h² = 2083.33 kg/s² its row's diagonal exceeds 1e+30, beyond what "
                            "single-precision solves hold")},
    {"name": "workgroup size 0", "argv": [SMALL, "--workgroup-size", "0"], "status": 2,
     "stderr": tooltest.tool_line("clothvk-sim", "--workgroup-size: expected a whole number from 1 "
                                  "to 1024, got 0")},
    {"name": "no workgroups", "argv": [SMALL, "--max-workgroups", "0"], "status": 2,
     "stderr": tooltest.tool_line("clothvk-sim", "--max-workgroups: expected a whole number of at "
                                  "least 1, got 0")},
    {"name": "no search lanes", "argv": [SMALL, "--search-lanes", "0"], "status": 2,
     "stderr": tooltest.tool_line("clothvk-sim", "--search-lanes: expected a whole number from 1 "
                                  "to 1024, got 0")},
    {"name": "NaN in the file", "argv": [scene("nan.json")], "status": 2,
     "stderr": error(scene("nan.json"), "cloths.0.origin.1: must be a finite number, got NaN")},
    {"name": "NaN via --set", "argv": [SMALL, "--set", "dt=NaN"], "status": 2,
     "stderr": error(SMALL, "dt (from --set): must be a finite number, got NaN")},
    {"name": "unknown solver in the file", "argv": [scene("unknown-solver.json")], "status": 2,
     "stderr": error(scene("unknown-solver.json"),
                     "solver.linear: unknown linear solver \"sor\" (expected rbgs, jacobi, chebyshev, gs-cpu or cg)")},
    {"name": "unknown solver via --set", "argv": [SMALL, "--set", "solver.linear=foo"], "status": 2,
     "stderr": error(SMALL, "solver.linear (from --set): unknown linear solver \"foo\" "
                     "(expected rbgs, jacobi, chebyshev, gs-cpu or cg)")},
    {"name": "implicit without its linear solver", "argv": [SMALL, "--set", "solver.method=implicit"],
     "status": 2,
     "stderr": error(SMALL, "solver.linear: rbgs is not a linear solver of the implicit method; "
                     "use cg or jacobi")},

    # The mesh keys: mistakes found before any mesh file is read.
    {"name": "unknown key in transform", "argv": [SMALL, "--set", "cloths.0.transform.shear=1"], "status": 2,
     "stderr": error(SMALL, "cloths.0.transform.shear (from --set): unknown key (expected one of: scale, "
                     "rotation, translation)")},
    {"name": "zero scale", "argv": [SMALL, "--set", "cloths.0.transform.scale=0"], "status": 2,
     "stderr": error(SMALL, "cloths.0.transform.scale (from --set): must not be zero, got 0")},
    {"name": "density on a rope", "argv": [ROPE, "--set", "cloths.0.density=0.2"], "status": 2,
     "stderr": error(ROPE, "cloths.0.density (from --set): a 1 x 20 grid is a rope, with no area for a "
                     "density; give its mass instead")},
    {"name": "vertex indices on a grid", "argv": [SMALL, "--set", "cloths.0.pins=[0, 3]"], "status": 2,
     "stderr": error(SMALL, "cloths.0.pins (from --set): a grid cloth takes [i, j] pairs, not vertex indices")},
    # small.json's [i, j] pins stay in the file: the message names them, not the mesh that was set.
    {"name": "grid pins on a mesh", "argv": [SMALL, "--set", "cloths.0.mesh=cloth.obj"], "status": 2,
     "stderr": error(SMALL, "cloths.0.pins: a mesh cloth takes vertex indices (file order), not [i, j] pairs")},
    {"name": "pin_box upside down", "argv": [SMALL, "--set", "cloths.0.pin_box=[[0, 0.5, 0], [1, 0.2, 1]]"],
     "status": 2, "stderr": error(SMALL, "cloths.0.pin_box (from --set): min 0.5 is above max 0.2 on axis y")},

    # The command line. With no scene the program says so and prints its usage: only the first
    # line is compared.
    {"name": "no scene", "argv": [], "status": 2, "usage": True,
     "stderr": "clothvk-sim: no scene file given"},
    {"name": "unknown option", "argv": [SMALL, "--bogus"], "status": 2,
     "stderr": "clothvk-sim: unknown option --bogus (see --help)"},
    {"name": "--frames not a number", "argv": [SMALL, "--frames", "abc"], "status": 2,
     "stderr": "clothvk-sim: --frames: expected a whole number from 0 to 100000000, got abc"},
    {"name": "--frames negative", "argv": [SMALL, "--frames", "-3"], "status": 2,
     "stderr": "clothvk-sim: --frames: expected a whole number from 0 to 100000000, got -3"},
    {"name": "--set without =", "argv": [SMALL, "--set", "dt"], "status": 2,
     "stderr": "clothvk-sim: --set dt: expected key.path=value"},
    # GNU style: a long option's value after '=' is read as the next argument would be.
    {"name": "--frames= not a number", "argv": [SMALL, "--frames=abc"], "status": 2,
     "stderr": "clothvk-sim: --frames: expected a whole number from 0 to 100000000, got abc"},
    {"name": "--set= without =", "argv": [SMALL, "--set=dt"], "status": 2,
     "stderr": "clothvk-sim: --set dt: expected key.path=value"},
    {"name": "--set= an unknown key", "argv": [SMALL, "--set=solver.iterationz=8"], "status": 2,
     "stderr": error(SMALL, "solver.iterationz (from --set): unknown key (expected one of: method, "
                     "linear, outer_iterations, inner_iterations, omega, chebyshev_rho, chebyshev_delay, tolerance, max_iterations, kd, integrator, damping_model, tether_every, strain_limit, fuse)")},
    {"name": "a flag with a value", "argv": [SMALL, "--json=yes"], "status": 2,
     "stderr": "clothvk-sim: --json takes no value, got --json=yes"},
    {"name": "--frames= empty", "argv": [SMALL, "--frames="], "status": 2,
     "stderr": "clothvk-sim: --frames: expected a whole number from 0 to 100000000, got "},

    # Good input.
    {"name": "--plan red-black", "argv": [HANGING, "--plan"], "status": 0,
     "check": plan_has("colours: 2 (red-black)", "per frame: 8 substeps x 32 dispatches")},
    {"name": "--plan fused", "argv": [HANGING, "--plan", "--set", 'solver.fuse="on"'], "status": 0,
     "check": plan_has("solver: pd / rbgs, 4 outer x 4 inner, omega 1, sweeps fused (one dispatch "
                       "for every outer iteration)", "per frame: 8 substeps x 1 dispatch =",
                       "  solve    dispatch gauss-seidel, fused sweeps particles "
                       "0..9997, 1 groups, predict, outers 1-4: 4 sweeps x 2 colours (the last "
                       "+ finalize); one workgroup of 1024, global memory; u0 -> u1 first")},
    # Instances fuse a workgroup a copy, sized to a copy, the prediction a dispatch before.
    {"name": "--plan fused instances", "argv": [SMALL, "--plan", "--set", 'solver.fuse="on"',
                                                "--set", 'instances={"count": 3, "spacing": [1, 0, 0]}'],
     "status": 0,
     "check": plan_has("  predict  dispatch predict (Verlet)           particles 0..29, 1 groups",
                       "  solve    dispatch gauss-seidel, fused sweeps particles 0..29, 3 groups, "
                       "outers 1-2: 2 sweeps x 2 colours (the last + finalize); a workgroup a "
                       "copy of 64, global memory; u0 -> u1 first")},
    {"name": "--plan fuse auto on lavapipe", "argv": [HANGING, "--plan"], "status": 0,
     "check": plan_has("solver: pd / rbgs, 4 outer x 4 inner, omega 1, sweeps not fused: "
                       "solver.fuse auto, which does not fuse: slower on every device "
                       "measured")},
    {"name": "--plan full stencil", "argv": [STENCIL, "--plan"], "status": 0,
     "check": plan_has("colours: 5")},
    {"name": "--plan with contact", "argv": [asset("drape.json"), "--plan"], "status": 0,
     "check": plan_has("collision: thickness 0.01064 m, friction 0.3 (static 0.4), self-contact on "
                       "(contact radius 0.01383 m, bounds 0.45 of the nearest distance),",
                       "  colliders dispatch", "  hash     dispatch", "  contacts dispatch",
                       "  contact  dispatch")},
    {"name": "--plan with detection", "argv": [asset("ribbons.json"), "--plan"], "status": 0,
     "check": plan_has("collision: thickness 0.006 m, friction 0.4 (static 0.5), self-contact on "
                       "(contact radius 0.0078 m, bounds 0.45 of the nearest distance),",
                       "  detect faces indirect detection: vertices against faces particles, "
                       "groups from the device (offset 0), vertices against faces within 0.0078 m",
                       "  detect edges indirect detection: edges against edges particles, "
                       "groups from the device (offset 16), edges against edges within 0.0078 m")},
    {"name": "--json ribbons with edge contact", "argv": [asset("ribbons.json"), "--frames", "60",
                                                          "--json"], "status": 0,
     "check": json_pairs(lambda n: n == 0, "no intersecting pair: the ribbons lie on each other")},
    {"name": "--json ribbons with collision.edges=false (no effect)",
     "argv": [asset("ribbons.json"), "--frames", "60", "--set", "collision.edges=false", "--json"],
     "status": 0,
     "check": json_pairs(lambda n: n == 0, "no intersecting pair: edge-edge contact is always on")},
    # Detections held back to every fourth substep (collision.detection_interval): still no
    # cloth through cloth; more than 64 substeps is refused.
    {"name": "--json ribbons with collision.detection_interval=4",
     "argv": [asset("ribbons.json"), "--frames", "60", "--set", "collision.detection_interval=4",
              "--json"], "status": 0,
     "check": json_pairs(lambda n: n == 0, "no intersecting pair with detections held back")},
    {"name": "collision.detection_interval past 64",
     "argv": [SMALL, "--set", "collision.detection_interval=65"], "status": 2,
     "stderr": error(SMALL, "collision.detection_interval (from --set): must be at most 64 "
                            "substeps, got 65")},
    {"name": "--json contacts", "argv": [asset("drape.json"), "--set", "cloths.0.grid=[12,12]",
                                         "--set", "cloths.0.origin=[1,0.05,1]",
                                         "--frames", "40", "--json"], "status": 0,
     "check": json_contacts},
    {"name": "--json", "argv": [SMALL, "--set", "cloths.0.grid=[10,10]", "--frames", "3", "--json"], "status": 0,
     "check": json_stats(particles=100, structural=180, frames=3)},
    # The clean start: cloths that cross at the start are refused, naming the first pair;
    # collision.allow_intersecting_start simulates them anyway. Keys that no longer have an
    # effect are noted: on stderr, or in --json's "notes".
    {"name": "cloths crossing at the start", "argv": [CROSSING], "status": 2,
     "stderr": error(CROSSING, "collision: cloths \"a\" and \"b\" intersect at the start "
                               "(triangle 101 of \"a\" and triangle 80 of \"b\", near (-0.425, "
                               "0.992, 0.558)); set collision.allow_intersecting_start to simulate "
                               "anyway")},
    {"name": "cloths crossing at the start, allowed",
     "argv": [CROSSING, "--set", "collision.allow_intersecting_start=true", "--json"], "status": 0,
     "check": json_all(json_pairs(lambda n: n > 0, "the cloths still cross"), json_notes([]))},
    {"name": "a key without effect", "argv": [SMALL, "--set", "collision.edges=true", "--frames", "1"],
     "status": 0, "notes": [EDGES_NOTE]},
    {"name": "a key without effect, --json",
     "argv": [SMALL, "--set", "collision.edges=true", "--frames", "1", "--json"], "status": 0,
     "check": json_notes([EDGES_NOTE[len("clothvk-sim: note: "):]])},
    {"name": "--dump before any step", "argv": [SMALL, "--frames", "0", "--dump", DUMP], "status": 0,
     "check": dump_grid(SMALL, first_two_at_rest=True)},
    # small.json's grid is [4, 3]: 15 rows 0.225 m apart (not 12, 0.3 m) say --set= was applied.
    {"name": "--frames=0 --dump=FILE --set=KEY=VALUE",
     "argv": [SMALL, "--frames=0", f"--dump={DUMP}", "--set=cloths.0.grid=[5,3]"], "status": 0,
     "check": dump_grid(SMALL, first_two_at_rest=True, grid=[5, 3])},
    {"name": "1 x N rope", "argv": [ROPE, "--frames", "10", "--dump", DUMP], "status": 0,
     "check": dump_grid(ROPE, first_two_at_rest=False)},
    # Tearing: the count in --json, and a bad threshold. A 10 x 10 sheet thrown down from its two
    # pins ([0,0] and [3,0]) at 20 m/s tears there at 0.2: the 5 springs that hold the pinned
    # strip [0..3, 0] to the rest (the 4 down to row 1 and [3,0]-[4,0]), then 3 the recoil
    # breaks ([4,0]-[4,1], [0,1]-[0,2], [2,1]-[2,2]): 4 in frame 1, 8 from frame 2 on. Exactly 8:
    # each spring's break is decided alone, so the same springs break for every dispatch shape
    # and run (docs/how-it-works.md "Tearing"; gs-cpu breaks the same 8). Without tearing it
    # stretches 85 % and keeps them all.
    {"name": "--json torn_springs", "argv": [SMALL, "--set", "cloths.0.grid=[10,10]",
                                             "--set", "cloths.0.velocity=[0,-20,0]",
                                             "--set", "cloths.0.tearing.max_stretch=0.2",
                                             "--frames", "3", "--json"], "status": 0,
     "check": json_torn(8, 8)},
    {"name": "--json torn_springs without tearing", "argv": [SMALL, "--set", "cloths.0.grid=[10,10]",
                                                           "--set", "cloths.0.velocity=[0,-20,0]",
                                                           "--frames", "3", "--json"], "status": 0,
     "check": json_stats(particles=100, structural=180, frames=3)},
    {"name": "negative max_stretch", "argv": [SMALL, "--set", "cloths.0.tearing.max_stretch=-1"],
     "status": 2,
     "stderr": error(SMALL, "cloths.0.tearing.max_stretch (from --set): must be at least 0, got -1")},
] + [
    {"name": f"--set solver.linear={linear}",
     "argv": [SMALL, "--set", f"solver.linear={linear}", "--frames", "5", "--json"], "status": 0,
     "check": json_stats(particles=12, structural=17, frames=5, linear=linear)}
    for linear in ["rbgs", "jacobi", "chebyshev", "gs-cpu"]
]


def case_argv(case):
    """A bad-input case also asks for a dump, which must not be written."""
    return case["argv"] + (["--dump", DUMP] if case["status"] != 0 else [])


def run_case(case):
    """Runs one case in a fresh directory; returns a list of problems."""
    argv = case_argv(case)
    bad_input = case["status"] != 0
    env = dict(os.environ, **case.get("env", {}))
    with tempfile.TemporaryDirectory(prefix="clothvk-cli-") as workdir:
        try:
            p = tooltest.run_tool(SIM, argv, workdir, env, timeout=120)
        except subprocess.TimeoutExpired:
            return ["timed out after 120 s"]
        if bad_input:
            # A usage message follows its first line with the usage text.
            def stderr_ok(lines):
                one_line = len(lines) == 1 or case.get("usage")
                return lines and one_line and tooltest.line_matches(lines[0], case["stderr"])
            return tooltest.refusal_problems(p, case["stderr"], [], tooltest.listing(workdir),
                                             case["status"], stderr_ok)
        return tooltest.accepted_problems(p, case["status"], workdir, case.get("check"),
                                          case.get("notes", ()))


def same_dump(argv_a, argv_b):
    """Two runs with --dump: both succeed and write the same bytes (compute shapes change how
    the work is split, never the result: the solve is deterministic per particle)."""
    with tempfile.TemporaryDirectory(prefix="clothvk-cli-") as workdir:
        dumps = []
        for i, argv in enumerate((argv_a, argv_b)):
            name = f"run{i}.csv"
            p = tooltest.run_tool(SIM, argv + ["--dump", name], workdir, timeout=120)
            if p.returncode != 0 or p.stderr:
                return [f"{' '.join(argv)}: exit status {p.returncode}, stderr {p.stderr.strip()!r}"]
            with open(os.path.join(workdir, name), "rb") as f:
                dumps.append(f.read())
        return [] if dumps[0] == dumps[1] else [f"{' '.join(argv_b)} wrote other positions"]


def divergence_problems(argv, frame):
    """A run that blows up (the library's divergence watch): exit status 3, one line on stderr
    naming the frame, the statistics on stdout with "diverged": true and where, and no --dump
    written (the state is not a result)."""
    with tempfile.TemporaryDirectory(prefix="clothvk-cli-") as workdir:
        p = tooltest.run_tool(SIM, argv + ["--json", "--dump", DUMP], workdir, timeout=120)
        problems = []
        if p.returncode != 3:
            problems.append(f"exit status {p.returncode}, expected 3")
        line = tooltest.tool_line("clothvk-sim", f"{argv[0]}: diverged in frame {frame}, cloth 0: a "
                                  "particle moved faster than 10000 m/s or a spring stretched past "
                                  "ten times its rest length; stopped there")
        if p.stderr.splitlines() != [line]:
            problems.append(f"stderr {p.stderr!r}, expected the line {line!r}")
        stats = parse_json(p.stdout, problems)
        if stats is not None:
            got = {k: stats.get(k) for k in ("diverged", "diverged_frame", "diverged_cloth",
                                             "diverged_reason")}
            want = {"diverged": True, "diverged_frame": frame, "diverged_cloth": 0,
                    "diverged_reason": "run-away"}
            if got != want:
                problems.append(f"JSON says {got}, expected {want}")
        if tooltest.listing(workdir):
            problems.append(f"files were written: {tooltest.listing(workdir)}")
        return problems


def main():
    cases = tooltest.Cases("cli")
    for case in CASES:
        cases.add(f"{case['name']}: clothvk-sim {' '.join(case_argv(case))}", run_case(case))
    # dt = 1000 s: springs ten times their length within the first frame; a cloth at 9990.5 m/s
    # gaining 1 m/s a substep (dt 0.01 s, 100 m/s², 4 substeps a frame) passes 10000 m/s in its
    # 10th substep, in frame 2.
    cases.add("divergence at dt = 1000 s", divergence_problems([SMALL, "--set", "dt=1000"], 0))
    fast = [SMALL, "--set", "cloths.0.pins=[]", "--set", "cloths.0.velocity=[0,-9990.5,0]",
            "--set", "dt=0.01", "--set", "gravity=[0,-100,0]", "--set", "damping=0",
            "--frames", "40"]
    cases.add("divergence of a cloth too fast", divergence_problems(fast, 2))
    # The explicit method past its step: Adams-Bashforth at seed001.json's h = 1 ms, seven
    # times its limit (README "Explicit integrators"), runs away in frame 2.
    explicit = [os.path.join(ROOT, "assets", "scenes", "seed001.json"), "--set",
                "solver.integrator=adams-bashforth", "--frames", "20"]
    cases.add("divergence of an explicit integrator", divergence_problems(explicit, 2))
    hanging = [os.path.join(ROOT, "assets", "scenes", "hanging.json"), "--frames", "3"]
    for shape in (["--workgroup-size", "32"], ["--max-workgroups", "1"],
                  ["--workgroup-size", "1", "--max-workgroups", "3"]):
        cases.add(f"{' '.join(shape)}: the same positions", same_dump(hanging, hanging + shape))
    return cases.finish()


if __name__ == "__main__":
    sys.exit(main())
