#!/usr/bin/env python3
"""Bad mesh files through clothvk-sim and clothvk-render, as a person meets them: the same
treatment as a bad scene, i.e. one line naming the scene file, the key path and the problem,
exit status 2 and nothing written. Also one good mesh scene, the shipped poncho.

    python3 tests/tools/test_mesh_cli.py PATH/TO/clothvk-sim PATH/TO/clothvk-render

Every case runs in a fresh temporary directory, its working directory, into which it first
writes its inputs: in/scene.json and the mesh files under in/meshes/. The scene is passed as
"in/scene.json" and names its mesh relative to itself ("meshes/cloth.obj"), so the path in a
message is the one the tool resolves: "in/meshes/cloth.obj". A bad case asks clothvk-sim for
"--dump out.csv --obj frames" and clothvk-render for "-o out"; afterwards the directory must hold
exactly what it held before the run (no output, no temporary file beside the inputs).
"""
import json
import math
import os
import subprocess
import sys
import tempfile

import tooltest

TOOLS = dict(zip(["clothvk-sim", "clothvk-render"], tooltest.tool_paths("clothvk-sim", "clothvk-render")))
ROOT = tooltest.ROOT

SCENE = os.path.join("in", "scene.json")
OUTPUTS = {"clothvk-sim": ["--dump", "out.csv", "--obj", "frames"], "clothvk-render": ["-o", "out"]}

# ---- mesh files: each good but for the one problem its name says ----

# A unit square of two triangles: vertices 0 to 3 in file order.
SQUARE = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"
# Vertices and polylines, no face.
LINES_ONLY = "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\nl 2 3\n"
# Vertex 2 (file order, from 0) is not a number.
NAN_VERTEX = "v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"
# Face 1 has its three corners on one line.
ZERO_AREA = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n"
# Three triangles hinged on the edge between vertices 0 and 1, like the pages of a book.
THREE_ON_ONE_EDGE = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n"
# A face whose corner is vertex 5 (from 1) of a file of four vertices.
FACE_PAST_VERTICES = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 5\n"
# A face whose corner is vertex 0, which OBJ's indices (from 1, or negative from the end) never name.
FACE_INDEX_ZERO = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 0 3 4\n"
# A disc fanned from its centre, vertex 0, into FAN triangles: the centre has FAN springs, which the
# solver's adjacency keeps in 2 texels per 4 springs for every particle: 17001 x 2 x 4250 texels,
# more than lavapipe's maxTexelBufferElements (134217728). A mesh too large for the device, in a
# file of under 1 MB. (The limit is checked after the build has laid the adjacency out on the host,
# max degree x particles entries, so this case costs about 1.2 GB of memory and a few seconds.)
FAN = 17000
DISC = "v 0 0 0\n" + "".join(f"v {math.cos(2 * math.pi * i / FAN):.9f} {math.sin(2 * math.pi * i / FAN):.9f} 0\n"
                             for i in range(FAN)) + \
    "".join(f"f 1 {2 + i} {2 + (i + 1) % FAN}\n" for i in range(FAN))
# A triangle whose header declares 4e9 faces (Assimp's reader reserved memory for them).
HUGE_PLY = ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\nelement face 4000000000\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
# Bytes that are no PLY file (no "ply" magic), fixed so the reader's reason is the same every run.
GARBAGE = bytes(range(256)) * 4


def mesh_scene(cloth_keys, cloths_before=()):
    """A scene whose last cloth is a mesh cloth with cloth_keys; cloths_before come first."""
    cloth = dict({"mesh": "meshes/cloth.obj"}, **cloth_keys)
    return {"name": "mesh-cli", "frames": 2, "cloths": list(cloths_before) + [cloth]}


def resolved(name):
    """The mesh path as the tools print it: the scene's folder joined with the path in the scene."""
    return os.path.join(os.path.dirname(SCENE), "meshes", name)


def error(tool, message):
    return tooltest.tool_line(tool, f"{SCENE}: {message}")


# Stands for lavapipe's device name in an expected line (see tooltest.line_matches).
LLVMPIPE = tooltest.LLVMPIPE


GRID = {"grid": [4, 4], "size": [0.3, 0.3], "pins": [[0, 0]]}

# ---- the cases ----
# meshes: file name under in/meshes/ -> contents (str or bytes); a value of None makes a folder.
# message: the exact text after "TOOL: in/scene.json: ".
# tools: which tools run the case (default clothvk-sim only); env: added to the environment.

