#!/usr/bin/env python3
"""The bounds docs/scene-format.md gives numeric keys, tried at their edges through clothvk-sim.

    python3 tests/tools/test_scene_bounds.py PATH/TO/clothvk-sim PATH/TO/docs/scene-format.md

For each key of the table below: the bound as the doc writes it appears word for word in the
doc's row for that key (or, for the 1e5 m bound on positions and lengths, in its "Lengths and
positions" paragraph), so a changed bound in the doc fails here until the checks change too;
each edge value the bound allows runs (--frames 0 --dump: exit 0, nothing on stderr, the dump
written), except instances.count's upper edge: 1048576 copies of the test's cloth are more
particles than a device holds, a refusal by the device's limit that test_instances.py checks;
each value just past it (the next single-precision number, or the next integer) is
refused: exit status 2, the one stderr line naming the scene file and the key path with the
problem (compared whole), nothing on stdout and nothing written.
"""
import json
import os
import re
import sys
import tempfile

import tooltest

SIM, DOC = tooltest.tool_paths("clothvk-sim", "scene-format.md")

CLOTH = {"name": "flag", "grid": [8, 6], "size": [0.5, 0.4], "origin": [0.0, 1.0, 0.0],
         "u_axis": [1, 0, 0], "v_axis": [0, -1, 0], "mass": 0.1,
         "stiffness": {"structural": 1e4, "shear": 1e3, "bend": 10}, "pins": [[0, 0], [7, 0]]}
SCENE = {"name": "flag", "dt": 0.002, "substeps": 4, "frames": 2,
         "solver": {"linear": "rbgs", "outer_iterations": 2, "inner_iterations": 2},
         "cloths": [CLOTH]}

TETHERS = "must be 0 (no tethers) or from 1 to 10 (a scale of the rest distance to the pins), got "
SPHERE = 'colliders=[{"type": "sphere", "radius": %s}]'
CENTRE = 'colliders=[{"type": "sphere", "center": [%s, 0, 0]}]'
# A sphere under the cloth, its top at y = 0: a cloth that starts inside a collider is refused.
SPHERE_BELOW = 'colliders=[{"type": "sphere", "center": [0, %s, 0], "radius": %s}]'
ONE_INNER = ["solver.inner_iterations=1"]

