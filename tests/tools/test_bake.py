#!/usr/bin/env python3
"""clothvk-sim --bake DIR / --resume DIR: a bake resumed gives the bits of an uninterrupted one.

    python3 tests/tools/test_bake.py PATH/TO/clothvk-sim

Good input, on a small swinging cloth:
- a bake of F frames holds cache.json (format, version 3, the scene text copied whole, frames,
  every, particles, snapshot size) and frame_0000.snap ... frame_{F}.snap (the start and the state
  after every frame: the last is the state --dump writes), nothing else;
- a bake of F/2 frames resumed to F gives the same files, byte for byte (cache.json included), and
  the same --dump as the uninterrupted bake;
- a full bake whose last frame file is deleted (an interrupted bake) and then resumed: the same;
- the same two with --every 3 (files 0, 1, 2 for frames 0, 3, 6 of 8) and with a --set item;
- a bake of 5 frames with dt 0.003 over one of 12 with dt 0.002 (and over another scene's) leaves
  frame_0000 ... frame_0005 only, and resumed to 12 frames equals an uninterrupted bake;
- one bake folder taken through six cycles over three scenes and two dt, each changing both the
  scene and dt (a bake of 8 frames re-baked with 1 to 6 frames of the next scene and dt, then
  resumed to 8): after each bake and each resume the folder holds exactly the files of the new
  run, each byte for byte as its uninterrupted bake's (cache.json too, once resumed);
- a --set item spelled with a space (cloths.0.grid=[8, 6]) resumes a bake made with [8,6];
- a complete bake resumed simulates nothing, writes no frame, and its --dump (the last frame
  file, loaded) equals the uninterrupted bake's: the bake's last state is --dump's.
Bad input: exit status 2, exactly one line on stderr (compared whole) and the bake folder as it was:
no folder, another scene's bake and other --set items (naming the key paths and both values), a
frame file cut short, one bit flipped in a frame (the CRC-32), the same scene under another run
hash in cache.json, another --every, --bake with
--resume, a link named as a frame for --bake and --resume, a folder named cache.json.
"""
import filecmp
import json
import os
import shutil
import sys
import tempfile
import zlib

import tooltest

[SIM] = tooltest.tool_paths("clothvk-sim")

FRAMES = 8
CLOTH = {"name": "flag", "grid": [8, 6], "size": [0.5, 0.4], "origin": [0.0, 1.0, 0.0],
         "u_axis": [1, 0, 0], "v_axis": [0, -1, 0], "mass": 0.1,
         "stiffness": {"structural": 1e4, "shear": 1e3, "bend": 10}, "pins": [[0, 0], [7, 0]]}
SCENE = {"name": "flag", "dt": 0.002, "substeps": 4, "frames": FRAMES,
         "solver": {"linear": "rbgs", "outer_iterations": 2, "inner_iterations": 2},
         "cloths": [CLOTH]}
SCENE_TEXT = json.dumps(SCENE, indent=2) + "\n"
OTHER_TEXT = json.dumps(dict(SCENE, dt=0.001), indent=2) + "\n"

CHECKS = tooltest.Checks()
check = CHECKS.check


def run(args):
    return tooltest.run_tool(SIM, args)


def ok(args, what):
    r = run(args)
    check(r.returncode == 0, f"{what}: exit {r.returncode}: {r.stderr.strip()}")
    return r


def same_bake(a, b, what):
    ca, cb = tooltest.contents(a), tooltest.contents(b)
    check(sorted(ca) == sorted(cb), f"{what}: files {sorted(cb)}, expected {sorted(ca)}")
    for name in ca:
        if name in cb and ca[name] != cb[name]:
            differ = sum(x != y for x, y in zip(ca[name], cb[name])) + abs(len(ca[name]) - len(cb[name]))
            check(False, f"{what}: {name} differs from the uninterrupted bake's in {differ} bytes")