BAD = [
    {"name": "missing mesh file", "meshes": {}, "scene": mesh_scene({}),
     "tools": ["clothvk-sim", "clothvk-render"],
     "message": f"cloths.0.mesh: cannot read {resolved('cloth.obj')}: No such file or directory"},
    {"name": "a folder as the mesh", "meshes": {"cloth.obj": None}, "scene": mesh_scene({}),
     "message": f"cloths.0.mesh: cannot read {resolved('cloth.obj')}: it is a directory"},
    # Root reads any file whatever its mode, so this case is skipped when run as root.
    {"name": "unreadable mesh file (mode 000)", "meshes": {"cloth.obj": SQUARE}, "mode": 0o000,
     "scene": mesh_scene({}), "message": f"cloths.0.mesh: cannot read {resolved('cloth.obj')}: Permission denied"},
    # The reason is Assimp's own text (its PLY reader's, as of Assimp 5.2), compared whole like the rest.
    {"name": "garbage bytes in a .ply file", "meshes": {"cloth.ply": GARBAGE},
     "scene": mesh_scene({"mesh": "meshes/cloth.ply"}),
     "message": f"cloths.0.mesh: cannot read {resolved('cloth.ply')}: Invalid .ply file: Incorrect magic "
                "number (expected 'ply' or 'PLY')."},
    # Assimp's OBJ reader's own text (the same in Assimp 5.2 to 6.0). Each file is one object: where
    # a bad face comes after another object, Assimp 5.2 leaks that object's meshes (docs/limits.md),
    # which the sanitized run of this test would report.
    {"name": "a face's vertex index past the file's vertices", "meshes": {"cloth.obj": FACE_PAST_VERTICES},
     "scene": mesh_scene({}),
     "message": f"cloths.0.mesh: cannot read {resolved('cloth.obj')}: OBJ: vertex index out of range"},
    {"name": "a face's vertex index 0", "meshes": {"cloth.obj": FACE_INDEX_ZERO}, "scene": mesh_scene({}),
     "message": f"cloths.0.mesh: cannot read {resolved('cloth.obj')}: OBJ: Invalid face index."},
    # A PLY header's counts are checked before Assimp reserves memory for them.
    {"name": "a PLY header declaring 4e9 faces", "meshes": {"cloth.ply": HUGE_PLY},
     "scene": mesh_scene({"mesh": "meshes/cloth.ply"}), "tools": ["clothvk-sim", "clothvk-render"],
     "message": f"cloths.0.mesh: {resolved('cloth.ply')}: the mesh is too large: its header declares "
                "4000000000 face elements, and a mesh may have at most 1073741824"},
    {"name": "no triangles (vertices and lines only)", "meshes": {"cloth.obj": LINES_ONLY}, "scene": mesh_scene({}),
     "message": f"cloths.0.mesh: {resolved('cloth.obj')} has no triangles"},
    {"name": "NaN coordinate", "meshes": {"cloth.obj": NAN_VERTEX}, "scene": mesh_scene({}),
     "message": f"cloths.0.mesh: {resolved('cloth.obj')}: vertex 2 has a coordinate that is not a finite number"},
    {"name": "zero-area triangle", "meshes": {"cloth.obj": ZERO_AREA}, "scene": mesh_scene({}),
     "message": f"cloths.0.mesh: {resolved('cloth.obj')}: face 1 is degenerate (zero area)"},
    # In the second cloth, after a grid: the key path names the cloth's index.
    {"name": "non-manifold edge (three triangles on one edge)", "meshes": {"cloth.obj": THREE_ON_ONE_EDGE},
     "scene": mesh_scene({}, cloths_before=[GRID]), "tools": ["clothvk-sim", "clothvk-render"],
     "message": f"cloths.1.mesh: {resolved('cloth.obj')}: the edge between vertices 0 and 1 is shared by 3 faces "
                "(non-manifold)"},
    {"name": "pin vertex index out of range", "meshes": {"cloth.obj": SQUARE}, "scene": mesh_scene({"pins": [0, 4]}),
     "tools": ["clothvk-sim", "clothvk-render"],
     "message": "cloths.0.pins.1: vertex 4 is out of range; the mesh has 4 vertices"},
    {"name": "pin_box that holds no vertex", "meshes": {"cloth.obj": SQUARE},
     "scene": mesh_scene({"pin_box": [[2, 2, -1], [3, 3, 1]]}),
     "message": "cloths.0.pin_box: holds none of the cloth's 4 vertices"},
    {"name": "a mesh too large for the device", "meshes": {"cloth.obj": DISC}, "scene": mesh_scene({}),
     "env": {"CLOTHVK_DEVICE": "llvmpipe"},
     "message": f"cloths.0.mesh: {FAN + 1} particles with up to {FAN} springs each need {(FAN + 1) * 2 * ((FAN + 3) // 4)} "
                f"adjacency texels; {LLVMPIPE} allows 134217728 texel buffer elements (maxTexelBufferElements)"},
]


