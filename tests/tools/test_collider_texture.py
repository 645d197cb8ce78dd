#!/usr/bin/env python3
"""A collider's texture as clothvk-render draws it (colliders.N.material.texture, texture_scale),
checked on what the picture shows, with a black and white checker the test writes (2 x 2
squares per repeat):

- a wall (a plane collider facing the camera) without a texture is one colour across the middle
  of the picture (every channel within a few levels); with the checker it shows both squares
  (dark and light pixels far apart);
- a static plane facing up is the ground: with the checker, the ground shows it across the middle
  of the picture, where the plain ground has its faint checkerboard alone (within 20 levels);
- texture_scale is metres per repeat: along a row across the middle third of the wall, half
  the scale gives twice the light-dark edges (within two), and their count matches the width
  of wall seen there (2 edges per repeat, within 1.5);
- the texture moves with a keyframed collider: the wall moved along itself by one square of the
  checker turns light for dark across the middle of the picture (a texture fixed in the scene
  would not change);
- a textured box moved by keyframes draws the same picture as a static box at its destination
  (every channel within 2 levels; the box's texture frame is its own), and not the picture of
  the box where it started;
- the keyframed box's images are the same bytes on four lavapipe threads and on one;
- several colliders naming the same file share one texture: 8 of them draw (a texture file
  each would be one too many).

    test_collider_texture.py CLOTHVK_RENDER
"""
import json
import math
import os
import struct
import sys
import tempfile
import zlib

import tooltest

RENDER = sys.argv[1] if len(sys.argv) > 1 else tooltest.tool_paths("clothvk-render")[0]
WIDTH, HEIGHT = 320, 180
FOV_Y = 40.0
DISTANCE = 2.0  # m from the eye to the wall