# (row: the doc row's key, or "sphere" for the collider table, or "positions" for the paragraph
#  on lengths and positions; the bound as the doc writes it there; the --set items that run;
#  (--set item, key path in the message, problem) for each value just past a bound; extra --set
#  items for every run of the entry).
BOUNDS = [
    ("dt", "≥ 1e-6", ["dt=1e-6"],
     [("dt=9.99e-7", "dt", "must be at least 1e-06 s (1/dt² must fit single precision with room "
       "for masses and stiffnesses), got 9.99e-07"),
      ("dt=0", "dt", "must be greater than 0, got 0")], []),
    ("substeps", "1 to 10000", ["substeps=1", "substeps=10000"],
     [("substeps=0", "substeps", "must be at least 1, got 0"),
      ("substeps=10001", "substeps", "must be at most 10000, got 10001")], []),
    ("damping", "in [0, 1)", ["damping=0", "damping=0.99999994"],
     [("damping=-1e-7", "damping", "must be at least 0 and less than 1, got -1e-07"),
      ("damping=1", "damping", "must be at least 0 and less than 1, got 1")], []),
    ("solver.omega", "in (0, 2)", ["solver.omega=1e-30", "solver.omega=1.9999999"],
     [("solver.omega=0", "solver.omega", "must be greater than 0 and less than 2, got 0"),
      ("solver.omega=2", "solver.omega", "must be greater than 0 and less than 2, got 2")], []),
    ("solver.strain_limit", "at most 10", ["solver.strain_limit=0", "solver.strain_limit=10"],
     [("solver.strain_limit=-1e-7", "solver.strain_limit", "must be between 0 and 10, got -1e-07"),
      ("solver.strain_limit=10.000001", "solver.strain_limit",
       "must be between 0 and 10, got 10.000001")], []),
    ("solver.outer_iterations", "(1 to 10000)",
     ["solver.outer_iterations=1", "solver.outer_iterations=10000"],
     [("solver.outer_iterations=0", "solver.outer_iterations", "must be at least 1, got 0"),
      ("solver.outer_iterations=10001", "solver.outer_iterations", "must be at most 10000, got 10001")],
     ONE_INNER),
    ("solver.inner_iterations", "(1 to 10000; outer × inner at most 10000)",
     ["solver.inner_iterations=5000"],
     [("solver.inner_iterations=5001", "solver",
       "2 outer × 5001 inner iterations are 10002 sweeps per substep; at most 10000"),
      ("solver.inner_iterations=0", "solver.inner_iterations", "must be at least 1, got 0")], []),
    ("cloths.N.tethers", "from 1 to 10",
     ["cloths.0.tethers=0", "cloths.0.tethers=1", "cloths.0.tethers=10"],
     [("cloths.0.tethers=0.9999999", "cloths.0.tethers", TETHERS + "0.9999999"),
      ("cloths.0.tethers=10.000001", "cloths.0.tethers", TETHERS + "10.000001")], []),
    ("cloths.N.mass", "> 0", ["cloths.0.mass=1e-30"],
     [("cloths.0.mass=0", "cloths.0.mass", "must be greater than 0, got 0")], []),
    ("collision.thickness", "at most 1", ["collision.thickness=0", "collision.thickness=1"],
     [("collision.thickness=-1e-7", "collision.thickness", "must be at least 0, got -1e-07"),
      ("collision.thickness=1.0000001", "collision.thickness", "must be at most 1 m, got 1.0000001")],
     []),
    ("collision.radius", "at most 1", ["collision.radius=1"],
     [("collision.radius=1.0000001", "collision.radius", "must be at most 1 m, got 1.0000001")], []),
    ("sphere", "`radius` (0.25, > 0)", [SPHERE % "1e-30"],
     [(SPHERE % "0", "colliders.0.radius", "must be greater than 0, got 0")], []),
    ("positions", "at most 1e5 m in magnitude", [SPHERE_BELOW % ("-1e5", "1e5"), CENTRE % "-1e5"],
     [(SPHERE % "100000.01", "colliders.0.radius",
       "must be at most 100000 m (single-precision metres), got 100000.01"),
      (CENTRE % "-100000.01", "colliders.0.center.0",
       "must be at most 100000 m from the origin (single-precision metres), got -100000.01")], []),
    ("cloths.N.tearing.max_stretch", "at most 9", ["cloths.0.tearing.max_stretch=9"],
     [("cloths.0.tearing.max_stretch=9.000001", "cloths.0.tearing.max_stretch",
       "must be at most 9 (a spring 10 times its rest length is a diverged solve), got 9.000001")],
     []),
    ("air_density", "> 0 (at most 1e4)", ["air_density=1e-30", "air_density=1e4"],
     [("air_density=0", "air_density", "must be greater than 0, got 0"),
      ("air_density=10000.001", "air_density", "must be at most 10000, got 10000.001")], []),
    ("cloths.N.velocity", "at most 10000 m/s fast", ["cloths.0.velocity=[10000, 0, 0]"],
     [("cloths.0.velocity=[10000.001, 0, 0]", "cloths.0.velocity",
       "must be at most 10000 m/s in magnitude, got 10000.001 m/s ([10000.001, 0, 0])")], []),
    ("wind.velocity", "at most 700 m/s fast", ["wind.velocity=[0, 0, -700]"],
     [("wind.velocity=[0, 0, -700.0001]", "wind.velocity",
       "must be at most 700 m/s fast, got 700.0001 m/s")], []),
    ("wind.gusts.amplitude", "0 to 1", ["wind.gusts.amplitude=1"],
     [("wind.gusts.amplitude=1.0000001", "wind.gusts.amplitude", "must be at most 1, got 1.0000001"),
      ("wind.gusts.amplitude=-1e-7", "wind.gusts.amplitude", "must be at least 0, got -1e-07")],
     ["wind={}"]),
    ("cloths.N.aero.drag", "0 to 100", ["cloths.0.aero.drag=0", "cloths.0.aero.drag=100"],
     [("cloths.0.aero.drag=100.00001", "cloths.0.aero.drag", "must be at most 100, got 100.00001")],
     []),
    ("render.shadow_map_size", "16 to 16384",
     ["render.shadow_map_size=16", "render.shadow_map_size=16384"],
     [("render.shadow_map_size=15", "render.shadow_map_size", "must be from 16 to 16384, got 15"),
      ("render.shadow_map_size=16385", "render.shadow_map_size", "must be from 16 to 16384, got 16385")],
     []),
    ("instances.count", "1 to 1048576", ["instances.count=1", "instances.count=2"],
     [("instances.count=0", "instances.count", "must be at least 1, got 0"),
      ("instances.count=1048577", "instances.count", "must be at most 1048576, got 1048577")],
     []),
    ("render.fov_y", "in (0, 180)", ["render.fov_y=179.99998"],
     [("render.fov_y=180", "render.fov_y", "must be greater than 0 and less than 180, got 180")], []),
]