def check_layout(folder, scene_text, frames, every, extra):
    files = tooltest.contents(folder)
    count = frames // every + 1
    expected = ["cache.json"] + [f"frame_{i:04d}.snap" for i in range(count)]
    check(sorted(files) == expected, f"{folder}: files {sorted(files)}, expected {expected}")
    cache = json.loads(files.get("cache.json", b"{}"))
    want = {"format": "clothvk-bake", "version": 3, "scene": scene_text, "frames": frames,
            "every": every, "substeps": 4, "particles": 48, "overrides": extra}
    for key, value in want.items():
        check(cache.get(key) == value, f"{folder}/cache.json: {key} is {cache.get(key)!r}, expected {value!r}")
    check(isinstance(cache.get("resolved"), str) and json.loads(cache["resolved"])["dt"] == 0.002,
          f"{folder}/cache.json: resolved is {cache.get('resolved')!r}, expected the scene as read")
    check(len(cache.get("run", "")) == 16, f"{folder}/cache.json: run is {cache.get('run')!r}")
    size = cache.get("snapshot_bytes")
    for name, data in files.items():
        if name.endswith(".snap"):
            check(len(data) == size and data[:7] == b"CVKSNAP",
                  f"{folder}/{name}: {len(data)} bytes starting {data[:8]!r}; expected {size} starting CVKSNAP")


