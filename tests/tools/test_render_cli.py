#!/usr/bin/env python3
"""clothvk-render as a person meets it: exact messages and exit statuses for bad arguments, a
bad scene and an unusable output folder; the images and the summary for good input; the same
scene rendered twice, on four lavapipe threads and on one, gives the same PNG bytes.

    python3 tests/tools/test_render_cli.py PATH/TO/clothvk-render

Every run has a fresh temporary directory as its working directory. A bad-input case must exit
with status 2, print exactly one line on stderr (compared whole), print nothing on stdout and
leave the directory as it found it (no output folder, no image, no temporary file). A good
case must exit with status 0 and print nothing on stderr (validation messages included).
"""
import os
import re
import subprocess
import sys
import tempfile

import tooltest

[RENDER] = tooltest.tool_paths("clothvk-render")
ROOT = tooltest.ROOT

SCENES = os.path.join(ROOT, "tests", "scenes")
SMALL = os.path.join(SCENES, "small.json")
FLAG = os.path.join(ROOT, "assets", "scenes", "flag.json")
HANGING = os.path.join(ROOT, "assets", "scenes", "hanging.json")
# hanging.json made small enough for a test: 24 x 24 particles, 160 x 90 pixels.
TINY = [HANGING, "--set", "cloths.0.grid=[24,24]", "--set", "cloths.0.pins=[[0,0],[23,0]]", "--size", "160x90"]

# Stands for lavapipe's device name in an expected line (see tooltest.line_matches).
LLVMPIPE = tooltest.LLVMPIPE


def error(message):
    return tooltest.tool_line("clothvk-render", message)


def images(folder):
    return sorted(n for n in os.listdir(folder) if n.endswith(".png"))


def expect_images(folder, names, width, height):
    problems = []
    if not os.path.isdir(folder):
        return [f"{folder} was not created"]
    found = sorted(os.listdir(folder))
    if found != names:
        problems.append(f"{folder} holds {found}, expected {names}")
    for name in names:
        try:
            w, h, _ = tooltest.png_info(os.path.join(folder, name))
            if (w, h) != (width, height):
                problems.append(f"{name} is {w}x{h}, expected {width}x{height}")
        except (OSError, ValueError) as e:
            problems.append(f"{name}: {e}")
    return problems


def summary_check(pattern):
    def check(stdout, workdir):
        line = stdout.strip()
        return [] if re.fullmatch(pattern, line) else [f"summary {line!r} does not match {pattern!r}"]
    return check


def folder_check(folder, names, width, height, also=None):
    def check(stdout, workdir):
        problems = expect_images(os.path.join(workdir, folder), names, width, height)
        if also:
            problems += also(stdout, workdir)
        return problems
    return check


def quiet_check(stdout, workdir):
    return ([f"--quiet printed {stdout!r}"] if stdout else []) + \
        expect_images(os.path.join(workdir, "q"), ["frame_0000.png", "frame_0001.png", "frame_0002.png"],
                      64, 48)


FRAMES = [f"frame_{i:04d}.png" for i in range(4)]
NUMBER = r"[0-9]+\.[0-9]"