def doc_rows(text):
    """{key: the doc's table row} for every backquoted key in a row's first cell, with "sphere"
    and the other collider types for their rows, and "positions" for the paragraph on lengths
    and positions."""
    rows = {}
    for line in text.splitlines():
        cells = line.split("|")
        if line.startswith("| `") and len(cells) > 2:
            for key in re.findall(r"`([^`]+)`", cells[1]):
                rows[key] = line
    found = re.search(r"^- \*\*Lengths and positions\*\*.*?(?=^- \*\*|^$)", text, re.M | re.S)
    rows["positions"] = " ".join(found.group(0).split()) if found else ""
    return rows


def in_doc(rows, row, phrase):
    line = rows.get(row)
    if line is None:
        return [f"docs/scene-format.md has no row for {row}"]
    if phrase not in line:
        return [f"docs/scene-format.md's row for {row} does not say {phrase!r}: {line}"]
    return []


def accepted(scene, sets):
    argv = [scene, "--frames", "0", "--dump", "out.csv"] + sum((["--set", s] for s in sets), [])
    with tempfile.TemporaryDirectory(prefix="clothvk-bounds-") as workdir:
        p = tooltest.run_tool(SIM, argv, workdir, timeout=120)
        problems = tooltest.accepted_problems(p, 0, workdir)
        if p.returncode == 0 and tooltest.listing(workdir) != ["out.csv"]:
            problems.append(f"expected out.csv alone written, found {tooltest.listing(workdir)}")
    return problems


def refused(scene, sets, path, problem):
    argv = [scene, "--frames", "0", "--dump", "out.csv"] + sum((["--set", s] for s in sets), [])
    line = tooltest.tool_line("clothvk-sim", f"{scene}: {path} (from --set): {problem}")
    return tooltest.refused_run(SIM, argv, line)


def main():
    with open(DOC, encoding="utf-8") as f:
        rows = doc_rows(f.read())
    cases = tooltest.Cases("scene-bounds")
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "flag.json")
        with open(scene, "w") as f:
            json.dump(SCENE, f, indent=2)
        for row, phrase, good, bad, extra in BOUNDS:
            cases.add(f"{row}: the doc says {phrase!r}", in_doc(rows, row, phrase))
            for item in good:
                cases.add(f"{row}: {item} runs", accepted(scene, extra + [item]))
            for item, path, problem in bad:
                cases.add(f"{row}: {item} refused", refused(scene, extra + [item], path, problem))
    return cases.finish()


sys.exit(main())
