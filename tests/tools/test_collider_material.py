#!/usr/bin/env python3
"""A collider's material as clothvk-render draws it (colliders.N.material):

- a material block with the default roughness (0.5) and the collider's colour draws the same
  bytes as no material block (the highlight it stands for is the one before the block existed);
- material.color is the collider's colour: the same bytes as colliders.N.color;
- a smooth collider (roughness 0.1) has a brighter highlight than the default, a rough one
  (roughness 1) a fainter one: the brightest pixel of the middle of the image, on the ball.

    test_collider_material.py CLOTHVK_RENDER
"""
import json
import os
import sys
import tempfile

import tooltest

RENDER = sys.argv[1] if len(sys.argv) > 1 else tooltest.tool_paths("clothvk-render")[0]
SIZE = "160x90"


def scene(material=None, color=None):
    """A small cloth pinned above a grey ball, seen close."""
    ball = {"type": "sphere", "name": "ball", "center": [0, 0.3, 0], "radius": 0.3}
    if color is not None:
        ball["color"] = color
    if material is not None:
        ball["material"] = material
    return {
        "name": "material", "dt": 0.002, "substeps": 2, "frames": 1,
        "solver": {"linear": "rbgs", "outer_iterations": 1, "inner_iterations": 1},
        "cloths": [{"grid": [3, 3], "size": [0.2, 0.2], "origin": [-0.1, 0.9, -0.1], "u_axis": [1, 0, 0],
                    "v_axis": [0, 0, 1], "mass": 0.01, "pins": [[0, 0], [2, 0], [0, 2], [2, 2]]}],
        "colliders": [ball],
        "render": {"eye": [0.9, 0.7, 1.1], "target": [0, 0.3, 0], "samples": 1},
    }


def render(tmp, name, desc):
    """Renders desc's frame 0; returns (problems, image bytes, brightest pixel's channel sum)."""
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(desc, f)
    out = os.path.join(tmp, name)
    p = tooltest.run_tool(RENDER, [path, "-o", out, "--frames", "1", "--size", SIZE, "--quiet"])
    if p.returncode != 0:
        return [f"{name}: exit status {p.returncode}: {p.stderr.strip()}"], b"", 0
    png = os.path.join(out, "frame_0000.png")
    with open(png, "rb") as f:
        data = f.read()
    width, n, px = tooltest.png_pixels(png)
    height = len(px) // (width * n)
    # The ball fills the middle of the picture (the camera looks at its centre).
    brightest = max(sum(px[(y * width + x) * n:(y * width + x) * n + 3])
                    for y in range(height * 3 // 10, height * 7 // 10)
                    for x in range(width * 3 // 10, width * 7 // 10))
    return [], data, brightest


def main():
    cases = tooltest.Cases("collider material")
    with tempfile.TemporaryDirectory(prefix="clothvk-collider-material-") as tmp:
        grey = [0.5, 0.5, 0.52]
        problems, plain, _ = render(tmp, "plain", scene(color=grey))
        more, default, mid = render(tmp, "default", scene(material={"color": grey, "roughness": 0.5}))
        problems += more
        if not problems and default != plain:
            problems.append("material {color, roughness 0.5} does not draw the same bytes as colliders.N.color alone")
        cases.add("the default roughness and material.color draw what colliders.N.color drew", problems)
        problems, _, smooth = render(tmp, "smooth", scene(color=grey, material={"roughness": 0.1}))
        more, _, rough = render(tmp, "rough", scene(color=grey, material={"roughness": 1}))
        problems += more
        if not problems and not smooth > mid > rough:
            problems.append(f"brightest pixel (sum of R, G, B): roughness 0.1 {smooth}, 0.5 {mid}, 1 {rough}; "
                            "expected it to fall as the roughness grows")
        cases.add("a smoother collider has a brighter highlight", problems)
    return cases.finish()


if __name__ == "__main__":
    sys.exit(main())