def write_checker(path):
    """A 64 x 64 RGB checker: 2 x 2 squares of 32 texels, black (30) and white (230)."""
    rows = []
    for y in range(64):
        row = []
        for x in range(64):
            v = 230 if (x // 32 + y // 32) % 2 == 0 else 30
            row += [v, v, v]
        rows.append(row)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    raw = b"".join(b"\0" + bytes(r) for r in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 64, 64, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def base(colliders, eye, target, frames=1, ground=False):
    """A small pinned cloth out of sight behind the camera, the colliders, no ground unless
    asked for."""
    return {
        "name": "texture", "dt": 0.002, "substeps": 2, "frames": frames,
        "solver": {"linear": "rbgs", "outer_iterations": 1, "inner_iterations": 1},
        "cloths": [{"grid": [3, 3], "size": [0.1, 0.1], "origin": [-0.05, 0.5, 5.0], "u_axis": [1, 0, 0],
                    "v_axis": [0, 0, 1], "mass": 0.01, "pins": [[0, 0], [2, 0], [0, 2], [2, 2]]}],
        "colliders": colliders,
        "render": {"eye": eye, "target": target, "fov_y": FOV_Y, "samples": 1, "ground": ground,
                   "ao": False},
    }


def wall(material=None, keyframes=None):
    """A plane through the origin facing +z, seen square on from DISTANCE."""
    plane = {"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1], "color": [0.5, 0.5, 0.5]}
    if material is not None:
        plane["material"] = material
    if keyframes:
        plane["keyframes"] = keyframes
    return base([plane], [0, 0, DISTANCE], [0, 0, 0], frames=3 if keyframes else 1)


def floor(material=None):
    """A static plane facing up, which the renderer draws as the ground, seen from above."""
    plane = {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}
    if material is not None:
        plane["material"] = material
    return base([plane], [0, 2.0, 2.0], [0, 0, 0], ground=True)


def box(center, keyframes=None):
    b = {"type": "box", "center": center, "half_extents": [0.3, 0.3, 0.3],
         "material": {"texture": "checker.png", "texture_scale": 0.23}}
    if keyframes:
        b["keyframes"] = keyframes
    return base([b], [0.8, 1.2, 2.0], [0.2, 0.0, 0.0], frames=3)


def render(tmp, name, desc, threads=None):
    """Renders desc (on `threads` lavapipe threads, if given); returns (problems, (width,
    channels, pixels)) of its last frame. Anything on stderr (a validation message) is a
    problem."""
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(desc, f)
    out = os.path.join(tmp, name)
    env = dict(os.environ, LP_NUM_THREADS=threads) if threads is not None else None
    p = tooltest.run_tool(RENDER, [path, "-o", out, "--size", f"{WIDTH}x{HEIGHT}", "--quiet"], env=env)
    if p.returncode != 0 or p.stderr:
        return [f"{name}: exit status {p.returncode}: {p.stderr.strip()}"], None
    last = sorted(n for n in os.listdir(out) if n.endswith(".png"))[-1]
    return [], tooltest.png_pixels(os.path.join(out, last))


def middle(image):
    """The channel values of the middle third of the picture, each way."""
    width, n, px = image
    height = len(px) // (width * n)
    return [px[(y * width + x) * n + k] for y in range(height // 3, 2 * height // 3)
            for x in range(width // 3, 2 * width // 3) for k in range(3)]


def edges(image):
    """Light-dark changes along the middle third of the middle row (a change: crossing the mid
    grey); the wall, a square around the cloth's reach, covers at least that."""
    width, n, px = image
    height = len(px) // (width * n)
    y = height // 2
    light = [px[(y * width + x) * n] > 128 for x in range(width // 3, 2 * width // 3)]
    return sum(light[x] != light[x - 1] for x in range(1, len(light)))


def main():
    cases = tooltest.Cases("collider texture")
    with tempfile.TemporaryDirectory(prefix="clothvk-collider-texture-") as tmp:
        write_checker(os.path.join(tmp, "checker.png"))
        problems, plain = render(tmp, "plain", wall())
        more, textured = render(tmp, "textured", wall({"texture": "checker.png", "texture_scale": 0.5}))
        problems += more
        if not problems:
            p, t = middle(plain), middle(textured)
            if max(p) - min(p) > 4:
                problems.append(f"the plain wall spans {min(p)} to {max(p)}; expected one colour")
            if max(t) - min(t) < 100:
                problems.append(f"the textured wall spans only {min(t)} to {max(t)}; expected the checker's "
                                "dark and light squares")
        cases.add("a textured wall shows its checker where a plain one is uniform", problems)

        problems, plain = render(tmp, "plain-floor", floor())
        more, textured = render(tmp, "textured-floor", floor({"texture": "checker.png", "texture_scale": 0.5}))
        problems += more
        if not problems:
            p, t = middle(plain), middle(textured)
            if max(p) - min(p) > 20:
                problems.append(f"the plain ground spans {min(p)} to {max(p)}; expected its faint checker alone")
            if max(t) - min(t) < 100:
                problems.append(f"the textured ground spans only {min(t)} to {max(t)}; expected the checker's "
                                "dark and light squares")
        cases.add("a textured ground plane shows its checker where the plain ground is nearly uniform", problems)

        problems, coarse = render(tmp, "coarse", wall({"texture": "checker.png", "texture_scale": 0.2}))
        more, fine = render(tmp, "fine", wall({"texture": "checker.png", "texture_scale": 0.1}))
        problems += more
        if not problems:
            coarse_edges, fine_edges = edges(coarse), edges(fine)
            # The width of the middle third of the frame at the wall, in m; 2 edges per repeat.
            seen = 2 * DISTANCE * math.tan(math.radians(FOV_Y) / 2) * WIDTH / HEIGHT / 3
            expected = 2 * seen / 0.1
            if abs(fine_edges - 2 * coarse_edges) > 2:
                problems.append(f"{coarse_edges} edges at texture_scale 0.2, {fine_edges} at 0.1; expected twice "
                                "as many")
            if abs(fine_edges - expected) > 1.5:
                problems.append(f"{fine_edges} edges across {seen:.3f} m of wall at 0.1 m a repeat; "
                                f"expected {expected:.1f}")
        cases.add("texture_scale is metres per repeat", problems)

        # One square (half a repeat) along the wall: a checker that moves with it turns light for
        # dark; one fixed in the scene would stay as it was.
        checker = {"texture": "checker.png", "texture_scale": 0.2}
        shift = [{"time": 0}, {"time": 0.004, "translation": [0.1, 0, 0]}]
        problems, still = render(tmp, "still", wall(checker))
        more, slid = render(tmp, "slid", wall(checker, shift))
        problems += more
        if not problems:
            a, b = middle(still), middle(slid)
            decided = [(x > 128, y > 128) for x, y in zip(a, b) if abs(x - 128) > 40 and abs(y - 128) > 40]
            flipped = sum(x != y for x, y in decided) / max(len(decided), 1)
            if len(decided) < len(a) // 2 or flipped < 0.95:
                problems.append(f"{100 * flipped:.1f} % of {len(decided)} clearly light or dark values turned over "
                                "after the wall moved one square; expected nearly all")
        cases.add("the texture moves with a keyframed wall", problems)

        moved = [{"time": 0}, {"time": 0.004, "translation": [0.37, 0, 0]}]
        problems, moving = render(tmp, "moving", box([0, 0, 0], moved))
        more, there = render(tmp, "there", box([0.37, 0, 0]))
        problems += more
        more, start = render(tmp, "start", box([0, 0, 0]))
        problems += more
        if not problems:
            worst = max(abs(a - b) for a, b in zip(moving[2], there[2]))
            if worst > 2:
                problems.append(f"the moved box differs from a box placed there by up to {worst} levels")
            if max(abs(a - b) for a, b in zip(moving[2], start[2])) <= 2:
                problems.append("the keyframed box did not move")
        cases.add("a keyframed textured box draws what a box placed where it went draws", problems)

        # The same bytes, image for image, on four lavapipe threads and on one.
        problems = []
        for threads in ("4", "0"):
            problems += render(tmp, "threads-" + threads, box([0, 0, 0], moved), threads)[0]
        for name in [] if problems else sorted(os.listdir(os.path.join(tmp, "threads-4"))):
            with open(os.path.join(tmp, "threads-4", name), "rb") as a, \
                    open(os.path.join(tmp, "threads-0", name), "rb") as b:
                if a.read() != b.read():
                    problems.append(f"{name} differs between 4 lavapipe threads and 1")
        cases.add("the same bytes on 4 threads and on 1", problems)

        legs = [{"type": "sphere", "center": [0.3 * i - 1.05, 0, 0], "radius": 0.1,
                 "material": {"texture": "checker.png"}} for i in range(8)]
        problems, _ = render(tmp, "shared", base(legs, [0, 0, 3], [0, 0, 0]))
        cases.add("8 colliders with one texture file draw", problems)
    return cases.finish()


if __name__ == "__main__":
    sys.exit(main())