def write_inputs(workdir, case):
    os.makedirs(os.path.join(workdir, "in", "meshes"))
    with open(os.path.join(workdir, SCENE), "w") as f:
        json.dump(case["scene"], f, indent=2)
    for name, contents in case["meshes"].items():
        path = os.path.join(workdir, "in", "meshes", name)
        if contents is None:
            os.makedirs(path)
            continue
        with open(path, "wb") as f:
            f.write(contents.encode() if isinstance(contents, str) else contents)
        if "mode" in case:
            os.chmod(path, case["mode"])


def run(tool, argv, workdir, env=None):
    try:
        return tooltest.run_tool(TOOLS[tool], argv, workdir, dict(os.environ, **(env or {})), timeout=180)
    except subprocess.TimeoutExpired:
        return None


def expected_stderr(tool, case):
    """The line a bad case must print, as shown when it does not, and the test of stderr's lines."""
    expected = error(tool, case["message"])
    return expected, lambda lines: len(lines) == 1 and tooltest.line_matches(lines[0], expected)


def run_bad(tool, case):
    """Runs one bad case with one tool in a fresh directory; returns a list of problems."""
    with tempfile.TemporaryDirectory(prefix="clothvk-mesh-cli-") as workdir:
        write_inputs(workdir, case)
        before = tooltest.listing(workdir)
        p = run(tool, [SCENE] + OUTPUTS[tool], workdir, case.get("env"))
        if p is None:
            return ["timed out after 180 s"]
        expected, stderr_ok = expected_stderr(tool, case)
        problems = tooltest.refusal_problems(p, expected, before, tooltest.listing(workdir), 2, stderr_ok)
        for base, dirs, files in os.walk(workdir):  # let the temporary directory go
            for name in files:
                os.chmod(os.path.join(base, name), 0o600)
        return problems


def good_square():
    """The control for the bad cases: the same inputs with a good mesh do run, and the outputs
    the bad cases ask for do appear (so "nothing written" is a check that can fail)."""
    case = {"meshes": {"cloth.obj": SQUARE}, "scene": mesh_scene({"pins": [3], "pin_box": [[0, 0.5, -1], [1, 2, 1]]})}
    with tempfile.TemporaryDirectory(prefix="clothvk-mesh-cli-") as workdir:
        write_inputs(workdir, case)
        p = run("clothvk-sim", [SCENE] + OUTPUTS["clothvk-sim"], workdir)
        if p is None:
            return ["timed out after 180 s"]
        problems = []
        if p.returncode != 0 or p.stderr:
            problems.append(f"exit status {p.returncode}, stderr: {p.stderr.strip() or '(nothing)'}")
        made = sorted(set(tooltest.listing(workdir)) - {"in", SCENE, "in/meshes", "in/meshes/cloth.obj"})
        expected = ["frames", "frames/frame_0000.obj", "frames/frame_0001.obj",
                    "frames/frame_0002.obj", "out.csv"]
        if made != expected:
            problems.append(f"expected {expected} written, found {made}")
        return problems


def good_poncho():
    """The shipped mesh scene: 755 particles, none pinned (it falls on a mannequin), at most 8 colours, no NaN."""
    poncho = os.path.join(ROOT, "assets", "scenes", "poncho.json")
    with tempfile.TemporaryDirectory(prefix="clothvk-mesh-cli-") as workdir:
        p = run("clothvk-sim", [poncho, "--frames", "2", "--json"], workdir)
        if p is None:
            return ["timed out after 180 s"]
        if p.returncode != 0 or p.stderr:
            return [f"exit status {p.returncode}, stderr: {p.stderr.strip() or '(nothing)'}"]
        try:
            stats = json.loads(p.stdout)
        except ValueError as e:
            return [f"stdout is not one JSON object: {e}"]
        problems = []
        for key, want in {"particles": 755, "pinned": 0, "frames": 2, "nan_count": 0}.items():
            if stats.get(key) != want:
                problems.append(f"{key}: expected {want}, got {stats.get(key)!r}")
        colours = stats.get("colours")
        if not isinstance(colours, int) or not 1 <= colours <= 8:
            problems.append(f"colours: expected 1 to 8, got {colours!r}")
        return problems


def main():
    cases = tooltest.Cases("mesh cli")
    for case in BAD:
        for tool in case.get("tools", ["clothvk-sim"]):
            label = f"{tool}: {case['name']}"
            if case.get("mode") is not None and os.geteuid() == 0:
                cases.skip(f"{label}: running as root, which reads any file whatever its mode")
            else:
                cases.add(label, run_bad(tool, case))
    cases.add("clothvk-sim: a good square mesh writes its outputs", good_square())
    cases.add("clothvk-sim: poncho.json, 2 frames", good_poncho())
    return cases.finish(count_skipped=True)


if __name__ == "__main__":
    sys.exit(main())
