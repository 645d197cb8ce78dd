#!/usr/bin/env python3
"""Writes the contact scenes whose geometry is computed rather than typed: a square cloth
twisted by two full turns while its held edges close in (assets/scenes/contact-twist.json),
six cloths dropped on a box (assets/scenes/contact-pile.json) and, for a GPU, 25 layers of
100 x 100 dropped on a cylinder (assets/scenes/contact-pile-large.json: 250,000 particles). Run
from the repository root; standard library only. The drape (assets/scenes/contact-drape.json) is written by hand."""
import json
import math
import os

SOLVER = {"linear": "rbgs", "outer_iterations": 4, "inner_iterations": 4, "omega": 1.5}
CONTACT = {"self": True, "friction": 0.3, "static_friction": 0.4}
STIFF = {"structural": 1000000.0, "shear": 1000000.0, "bend": 100.0}
GROUND = {"type": "plane", "name": "ground", "point": [0, 0, 0], "normal": [0, 1, 0],
          "color": [0.62, 0.6, 0.56]}


def render(eye, target):
    return {"size": [1280, 720], "eye": eye, "target": target, "fov_y": 40, "samples": 4}


def twist(n=24, side=0.6, turns=2.0, close_in=0.2, turn_time=3.0, steps_per_turn=8):
    """The cloth lies in the plane y = 1.2 across the x axis' span [-side/2, side/2]; its edge
    i = 0 is pinned, its edge i = n - 1 is an attachment that turns about the line y = 1.2,
    z = 0 (the cloth's own centre line) by `turns` full turns over `turn_time` s while moving
    `close_in` m towards the pinned edge, then holds. Keyframes every 1/steps_per_turn of a
    turn keep each slerp under half a turn."""
    height = 1.2
    keyframes = []
    count = int(turns * steps_per_turn)
    for k in range(count + 1):
        s = k / count
        angle = 2.0 * math.pi * turns * s
        # Rotation about the world x axis, then the axis lifted back to y = height:
        # p' = R p + t with t = (-close_in s, height, 0) - R (0, height, 0).
        c, si = math.cos(angle), math.sin(angle)
        t = [-close_in * s, height - c * height, -si * height]
        keyframes.append({"time": round(turn_time * s, 6),
                          "translation": [round(v, 7) for v in t],
                          "rotation": [round(math.cos(angle / 2), 7), round(math.sin(angle / 2), 7),
                                       0, 0]})
    return {
        "name": "contact-twist", "dt": 0.00208333333, "substeps": 8, "frames": 240,
        "damping": 0.002, "solver": SOLVER, "collision": CONTACT,
        "cloths": [{
            "name": "towel", "grid": [n, n], "size": [side, side],
            "origin": [-side / 2, height, -side / 2], "u_axis": [1, 0, 0], "v_axis": [0, 0, 1],
            "mass": 0.05, "stiffness": STIFF,
            "pins": [[0, j] for j in range(n)], "color": [0.25, 0.5, 0.75],
        }],
        "attachments": [{"cloth": 0, "pins": [[n - 1, j] for j in range(n)],
                         "keyframes": keyframes}],
        "render": render([1.2, 1.6, 1.4], [0, 1.2, 0]),
    }


def layers(count, n, side, first, gap, mass):
    """`count` square n x n cloths of `side` m and `mass` kg, each turned 15 degrees further
    about the vertical than the one below, stacked `gap` m apart from `first` m up."""
    colours = [[0.75, 0.18, 0.12], [0.2, 0.45, 0.75], [0.85, 0.65, 0.2], [0.3, 0.6, 0.3],
               [0.55, 0.3, 0.65], [0.8, 0.8, 0.78]]
    cloths = []
    for k in range(count):
        a = math.radians(15.0 * k)
        u = [math.cos(a), 0.0, math.sin(a)]
        v = [-math.sin(a), 0.0, math.cos(a)]
        y = first + gap * k
        origin = [-side / 2 * (u[i] + v[i]) for i in range(3)]
        origin[1] = y
        cloths.append({
            "name": f"cloth{k}", "grid": [n, n], "size": [side, side],
            "origin": [round(c, 7) for c in origin], "u_axis": [round(c, 7) for c in u],
            "v_axis": [round(c, 7) for c in v], "mass": mass, "stiffness": STIFF,
            "color": colours[k % len(colours)],
        })
    return cloths


def pile(count=6, n=20, side=0.7, first=0.75, gap=0.06):
    """`count` cloths (layers) over a box on the ground."""
    cloths = layers(count, n, side, first, gap, 0.049)
    return {
        "name": "contact-pile", "dt": 0.00208333333, "substeps": 8, "frames": 180,
        "damping": 0.002, "solver": {**SOLVER, "strain_limit": 0.05}, "collision": CONTACT,
        "cloths": cloths,
        "colliders": [GROUND, {"type": "box", "name": "box", "center": [0, 0.2, 0],
                               "half_extents": [0.22, 0.2, 0.22], "color": [0.5, 0.52, 0.58]}],
        "render": render([2.0, 1.5, 2.2], [0, 0.35, 0]),
    }


def write(name, scene):
    path = os.path.join("assets", "scenes", name)
    with open(path, "w", encoding="utf-8") as f:
        json.dump(scene, f, indent=2)
        f.write("\n")
    print(f"make_contact_scenes: wrote {path}")


def pile_large(count=25, n=100, side=1.0, first=0.5, gap=0.015):
    """The issue's GPU pile (OGC's 50 layers dropped on a cylinder, halved): `count` layers of
    n x n over a horizontal cylinder (a capsule longer than the cloths are wide) on the
    ground. The layers start `gap` apart, past the contact radius (1.3 half-spacings), so the
    start is clean."""
    cloths = layers(count, n, side, first, gap, 0.1)
    return {
        "name": "contact-pile-large", "dt": 0.00208333333, "substeps": 8, "frames": 120,
        "damping": 0.002, "solver": {**SOLVER, "strain_limit": 0.05}, "collision": CONTACT,
        "cloths": cloths,
        "colliders": [GROUND, {"type": "capsule", "name": "cylinder", "a": [-0.7, 0.25, 0],
                               "b": [0.7, 0.25, 0], "radius": 0.15,
                               "color": [0.5, 0.52, 0.58]}],
        "render": render([2.4, 1.6, 2.6], [0, 0.3, 0]),
    }


if __name__ == "__main__":
    write("contact-twist.json", twist())
    write("contact-pile.json", pile())
    write("contact-pile-large.json", pile_large())
