#!/usr/bin/env python3
"""clothvk-render --from BAKE --frames A:B: images from a bake equal a direct render's, byte for byte.

    python3 tests/tools/test_bake_render.py PATH/TO/clothvk-sim PATH/TO/clothvk-render

A small scene is baked for F frames (every 1 and every 2) and rendered directly with --frames F
(--every 1: frame_0000.png ... frame_{F}.png, the start and the state after each frame, as the
bake holds them). Then:
- --from the bake with --frames 1:4 writes exactly frame_0001.png ... frame_0004.png, each equal
  byte for byte to the direct render's image of that frame; --frames 5:5 and 0:0, run separately,
  give frame_0005.png and frame_0000.png equal to theirs;
- without --frames, every frame the bake holds (all of them, 0 to F; 0, 2, 4, 6 for the --every 2
  bake of F = 6);
- a frame the bake does not hold (frame 1 of the --every 2 bake, frame F + 1 of either) is refused:
  exit 2, one line, no output folder made; so are --frames A:B without --from, --every with
  --from, a missing bake and another scene's bake (naming the key path and both values);
- a --set item that leaves the scene as baked (dt=4e-3 where the file says 0.004) is no other scene;
- keys that only draw the scene (render.*, a cloth's color and material) may differ from the
  bake's: the image equals a direct render with the same --set items, and differs from the
  bake's own scene's.
"""
import json
import os
import sys
import tempfile

import tooltest

SIM, RENDER = tooltest.tool_paths("clothvk-sim", "clothvk-render")

FRAMES = 6
CLOTH = {"name": "flag", "grid": [8, 6], "size": [0.5, 0.4], "origin": [-0.25, 1.0, 0.0],
         "u_axis": [1, 0, 0], "v_axis": [0, -1, 0], "mass": 0.1,
         "stiffness": {"structural": 1e4, "shear": 1e3, "bend": 10}, "pins": [[0, 0], [7, 0]]}
SCENE = {"name": "flag", "dt": 0.004, "substeps": 4, "frames": FRAMES,
         "solver": {"linear": "rbgs", "outer_iterations": 2, "inner_iterations": 2},
         "render": {"size": [96, 64]}, "cloths": [CLOTH]}

CHECKS = tooltest.Checks()
check = CHECKS.check


def run(tool, args, what, status=0):
    r = tooltest.run_tool(tool, args)
    check(r.returncode == status, f"{what}: exit {r.returncode}, expected {status}: {r.stderr.strip()}")
    return r


def from_bake(tmp, scene, bake, frames, direct, what):
    """Renders `frames` (a list) from `bake` with the given --frames argument and compares."""
    out = os.path.join(tmp, what.replace(" ", "-").replace(":", "-"))
    args = [scene, "-o", out, "--from", bake, "--quiet"]
    if what.startswith("--frames"):
        args += ["--frames", what.split()[1]]
    run(RENDER, args, what)
    got = tooltest.contents(out)
    want = [f"frame_{f:04d}.png" for f in frames]
    check(sorted(got) == want, f"{what}: images {sorted(got)}, expected {want}")
    for name, data in got.items():
        ref = direct.get(name)
        check(ref is not None and data == ref,
              f"{what}: {name} differs from the direct render's ({len(data)} bytes against "
              f"{len(ref) if ref else 0})")