CASES = [
    # Arguments.
    {"name": "no output folder", "argv": [SMALL], "status": 2,
     "stderr": error("no output folder given (-o DIR)")},
    {"name": "size 0", "argv": [SMALL, "-o", "out", "--size", "0x720"], "status": 2,
     "stderr": error("--size: expected WIDTHxHEIGHT in pixels, each at least 1, got 0x720")},
    {"name": "negative size", "argv": [SMALL, "-o", "out", "--size", "-640x480"], "status": 2,
     "stderr": error("--size: expected WIDTHxHEIGHT in pixels, each at least 1, got -640x480")},
    {"name": "size without height", "argv": [SMALL, "-o", "out", "--size", "640"], "status": 2,
     "stderr": error("--size: expected WIDTHxHEIGHT in pixels, each at least 1, got 640")},
    {"name": "size above the device's limit", "argv": [SMALL, "-o", "out", "--size", "20000x720"], "status": 2,
     "env": {"CLOTHVK_DEVICE": "llvmpipe"},
     "stderr": error(f"--size 20000x720: {LLVMPIPE} draws at most 16384 x 16384 pixels")},
    {"name": "scene size above the device's limit", "argv": [SMALL, "-o", "out", "--set", "render.size=[100,20000]"],
     "status": 2, "env": {"CLOTHVK_DEVICE": "llvmpipe"},
     "stderr": error(f"{SMALL}: render.size: 100 x 20000 pixels is more than {LLVMPIPE} allows (16384 x 16384)")},
    # Within the largest image size, but an image larger than the device allows for one image
    # (4 GiB − 1 on lavapipe), or than the memory heap it would come from (lavapipe's: 2 GiB):
    # a device limit found before any frame, not a validation error.
    {"name": "image larger than the device allows", "argv": [SMALL, "-o", "out", "--size", "16384x16384"],
     "status": 2, "env": {"CLOTHVK_DEVICE": "llvmpipe"},
     "stderr": error(f"{SMALL}: cloth image: 16384 x 16384 pixels at 4 samples take 4294967296 bytes "
                     f"(4.0 GiB); {LLVMPIPE} allows 4294967295 bytes for one image (maxResourceSize)")},
    {"name": "image larger than the memory heap", "argv": [SMALL, "-o", "out", "--size", "12000x12000"],
     "status": 2, "env": {"CLOTHVK_DEVICE": "llvmpipe"},
     "stderr": error(f"{SMALL}: cloth image needs 2304000000 bytes (2.1 GiB) in one allocation; "
                     f"{LLVMPIPE}'s memory heap 0 holds {tooltest.HEAP_SIZE}")},
    {"name": "samples the device lacks", "argv": [SMALL, "-o", "out", "--set", "render.samples=8"], "status": 2,
     "env": {"CLOTHVK_DEVICE": "llvmpipe"},
     "stderr": error(f"{SMALL}: render.samples: {LLVMPIPE} draws 1 or 4 samples per pixel, not 8")},
    {"name": "every 0", "argv": [SMALL, "-o", "out", "--every", "0"], "status": 2,
     "stderr": error("--every: expected a whole number from 1 to 100000000, got 0")},
    {"name": "frames 0", "argv": [SMALL, "-o", "out", "--frames", "0"], "status": 2,
     "stderr": error("--frames: expected a whole number from 1 to 100000000, got 0")},
    {"name": "unknown option", "argv": [SMALL, "-o", "out", "--fps", "30"], "status": 2,
     "stderr": error("unknown option --fps (see --help)")},
    # GNU style: --option=value as --option value.
    {"name": "frames=0", "argv": [SMALL, "--output=out", "--frames=0"], "status": 2,
     "stderr": error("--frames: expected a whole number from 1 to 100000000, got 0")},
    {"name": "size=0x720", "argv": [SMALL, "-o", "out", "--size=0x720"], "status": 2,
     "stderr": error("--size: expected WIDTHxHEIGHT in pixels, each at least 1, got 0x720")},
    {"name": "a flag with a value", "argv": [SMALL, "-o", "out", "--quiet=yes"], "status": 2,
     "stderr": error("--quiet takes no value, got --quiet=yes")},
    {"name": "unknown option with a value", "argv": [SMALL, "-o", "out", "--fps=30"], "status": 2,
     "stderr": error("unknown option --fps=30 (see --help)")},
    # The scene.
    {"name": "unknown render key", "argv": [SMALL, "-o", "out", "--set", "render.fov=40"], "status": 2,
     "stderr": error(f"{SMALL}: render.fov (from --set): unknown key (expected one of: size, eye, target, up, "
                     "fov_y, key, fill, ambient, background, ground, ground_height, ground_color, "
                     "shadow_map_size, samples, wireframe, camera_keyframes, camera_loop, soft_shadows, key_angle, sky_light, ao, ao_radius, tone_map, smooth, fit, overlay, vertex_lighting)")},
    {"name": "bad render value", "argv": [SMALL, "-o", "out", "--set", "render.key.direction=[0,0,0]"],
     "status": 2, "stderr": error(f"{SMALL}: render.key.direction (from --set): must not be zero, got [0, 0, 0]")},
    # render.fit: true, false or an object with a margin, and no camera that places itself.
    {"name": "fit not a boolean", "argv": [SMALL, "-o", "out", "--set", 'render.fit="yes"'], "status": 2,
     "stderr": error(f'{SMALL}: render.fit (from --set): expected true, false or an object such as '
                     '{"margin": 0.1}, got the string "yes"')},
    {"name": "fit margin too wide", "argv": [SMALL, "-o", "out", "--set", 'render.fit={"margin": 0.5}'],
     "status": 2, "stderr": error(f"{SMALL}: render.fit.margin (from --set): must be between 0 and 0.45, got 0.5")},
    {"name": "fit with an eye alone", "argv": [SMALL, "-o", "out", "--set", "render.fit=true",
                                               "--set", "render.eye=[0,1,3]"], "status": 2,
     "stderr": error(f"{SMALL}: render.fit (from --set): takes its view direction from render.eye - "
                     "render.target: give both or neither, got only render.eye")},
    {"name": "overlay not a boolean", "argv": [SMALL, "-o", "out", "--set", "render.overlay=1"], "status": 2,
     "stderr": error(f"{SMALL}: render.overlay (from --set): expected true or false, got the number 1")},
    # A cloth's texture (read when the renderer is made, before any image).
    {"name": "missing texture", "argv": [SMALL, "-o", "out", "--set", 'cloths.0.texture="no-such.png"'],
     "status": 2, "stderr": error(f"{SMALL}: cloths.0.texture: {SCENES}/no-such.png: cannot open: "
                                  "No such file or directory")},
    {"name": "texture not an image", "argv": [SMALL, "-o", "out", "--set", 'cloths.0.texture="small.json"'],
     "status": 2, "stderr": error(f"{SMALL}: cloths.0.texture: {SCENES}/small.json: not an image stb_image can "
                                  "read (unknown image type)")},
    {"name": "texture too large", "argv": [SMALL, "-o", "out", "--set", 'cloths.0.texture="wide-texture.png"'],
     "status": 2, "env": {"CLOTHVK_DEVICE": "llvmpipe"},
     "stderr": error(f"{SMALL}: cloths.0.texture: {SCENES}/wide-texture.png: 20000 x 1 texels is more than "
                     f"{LLVMPIPE} allows (16384 x 16384)")},
    {"name": "texture on a mesh without texture coordinates",
     "argv": [FLAG, "-o", "out", "--set", 'cloths.0.texture="../textures/plaid.png"'], "status": 2,
     "stderr": error(f"{FLAG}: cloths.0.texture: {ROOT}/assets/scenes/../meshes/flag.obj has no texture "
                     "coordinates to map the texture by")},
    # A cloth's material block.
    {"name": "unknown material key", "argv": [SMALL, "-o", "out", "--set", "cloths.0.material.shine=1"],
     "status": 2, "stderr": error(f"{SMALL}: cloths.0.material.shine (from --set): unknown key (expected one of: "
                                  "color, back_color, texture, sheen, roughness, thickness, normal_map, "
                                  "normal_strength)")},
    {"name": "material texture not an image",
     "argv": [SMALL, "-o", "out", "--set", 'cloths.0.material.texture="small.json"'], "status": 2,
     "stderr": error(f"{SMALL}: cloths.0.material.texture: {SCENES}/small.json: not an image stb_image can "
                     "read (unknown image type)")},
    {"name": "material texture on a mesh without texture coordinates",
     "argv": [FLAG, "-o", "out", "--set", 'cloths.0.material.texture="../textures/plaid.png"'], "status": 2,
     "stderr": error(f"{FLAG}: cloths.0.material.texture: {ROOT}/assets/scenes/../meshes/flag.obj has no texture "
                     "coordinates to map the texture by")},
    {"name": "sheen out of range", "argv": [SMALL, "-o", "out", "--set", "cloths.0.material.sheen=1.5"],
     "status": 2, "stderr": error(f"{SMALL}: cloths.0.material.sheen (from --set): must be between 0 and 1, "
                                  "got 1.5")},
    {"name": "roughness out of range", "argv": [SMALL, "-o", "out", "--set", "cloths.0.material.roughness=0"],
     "status": 2, "stderr": error(f"{SMALL}: cloths.0.material.roughness (from --set): must be between 0.1 "
                                  "and 1, got 0")},
    {"name": "normal map not an image",
     "argv": [SMALL, "-o", "out", "--set", 'cloths.0.material.normal_map="small.json"'], "status": 2,
     "stderr": error(f"{SMALL}: cloths.0.material.normal_map: {SCENES}/small.json: not an image stb_image can "
                     "read (unknown image type)")},
    {"name": "normal strength out of range",
     "argv": [SMALL, "-o", "out", "--set", "cloths.0.material.normal_strength=3"], "status": 2,
     "stderr": error(f"{SMALL}: cloths.0.material.normal_strength (from --set): must be between 0 and 2, "
                     "got 3")},
    {"name": "thickness out of range", "argv": [SMALL, "-o", "out", "--set", "cloths.0.material.thickness=0.1"],
     "status": 2, "stderr": error(f"{SMALL}: cloths.0.material.thickness (from --set): must be between 0 and "
                                  "0.05, got 0.1")},
    {"name": "back colour out of range",
     "argv": [SMALL, "-o", "out", "--set", "cloths.0.material.back_color=[0.2,2,0.2]"], "status": 2,
     "stderr": error(f"{SMALL}: cloths.0.material.back_color.1 (from --set): must be between 0 and 1, got 2")},
    # A collider's material block.
    {"name": "unknown collider material key",
     "argv": [SMALL, "-o", "out", "--set", 'colliders=[{"type": "sphere", "material": {"shine": 1}}]'],
     "status": 2, "stderr": error(f"{SMALL}: colliders.0.material.shine (from --set): unknown key (expected one "
                                  "of: color, roughness, texture, texture_scale)")},
    # A collider's texture: read when the renderer is made, with the messages of a cloth's.
    {"name": "missing collider texture",
     "argv": [SMALL, "-o", "out", "--set", 'colliders=[{"type": "sphere", "material": {"texture": "no-such.png"}}]'],
     "status": 2, "stderr": error(f"{SMALL}: colliders.0.material.texture: {SCENES}/no-such.png: cannot open: "
                                  "No such file or directory")},
    {"name": "collider texture not an image",
     "argv": [SMALL, "-o", "out", "--set", 'colliders=[{"type": "sphere", "material": {"texture": "small.json"}}]'],
     "status": 2, "stderr": error(f"{SMALL}: colliders.0.material.texture: {SCENES}/small.json: not an image "
                                  "stb_image can read (unknown image type)")},
    {"name": "collider texture an empty string",
     "argv": [SMALL, "-o", "out", "--set", 'colliders=[{"type": "sphere", "material": {"texture": ""}}]'],
     "status": 2, "stderr": error(f"{SMALL}: colliders.0.material.texture (from --set): must name an image file, "
                                  "got an empty string")},
    {"name": "collider texture not a string",
     "argv": [SMALL, "-o", "out", "--set", 'colliders=[{"type": "sphere", "material": {"texture": 3}}]'],
     "status": 2, "stderr": error(f"{SMALL}: colliders.0.material.texture (from --set): expected a string, got "
                                  "the number 3")},
    {"name": "collider texture scale 0",
     "argv": [SMALL, "-o", "out", "--set", 'colliders=[{"type": "sphere", "material": {"texture_scale": 0}}]'],
     "status": 2, "stderr": error(f"{SMALL}: colliders.0.material.texture_scale (from --set): must be greater "
                                  "than 0, got 0")},
    {"name": "collider texture scale not a number",
     "argv": [SMALL, "-o", "out", "--set", 'colliders=[{"type": "sphere", "material": {"texture_scale": "big"}}]'],
     "status": 2, "stderr": error(f"{SMALL}: colliders.0.material.texture_scale (from --set): expected a number, "
                                  'got the string "big"')},
    # Eight texture files (none read: the count is checked first) are one more than the sets.
    {"name": "too many collider textures",
     "argv": [SMALL, "-o", "out", "--set", "colliders=[" + ", ".join(
         f'{{"type": "sphere", "material": {{"texture": "t{i}.png"}}}}' for i in range(8)) + "]"],
     "status": 2, "stderr": error(f"{SMALL}: colliders.7.material.texture: 0 cloths with a texture or a normal map "
                                  "and 7 collider texture files before this one; the renderer draws at most 7 in "
                                  "all")},
    {"name": "collider roughness out of range",
     "argv": [SMALL, "-o", "out", "--set", 'colliders=[{"type": "sphere", "material": {"roughness": 2}}]'],
     "status": 2, "stderr": error(f"{SMALL}: colliders.0.material.roughness (from --set): must be between 0.1 "
                                  "and 1, got 2")},
    {"name": "collider material colour out of range",
     "argv": [SMALL, "-o", "out", "--set", 'colliders=[{"type": "sphere", "material": {"color": [0, -1, 0]}}]'],
     "status": 2, "stderr": error(f"{SMALL}: colliders.0.color.1 (from --set): must be between 0 and 1, "
                                  "got -1")},
    {"name": "missing scene", "argv": ["no-such.json", "-o", "out"], "status": 2,
     "stderr": error("no-such.json: cannot open: No such file or directory")},
    # The output folder: an existing file in the way, under it, or a folder that takes no file.
    {"name": "output is a file", "argv": [SMALL, "-o", "taken"], "status": 2, "files": ["taken"],
     "stderr": error("taken: exists and is not a folder")},
    {"name": "output under a file", "argv": [SMALL, "-o", "taken/frames"], "status": 2, "files": ["taken"],
     "stderr": error("taken/frames: cannot create the output folder: Not a directory")},
    {"name": "output folder not writable", "argv": [SMALL, "-o", "locked"], "status": 2, "locked": "locked",
     "stderr": error("locked: cannot write into the output folder: Permission denied")},

    # Good input.
    {"name": "four images, every 3rd frame", "argv": TINY + ["-o", "a/b", "--frames", "10", "--every", "3"],
     "status": 0,
     "check": folder_check("a/b", FRAMES, 160, 90, summary_check(
         rf"hanging: 4 images of 160x90 in a/b \(frames 0 to 9 of 10, every 3\), {NUMBER} s; per image: "
         rf"simulation {NUMBER} ms, render {NUMBER} ms \(mesh {NUMBER}, shadow {NUMBER}, lit {NUMBER}, ao {NUMBER}, "
         rf"composite {NUMBER}, "
         rf"readback {NUMBER}\), png {NUMBER} ms \(beside the next image's work\); {NUMBER} ms wall"))},
    {"name": "fit over the sequence, overlay", "argv": TINY + ["-o", "fit", "--frames", "3", "--set", "render.fit=true",
                                                             "--set", "render.overlay=true"],
     "status": 0,
     "check": folder_check("fit", FRAMES, 160, 90, summary_check(
         rf"hanging: 4 images of 160x90 in fit \(frames 0 to 3 of 3, every 1\), {NUMBER} s; per image: "
         rf"simulation {NUMBER} ms, render {NUMBER} ms \(mesh {NUMBER}, shadow {NUMBER}, lit {NUMBER}, ao {NUMBER}, "
         rf"composite {NUMBER}, "
         rf"readback {NUMBER}\), overlay [0-9]+\.[0-9]{{2}} ms, png {NUMBER} ms \(beside the next image's work\); "
         rf"{NUMBER} ms wall"))},
    {"name": "--quiet", "argv": [SMALL, "-o", "q", "--frames", "2", "--size", "64x48", "--quiet"], "status": 0,
     "check": quiet_check},
    {"name": "--quiet, values after =", "argv": [SMALL, "--output=q", "--frames=2", "--size=64x48",
                                                  "--every=1", "--set=render.samples=1", "--quiet"],
     "status": 0, "check": quiet_check},
    {"name": "existing folder, images replaced", "argv": [SMALL, "-o", "f", "--frames", "1", "--size", "64x48"],
     "status": 0, "folders": ["f"], "files": ["f/frame_0000.png"],
     "check": folder_check("f", ["frame_0000.png", "frame_0001.png"], 64, 48)},
]


