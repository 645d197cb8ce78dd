#!/usr/bin/env python3
"""The "instances" block through clothvk-sim: bad blocks refused, the plan, the copies' places.

    python3 tests/tools/test_instances.py PATH/TO/clothvk-sim

Each bad block (a count of 0, negative, not whole, past the format's bound or the device's
limits; offsets that disagree with the count; copies that would reach past 1e5 m; copies with
rotating attachments) is refused: exit status 2, the one stderr line naming the scene file and
the key path with the problem (compared whole; the device's limit on lavapipe, CLOTHVK_DEVICE=
llvmpipe, its name alone, which carries the LLVM version, by its pattern), nothing on stdout and
nothing written. --plan prints the copies' layout and the same dispatches per frame for 1 and 64
copies; --frames 0 --dump puts copy k where copy 0 is plus its offset; 80 copies at one place
with self-contact (their 80 spheres read from storage buffers) each end exactly as the scene
alone, 4 particles of each on its sphere.
"""
import json
import os
import re
import sys
import tempfile

import tooltest

(SIM,) = tooltest.tool_paths("clothvk-sim")

SCENE = {"name": "rows", "dt": 0.002, "substeps": 2, "frames": 2,
         "solver": {"outer_iterations": 1, "inner_iterations": 2},
         "cloths": [{"grid": [8, 6], "size": [0.4, 0.3], "origin": [-0.2, 1.0, 0.0],
                     "pins": [[0, 0], [7, 0]], "stiffness": {"structural": 1e4}}],
         "colliders": [{"type": "sphere", "center": [0, 0.7, 0.1], "radius": 0.1}],
         "instances": {"count": 3, "spacing": [1.0, 0, 0]}}

ATTACH = ('attachments=[{"cloth": 0, "pins": [[0, 0]], "keyframes": ['
          '{"time": 0, "rotation": [1, 0, 0, 0]}, {"time": 1, "rotation": [0, 1, 0, 0]}]}]')

# (--set items, key path in the message, problem)
REFUSED = [
    (["instances.count=0"], "instances.count", "must be at least 1, got 0"),
    (["instances.count=-2"], "instances.count", "must be at least 1, got -2"),
    (["instances.count=2.5"], "instances.count", "expected a whole number, got 2.5"),
    (["instances.count=1048577"], "instances.count", "must be at most 1048576, got 1048577"),
    (["instances=4"], "instances", "expected an object (count, spacing or offsets), got the number 4"),
    (["instances.count=600000", "instances.spacing=[0, 0, 0]",
      'colliders=[{"type": "sphere"}, {"type": "sphere"}]'],
     "instances.count", "600000 copies of 2 colliders make 1200000, more than the 1048576 a "
     "scene holds"),
    (["instances.offsets=[[0, 0, 0], [1, 0, 0]]"], "instances.offsets",
     "has 2 offsets for 3 copies (instances.count); give one per copy"),
    (["instances.offsets=[[0, 0, 0], [1, 0]]"], "instances.offsets.1",
     "expected an array of 3 numbers, got an array of 2"),
    (["instances.offsets=[]"], "instances.offsets",
     "expected a non-empty array of [x, y, z] offsets, got an array of 0"),
    (["instances.spacing=[60000, 0, 0]"], "instances.spacing",
     "3 copies 60000 m apart reach 120000 m, more than 100000 m from the origin"),
    ([ATTACH], "attachments.0.keyframes.1.rotation",
     "turns the attached particles about the world origin, which would move each of the 3 "
     "copies (instances.count) differently; copies take attachments that only translate"),
]

# Past what the device holds: 65536 copies of 256 particles, on lavapipe (maxStorageBufferRange
# 134217728 bytes / 16 bytes per particle = 8388608), whose name stands as LLVMPIPE.
DEVICE = (["instances.count=65536", "cloths.0.grid=[16, 16]", "instances.spacing=[0, 0, 0]",
           "colliders=[]"],
          f"instances.count: 16777216 particles are too many for {tooltest.LLVMPIPE}, which holds at "
          "most 8388608 (maxStorageBufferRange 134217728 bytes, 16 bytes per particle)")


def refused(scene, sets, path, problem):
    argv = [scene, "--frames", "0", "--dump", "out.csv"] + sum((["--set", s] for s in sets), [])
    line = tooltest.tool_line("clothvk-sim", f"{scene}: {path} (from --set): {problem}")
    return tooltest.refused_run(SIM, argv, line)


def refused_by_device(scene):
    sets, message = DEVICE
    argv = [scene, "--frames", "0", "--dump", "out.csv"] + sum((["--set", s] for s in sets), [])
    expected = tooltest.tool_line("clothvk-sim", f"{scene}: {message}")
    with tempfile.TemporaryDirectory(prefix="clothvk-instances-") as workdir:
        before = tooltest.listing(workdir)
        p = tooltest.run_tool(SIM, argv, workdir, dict(os.environ, CLOTHVK_DEVICE="llvmpipe"),
                              timeout=120)
        return tooltest.refusal_problems(
            p, expected, before, tooltest.listing(workdir),
            stderr_ok=lambda lines: len(lines) == 1 and tooltest.line_matches(lines[0], expected))


def plan(scene, sets):
    argv = [scene, "--plan", "--frames", "0"] + sum((["--set", s] for s in sets), [])
    p = tooltest.run_tool(SIM, argv, timeout=120)
    return p, p.stdout.splitlines()