def refused(tmp, args, line, what):
    out = os.path.join(tmp, "refused")
    r = run(RENDER, args + ["-o", out], what, status=2)
    check(r.stderr == line + "\n", f"{what}: stderr {r.stderr!r}, expected {line!r}")
    check(not os.path.exists(out), f"{what}: the output folder was made")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        scene, other = os.path.join(tmp, "flag.json"), os.path.join(tmp, "other.json")
        with open(scene, "w") as f:
            json.dump(SCENE, f, indent=2)
        with open(other, "w") as f:
            json.dump(dict(SCENE, dt=0.002), f, indent=2)
        bake, bake2, other_bake = (os.path.join(tmp, n) for n in ("bake", "bake2", "other-bake"))
        run(SIM, [scene, "--bake", bake], "bake")
        run(SIM, [scene, "--bake", bake2, "--every", "2"], "bake --every 2")
        run(SIM, [other, "--bake", other_bake, "--frames", "2"], "another scene's bake")
        direct_dir = os.path.join(tmp, "direct")
        run(RENDER, [scene, "-o", direct_dir, "--quiet"], "direct render")
        direct = tooltest.contents(direct_dir)
        check(len(direct) == FRAMES + 1, f"the direct render wrote {len(direct)} images, not {FRAMES + 1}")
        check(len(set(direct.values())) == FRAMES + 1, "the direct render's images are not all "
              "different: the cloth does not move, nothing is tested")

        from_bake(tmp, scene, bake, [1, 2, 3, 4], direct, "--frames 1:4")
        from_bake(tmp, scene, bake, [5], direct, "--frames 5:5")
        from_bake(tmp, scene, bake, [0], direct, "--frames 0:0")
        from_bake(tmp, scene, bake, list(range(FRAMES + 1)), direct, "all frames")
        from_bake(tmp, scene, bake2, [0, 2, 4, 6], direct, "all frames every 2")
        from_bake(tmp, scene, bake2, [2], direct, "--frames 2:2 every 2")

        refused(tmp, [scene, "--from", bake2, "--frames", "1:3"],
                f"clothvk-render: {bake2}: frame 1 is not in the bake (it holds frames 0 to 6, every 2)",
                "a frame an every-2 bake does not hold")
        refused(tmp, [scene, "--from", bake, "--frames", f"4:{FRAMES + 1}"],
                f"clothvk-render: {bake}: frame {FRAMES + 1} is not in the bake (it holds frames 0 "
                f"to {FRAMES}, every 1)", "a frame past the bake")
        refused(tmp, [scene, "--frames", "1:4"],
                "clothvk-render: --frames A:B needs --from BAKE (without it --frames is a count)",
                "--frames A:B without --from")
        refused(tmp, [scene, "--from", bake, "--every", "2"],
                "clothvk-render: --from: give the frames as --frames A:B (--every has no meaning here)",
                "--every with --from")
        refused(tmp, [scene, "--from", bake, "--video", os.path.join(tmp, "v.mp4")],
                "clothvk-render: --video and --from: a video is made while simulating; render "
                "the bake's frames to PNGs and encode those",
                "--video with --from")
        refused(tmp, [scene, "--from", bake, "--frames", "4:2"],
                "clothvk-render: --frames: expected A:B, whole numbers with A <= B, got 4:2",
                "--frames 4:2")
        missing = os.path.join(tmp, "nothing")
        refused(tmp, [scene, "--from", missing],
                f"clothvk-render: {missing}: no bake here ({missing}/cache.json: No such file or "
                "directory)", "a missing bake")
        refused(tmp, [scene, "--from", other_bake],
                f"clothvk-render: {other_bake}: baked from another scene: dt is 0.002 in the bake, "
                "0.004 here", "another scene's bake")
        same = os.path.join(tmp, "same-scene-set")
        run(RENDER, [scene, "-o", same, "--from", bake, "--frames", "3:3", "--quiet", "--set", "dt=4e-3"],
            "--from with a --set item that leaves the scene as baked")
        got = tooltest.contents(same)
        check(list(got) == ["frame_0003.png"] and got["frame_0003.png"] == direct["frame_0003.png"],
              f"--from with --set dt=4e-3: images {sorted(got)}, expected frame_0003.png as the direct one")
        drawn = ["--set", "render.ao=false", "--set", "render.size=[80,48]",
                 "--set", "cloths.0.color=[0.1,0.7,0.3]", "--set", "cloths.0.material.sheen=0"]
        redrawn_direct = os.path.join(tmp, "redrawn-direct")
        run(RENDER, [scene, "-o", redrawn_direct, "--quiet"] + drawn, "direct render, drawn otherwise")
        redrawn = os.path.join(tmp, "redrawn")
        run(RENDER, [scene, "-o", redrawn, "--from", bake, "--frames", "3:3", "--quiet"] + drawn,
            "--from with render keys and a cloth's colour and material not the bake's")
        got, want = tooltest.contents(redrawn), tooltest.contents(redrawn_direct)
        check(list(got) == ["frame_0003.png"] and got["frame_0003.png"] == want.get("frame_0003.png"),
              f"--from drawn otherwise: images {sorted(got)}, expected frame_0003.png as the "
              "direct render drawn the same way")
        check(got.get("frame_0003.png") != direct["frame_0003.png"],
              "--from drawn otherwise: the image is the bake scene's own: the --set items did nothing")
    return CHECKS.finish("bake-render: images from bakes equal the direct render's; bad input refused")


sys.exit(main())