def run_case(case):
    """Runs one case in a fresh directory; returns a list of problems (or None: skipped)."""
    if case.get("locked") and os.geteuid() == 0:
        found = tooltest.unwritable_folder()
        if not found:
            return None
        folder, reason = found
        case = dict(case, locked=None, argv=[SMALL, "-o", folder],
                    stderr=error(f"{folder}: cannot write into the output folder: {reason}"))
    env = dict(os.environ, **case.get("env", {}))
    with tempfile.TemporaryDirectory(prefix="clothvk-render-cli-") as workdir:
        for folder in case.get("folders", []):
            os.makedirs(os.path.join(workdir, folder))
        for name in case.get("files", []):
            with open(os.path.join(workdir, name), "w") as f:
                f.write("not an image\n")
        if case.get("locked"):
            os.makedirs(os.path.join(workdir, case["locked"]))
            os.chmod(os.path.join(workdir, case["locked"]), 0o555)
        before = tooltest.listing(workdir)
        try:
            p = tooltest.run_tool(RENDER, case["argv"], workdir, env, timeout=180)
        except subprocess.TimeoutExpired:
            return ["timed out after 180 s"]
        if case["status"] != 0:
            return tooltest.refusal_problems(
                p, case["stderr"], before, tooltest.listing(workdir), case["status"],
                lambda lines: len(lines) == 1 and tooltest.line_matches(lines[0], case["stderr"]))
        return tooltest.accepted_problems(p, case["status"], workdir, case.get("check"))