def dispatches(lines):
    for line in lines:
        found = re.match(r"per frame: .* = ([0-9]+) dispatches", line)
        if found:
            return int(found.group(1))
    return None


def plan_problems(scene):
    problems = []
    one, one_lines = plan(scene, ["instances.count=1"])
    many, many_lines = plan(scene, ["instances.count=64"])
    for p in (one, many):
        if p.returncode != 0 or p.stderr:
            problems.append(f"--plan: exit {p.returncode}, stderr {p.stderr.strip()!r}")
    layout = ("instances: 64 copies of 1 cloth (48 particles) and 1 collider, stepped together "
              "in the dispatches below; copy k: cloths 1 k.., particles 48 k.. (output order), "
              "offset k x [1, 0, 0] m")
    if layout not in many_lines:
        problems.append(f"64 copies: expected the line {layout!r} in --plan, got:\n    "
                        + "\n    ".join(many_lines[:8]))
    if any(line.startswith("instances:") for line in one_lines):
        problems.append("1 copy: --plan printed an instances line")
    if dispatches(one_lines) is None or dispatches(one_lines) != dispatches(many_lines):
        problems.append(f"dispatches per frame: {dispatches(one_lines)} for 1 copy, "
                        f"{dispatches(many_lines)} for 64")
    return problems


def places(scene, sets, offsets):
    """Copy k's start = copy 0's + offsets[k], within float rounding of the grid's positions."""
    with tempfile.TemporaryDirectory(prefix="clothvk-instances-") as workdir:
        argv = [scene, "--frames", "0", "--dump", "out.csv"] + sum((["--set", s] for s in sets), [])
        p = tooltest.run_tool(SIM, argv, workdir, timeout=120)
        problems = tooltest.accepted_problems(p, 0, workdir)
        if problems:
            return problems
        rows = tooltest.read_csv(os.path.join(workdir, "out.csv"))
    n = 48
    if len(rows) != n * len(offsets):
        return [f"expected {n * len(offsets)} particles, got {len(rows)}"]
    for k, o in enumerate(offsets):
        moved = [[x + d for x, d in zip(p, o)] for p in rows[:n]]
        diff = tooltest.worst(rows[k * n:(k + 1) * n], moved)
        if diff > 1e-6:
            problems.append(f"copy {k} is {diff:g} m from copy 0 moved by {o}")
    return problems


def same_place(scene, count):
    """Copies at one place with self-contact, falling onto a sphere each (4 particles of each
    touch it by frame 12: --json's contacts.colliders is 4 per copy): each copy's positions are
    the single scene's, bit for bit (more than 64 copies: the colliders are read from storage
    buffers)."""
    sets = ["instances.spacing=[0, 0, 0]", "collision.self=true", "frames=12",
            'colliders=[{"type": "sphere", "center": [0, 0.9, 0.15], "radius": 0.08}]']
    rows = {}
    with tempfile.TemporaryDirectory(prefix="clothvk-instances-") as workdir:
        for n in (1, count):
            argv = [scene, "--json", "--dump", f"out{n}.csv", "--set", f"instances.count={n}"]
            argv += sum((["--set", s] for s in sets), [])
            p = tooltest.run_tool(SIM, argv, workdir, timeout=300)
            problems = tooltest.accepted_problems(p, 0, workdir)
            if problems:
                return problems
            try:
                touching = json.loads(p.stdout)["contacts"]["colliders"]
            except (ValueError, KeyError, TypeError) as e:
                return [f"{n} copies: no contacts.colliders in --json: {e!r}"]
            if touching != 4 * n:
                return [f"{n} copies: {touching} particles touch the spheres at frame 12, "
                        f"expected 4 per copy, {4 * n}"]
            with open(os.path.join(workdir, f"out{n}.csv")) as f:
                rows[n] = [line for line in f.read().splitlines() if line[:1] in "-0123456789"]
    one, many = rows[1], rows[count]
    if len(many) != count * len(one):
        return [f"expected {count * len(one)} particles, got {len(many)}"]
    unlike = [k for k in range(count) if many[k * len(one):(k + 1) * len(one)] != one]
    return [f"copies {unlike[:8]} differ from the single scene's run"] if unlike else []


def main():
    cases = tooltest.Cases("instances")
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "rows.json")
        with open(scene, "w") as f:
            json.dump(SCENE, f, indent=2)
        for sets, path, problem in REFUSED:
            cases.add(f"{' '.join(sets)} refused", refused(scene, sets, path, problem))
        cases.add("past the device's limits refused", refused_by_device(scene))
        cases.add("--plan: the layout, the same dispatches for 1 and 64 copies", plan_problems(scene))
        cases.add("spacing: copy k at k x spacing",
                  places(scene, [], [[0, 0, 0], [1, 0, 0], [2, 0, 0]]))
        cases.add("offsets: copy k at its offset",
                  places(scene, ["instances={\"offsets\": [[0, 0, 0], [0, 0, 3], [-2, 1, 0.5]]}"],
                         [[0, 0, 0], [0, 0, 3], [-2, 1, 0.5]]))
        cases.add("80 copies at one place, self-contact: each the single scene's run",
                  same_place(scene, 80))
    return cases.finish()


sys.exit(main())