def resumes(tmp, scene, every, sets):
    """Full bake; half bake resumed; full bake without its last frame resumed: all the same."""
    tag = f"every{every}{'-set' if sets else ''}"
    extra = sum((["--set", s] for s in sets), [])
    opts = ["--every", str(every)] if every != 1 else []
    full, half, cut = (os.path.join(tmp, f"{tag}-{n}") for n in ("full", "half", "cut"))
    ok([scene, "--frames", str(FRAMES), "--bake", full, "--dump", full + ".csv"] + opts + extra, f"{tag}: bake")
    check_layout(full, SCENE_TEXT, FRAMES, every, sets)
    ok([scene, "--frames", str(FRAMES // 2), "--bake", half] + opts + extra, f"{tag}: half bake")
    ok([scene, "--frames", str(FRAMES), "--resume", half, "--dump", half + ".csv"] + extra, f"{tag}: resume")
    same_bake(full, half, f"{tag}: half bake resumed")
    check(filecmp.cmp(full + ".csv", half + ".csv", shallow=False),
          f"{tag}: the resumed --dump differs from the uninterrupted bake's")
    shutil.copytree(full, cut)
    last = sorted(n for n in os.listdir(cut) if n.endswith(".snap"))[-1]
    os.remove(os.path.join(cut, last))
    ok([scene, "--resume", cut, "--dump", cut + ".csv"] + extra, f"{tag}: resume after {last} deleted")
    same_bake(full, cut, f"{tag}: interrupted bake resumed")
    check(filecmp.cmp(full + ".csv", cut + ".csv", shallow=False),
          f"{tag}: the --dump after resuming an interrupted bake differs")
    return full


def refused(args, line, folder, what):
    before = tooltest.contents(folder)
    r = run(args)
    check(r.returncode == 2, f"{what}: exit {r.returncode}, expected 2 ({r.stderr.strip()})")
    check(r.stderr == line + "\n", f"{what}: stderr {r.stderr!r}, expected {line!r}")
    check(r.stdout == "", f"{what}: printed {r.stdout!r}")
    check(tooltest.contents(folder) == before, f"{what}: the bake folder changed")


def bad_inputs(tmp, scene, other, full):
    missing = os.path.join(tmp, "nothing")
    refused([scene, "--resume", missing],
            f"clothvk-sim: {missing}: no bake here ({missing}/cache.json: No such file or directory)",
            missing, "no bake folder")
    # contents() is {} for an empty folder as for none: the folder must still not exist.
    check(not os.path.exists(missing), f"no bake folder: --resume made {missing}")
    other_bake = os.path.join(tmp, "other")
    ok([other, "--frames", "2", "--bake", other_bake], "another scene's bake")
    refused([scene, "--resume", other_bake],
            f"clothvk-sim: {other_bake}: baked from another scene: dt is 0.001 in the bake, 0.002 here",
            other_bake, "another scene's bake")
    corrupt = os.path.join(tmp, "corrupt")
    shutil.copytree(full, corrupt)
    last = os.path.join(corrupt, f"frame_{FRAMES:04d}.snap")
    size = os.path.getsize(last)
    with open(last, "r+b") as f:
        f.truncate(size - 100)
    refused([scene, "--resume", corrupt],
            f"clothvk-sim: {last}: cvk_sim_load_snapshot: the snapshot is {size - 100} bytes; its "
            f"header says {size} (truncated or padded)", corrupt, "a frame file cut short")
    refused([scene, "--resume", full, "--set", "damping=0.01"],
            f"clothvk-sim: {full}: baked from another scene: damping is not set in the bake, 0.01 here",
            full, "other --set items")
    refused([scene, "--resume", full, "--set", "cloths.0.grid=[8, 7]", "--set", "dt=0.003"],
            f"clothvk-sim: {full}: baked from another scene: cloths.0.grid.1 is 6 in the bake, 7 here; "
            "dt is 0.002 in the bake, 0.003 here", full, "two values differ")
    damaged = os.path.join(tmp, "damaged")
    shutil.copytree(full, damaged)
    last = os.path.join(damaged, f"frame_{FRAMES:04d}.snap")
    with open(last, "r+b") as f:
        data = bytearray(f.read())
        data[size // 2] ^= 0x04
        f.seek(0)
        f.write(data)
    stored = int.from_bytes(data[64:68], "little")
    computed = zlib.crc32(bytes(data[:64] + data[68:]))
    refused([scene, "--resume", damaged],
            f"clothvk-sim: {last}: cvk_sim_load_snapshot: the snapshot is damaged: its CRC-32 is "
            f"{computed:08x}, its header says {stored:08x}", damaged, "one bit flipped in a frame")
    linked = os.path.join(tmp, "linked")
    os.mkdir(linked)
    elsewhere = os.path.join(tmp, "elsewhere.txt")
    with open(elsewhere, "w") as f:
        f.write("not a frame\n")
    os.symlink(elsewhere, os.path.join(linked, "frame_0001.snap"))
    refused([scene, "--bake", linked],
            f"clothvk-sim: {linked}/frame_0001.snap: exists and is not a regular file (a link); it "
            "is not replaced", linked, "--bake into a folder with a link named as a frame")
    with open(elsewhere) as f:
        check(f.read() == "not a frame\n", "--bake into a folder with a link: its target changed")
    shutil.copytree(full, os.path.join(tmp, "linked-bake"))
    linked_bake = os.path.join(tmp, "linked-bake")
    os.remove(os.path.join(linked_bake, "frame_0003.snap"))
    os.symlink(elsewhere, os.path.join(linked_bake, "frame_0003.snap"))
    refused([scene, "--resume", linked_bake],
            f"clothvk-sim: {linked_bake}/frame_0003.snap: exists and is not a regular file (a link); "
            "it is not replaced", linked_bake, "--resume of a bake with a link named as a frame")
    folder_cache = os.path.join(tmp, "folder-cache")
    os.makedirs(os.path.join(folder_cache, "cache.json"))
    r = run([scene, "--bake", folder_cache])
    check(r.returncode == 2 and r.stderr == f"clothvk-sim: {folder_cache}/cache.json: exists and "
          "is not a regular file (a folder); it is not replaced\n",
          f"--bake with a folder named cache.json: exit {r.returncode}, {r.stderr!r}")
    check(tooltest.listing(folder_cache) == ["cache.json"],
          f"--bake with a folder named cache.json: wrote {tooltest.listing(folder_cache)}")
    # The same scene with another run hash: what a clothvk whose default dt or substeps changed
    # would find (the scene text alone does not say the run).
    rehashed = os.path.join(tmp, "rehashed")
    shutil.copytree(full, rehashed)
    with open(os.path.join(rehashed, "cache.json")) as f:
        cache = json.load(f)
    run_here, cache["run"] = cache["run"], "0123456789abcdef"
    with open(os.path.join(rehashed, "cache.json"), "w") as f:
        json.dump(cache, f, indent=2)
    refused([scene, "--resume", rehashed],
            f"clothvk-sim: {rehashed}: baked as run 0123456789abcdef (dt 0.002 s, 4 substeps); this "
            f"clothvk makes run {run_here} of the scene (dt 0.002 s, 4 substeps)", rehashed,
            "the same scene, another run hash")
    refused([scene, "--resume", full, "--every", "2"],
            f"clothvk-sim: --every 2: {full} was baked with --every 1", full, "another --every")
    refused([scene, "--bake", full, "--resume", full],
            "clothvk-sim: --bake and --resume: give one (--resume continues a bake)", full,
            "--bake with --resume")


def rebakes(tmp, scene, other_grid):
    """A bake over an earlier, longer one (another dt; another scene) leaves only its own frames,
    and resuming it gives the bits of an uninterrupted bake, not the earlier bake's leftovers."""
    direct = os.path.join(tmp, "rebake-direct")
    ok([scene, "--frames", "12", "--set", "dt=0.003", "--bake", direct, "--dump", direct + ".csv"],
       "rebake: the uninterrupted bake")
    for tag, first in (("dt", [scene, "--frames", "12"]), ("scene", [other_grid, "--frames", "12"])):
        folder = os.path.join(tmp, f"rebake-{tag}")
        ok(first + ["--bake", folder], f"rebake ({tag}): the first bake")
        ok([scene, "--frames", "5", "--set", "dt=0.003", "--bake", folder], f"rebake ({tag}): the second")
        names = sorted(tooltest.contents(folder))
        expected = ["cache.json"] + [f"frame_{i:04d}.snap" for i in range(6)]
        check(names == expected, f"rebake ({tag}): files {names} after the second bake, expected {expected}")
        ok([scene, "--frames", "12", "--set", "dt=0.003", "--resume", folder, "--dump", folder + ".csv"],
           f"rebake ({tag}): resume")
        same_bake(direct, folder, f"rebake ({tag}): resumed")
        check(filecmp.cmp(direct + ".csv", folder + ".csv", shallow=False),
              f"rebake ({tag}): the resumed --dump differs from the uninterrupted bake's")


def cycles(tmp, scenes):
    """One bake folder through every (scene, dt) of three scenes and two dt, each cycle changing
    both: a bake of FRAMES frames of one run is re-baked with fewer frames of the next run, which
    must leave only its own files (each frame's bytes those of the next run's uninterrupted bake),
    then resumed to FRAMES, which must equal that uninterrupted bake, cache.json included."""
    runs = [(0, "0.002"), (1, "0.003"), (2, "0.002"), (0, "0.003"), (1, "0.002"), (2, "0.003")]
    fewer = [3, 5, 1, 6, 2, 4]
    direct = {}
    for index, dt in runs:
        folder = os.path.join(tmp, f"cycle-direct-{index}-{dt}")
        ok([scenes[index], "--frames", str(FRAMES), "--set", f"dt={dt}", "--bake", folder],
           f"cycle: the uninterrupted bake of scene {index} at dt {dt}")
        direct[index, dt] = tooltest.contents(folder)
    sizes = {len(files["frame_0000.snap"]) for files in direct.values()}
    check(len(sizes) == 3, f"cycle: the three scenes' snapshots are {sorted(sizes)} bytes, expected three sizes")
    folder = os.path.join(tmp, "cycle")
    index, dt = runs[0]
    ok([scenes[index], "--frames", str(FRAMES), "--set", f"dt={dt}", "--bake", folder], "cycle: the first bake")
    check(tooltest.contents(folder) == direct[index, dt], "cycle: the first bake differs from the uninterrupted one")
    for cycle, frames in enumerate(fewer):
        index, dt = runs[(cycle + 1) % len(runs)]
        what = f"cycle {cycle + 1} (scene {index}, dt {dt}, a bake of {frames} frame{'s' * (frames != 1)})"
        args = [scenes[index], "--set", f"dt={dt}"]
        ok(args + ["--frames", str(frames), "--bake", folder], f"{what}: the bake")
        files, want = tooltest.contents(folder), direct[index, dt]
        expected = ["cache.json"] + [f"frame_{i:04d}.snap" for i in range(frames + 1)]
        check(sorted(files) == expected, f"{what}: files {sorted(files)} after the bake, expected {expected}")
        stale = [name for name in files if name != "cache.json" and files[name] != want.get(name)]
        check(not stale, f"{what}: {stale} after the bake differ from the uninterrupted bake's")
        ok(args + ["--frames", str(FRAMES), "--resume", folder], f"{what}: resume to {FRAMES} frames")
        files = tooltest.contents(folder)
        check(sorted(files) == sorted(want), f"{what}: files {sorted(files)} after the resume, "
              f"expected {sorted(want)}")
        differ = [name for name in want if files.get(name) != want[name]]
        check(not differ, f"{what}: {differ} after the resume differ from the uninterrupted bake's")


def complete(scene, full):
    before = tooltest.contents(full)
    r = ok([scene, "--resume", full, "--dump", full + "-again.csv"], "complete bake resumed")
    check(r.stdout.startswith("flag: 0 frames of 4 substeps") and
          f"  0 snapshots written in {full} (the bake: frames 0 to {FRAMES} of {FRAMES}, every 1)"
          in r.stdout.splitlines(), f"complete bake resumed: printed {r.stdout!r}")
    check(filecmp.cmp(full + ".csv", full + "-again.csv", shallow=False),
          f"complete bake resumed: the --dump from frame_{FRAMES:04d}.snap differs from the bake's own")
    after = tooltest.contents(full)
    check(sorted(after) == sorted(before) and all(after[n] == before[n] for n in before if n != "cache.json"),
          "complete bake resumed: frame files changed")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "flag.json")
        other = os.path.join(tmp, "other.json")
        with open(scene, "w") as f:
            f.write(SCENE_TEXT)
        with open(other, "w") as f:
            f.write(OTHER_TEXT)
        other_grid = os.path.join(tmp, "other-grid.json")
        with open(other_grid, "w") as f:
            json.dump(dict(SCENE, cloths=[dict(CLOTH, grid=[7, 6], pins=[[0, 0], [6, 0]])]), f)
        rebakes(tmp, scene, other_grid)
        third = os.path.join(tmp, "third.json")
        with open(third, "w") as f:
            json.dump(dict(SCENE, substeps=3, cloths=[dict(CLOTH, grid=[5, 5], pins=[[0, 0], [4, 0]])]), f)
        cycles(tmp, [scene, other_grid, third])
        full = resumes(tmp, scene, 1, [])
        complete(scene, full)
        resumes(tmp, scene, 3, [])
        resumes(tmp, scene, 1, ["solver.linear=\"jacobi\""])
        spaced = os.path.join(tmp, "spaced")
        ok([scene, "--frames", "4", "--bake", spaced, "--set", "cloths.0.grid=[8,6]"], "bake with a --set")
        ok([scene, "--frames", str(FRAMES), "--resume", spaced, "--set", "cloths.0.grid=[8, 6]"],
           "resume with the --set item spelled with a space")
        bad_inputs(tmp, scene, other, full)
    return CHECKS.finish("bake: resumed bakes equal uninterrupted ones; bad input refused")


sys.exit(main())