def determinism():
    """The same scene rendered twice (every render effect on, as by default), the first time on
    four lavapipe threads, the second on one and with --serial (each image written before the
    next frame is simulated): the same PNG bytes, image for image."""
    with tempfile.TemporaryDirectory(prefix="clothvk-render-cli-") as workdir:
        for out, extra, threads in (("one", [], "4"), ("two", ["--serial"], "0")):
            env = dict(os.environ, LP_NUM_THREADS=threads)
            p = tooltest.run_tool(RENDER, TINY + ["-o", out, "--frames", "8", "--every", "4", "--quiet"]
                                  + extra, workdir, env, timeout=180)
            if p.returncode != 0 or p.stderr:
                return [f"run into {out} failed ({p.returncode}): {p.stderr.strip()}"]
        names = images(os.path.join(workdir, "one"))
        # --frames 8 --every 4: the states after 0, 4 and 8 frames.
        if names != ["frame_0000.png", "frame_0001.png", "frame_0002.png"] or \
                names != images(os.path.join(workdir, "two")):
            return [f"unexpected images: {names}"]
        problems = []
        for name in names:
            with open(os.path.join(workdir, "one", name), "rb") as a, open(os.path.join(workdir, "two", name), "rb") as b:
                if a.read() != b.read():
                    problems.append(f"{name} differs between two runs of the same scene")
        with open(os.path.join(workdir, "one", names[0]), "rb") as a, \
                open(os.path.join(workdir, "one", names[1]), "rb") as b:
            if a.read() == b.read():
                problems.append("frames 0 and 4 of a falling cloth are the same image")
        return problems


def main():
    cases = tooltest.Cases("render cli")
    for case in CASES:
        problems = run_case(case)
        if problems is None:
            cases.skip(f"{case['name']}: running as root, which writes into any folder, and /sys takes files")
        else:
            cases.add(f"{case['name']}: clothvk-render {' '.join(case['argv'])}", problems)
    cases.add("determinism", determinism())
    return cases.finish(count_skipped=True)


if __name__ == "__main__":
    sys.exit(main())
