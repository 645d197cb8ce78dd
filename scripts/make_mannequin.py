#!/usr/bin/env python3
"""Writes assets/meshes/mannequin.obj: a dress form (a torso with neck and head, no arms) for a
mesh collider, such as the one poncho.json's poncho falls on.

The surface is lofted through horizontal rings: each ring a superellipse |x/a|^p + |z/b|^p = 1
(p = 2.5: rounder than a box, squarer than an ellipse) at height y, 48 points around, joined
ring to ring by quads split into two triangles, and closed by one vertex under the lowest ring
and one over the highest. The profile below is refined into three rings per step by a
Catmull-Rom spline through its rings, and the head ends in a dome, so the outline stays round
and the shading smooth when the form fills a picture. So it is closed and watertight by construction (every edge in exactly two triangles,
checked below), genus 0, triangles counter-clockwise seen from outside. Resting height: the
hips' bottom at y = 0.78 m, the shoulders at about 1.2 m, the top of the head at 1.6 m; centred
on the y axis, front +z. Deterministic, the Python standard library only.

    python3 scripts/make_mannequin.py [OUT.obj]     (default: assets/meshes/mannequin.obj)
"""
import math
import os
import sys

SEGMENTS = 48
# Rings of the loft per step of the profile (RINGS).
REFINE = 3
POWER = 2.5
# (y, half width along x, half depth along z), bottom to top, m.
RINGS = [
    (0.79, 0.13, 0.09),   # under the hips
    (0.82, 0.16, 0.105),  # hips
    (0.92, 0.145, 0.095),
    (0.98, 0.13, 0.09),   # waist
    (1.06, 0.15, 0.10),
    (1.12, 0.165, 0.105), # chest
    (1.17, 0.19, 0.10),   # shoulders
    (1.21, 0.185, 0.095),
    (1.24, 0.16, 0.085),
    (1.26, 0.11, 0.07),
    (1.275, 0.065, 0.055), # base of the neck
    (1.29, 0.052, 0.05),
    (1.35, 0.05, 0.05),   # neck
    (1.39, 0.065, 0.07),  # jaw
    (1.44, 0.085, 0.095),
    (1.50, 0.09, 0.10),   # head
    (1.55, 0.075, 0.085),
    (1.575, 0.056, 0.064), # the dome of the head
    (1.59, 0.036, 0.041),
    (1.597, 0.018, 0.020),
]
BOTTOM, TOP = 0.78, 1.60


def ring(y, a, b):
    pts = []
    for k in range(SEGMENTS):
        t = 2.0 * math.pi * k / SEGMENTS
        c, s = math.cos(t), math.sin(t)
        x = a * math.copysign(abs(c) ** (2.0 / POWER), c)
        z = b * math.copysign(abs(s) ** (2.0 / POWER), s)
        pts.append((x, y, z))
    return pts


def refined():
    """RINGS with REFINE - 1 more between each two, on a uniform Catmull-Rom spline through them
    (the ends repeated)."""
    out = []
    for i in range(len(RINGS) - 1):
        p0, p1, p2, p3 = (RINGS[max(i - 1, 0)], RINGS[i], RINGS[i + 1], RINGS[min(i + 2, len(RINGS) - 1)])
        for j in range(REFINE):
            t = j / REFINE
            out.append(tuple(0.5 * (2.0 * b + (c - a) * t + (2.0 * a - 5.0 * b + 4.0 * c - d) * t * t +
                                    (3.0 * b - a - 3.0 * c + d) * t * t * t)
                             for a, b, c, d in zip(p0, p1, p2, p3)))
    out.append(RINGS[-1])
    return out


def build():
    rings = refined()
    verts = [(0.0, BOTTOM, 0.0)]
    for y, a, b in rings:
        verts += ring(y, a, b)
    verts.append((0.0, TOP, 0.0))
    top = len(verts) - 1
    n = SEGMENTS

    def at(r, k):
        return 1 + r * n + k % n

    tris = []
    # Angle t runs from +x towards +z: seen from outside (from -y below) the bottom fan
    # (0, k, k+1) winds counter-clockwise, the sides (lower k, upper k+1, upper k) too.
    for k in range(n):
        tris.append((0, at(0, k), at(0, k + 1)))
    for r in range(len(rings) - 1):
        for k in range(n):
            a, b = at(r, k), at(r, k + 1)
            c, d = at(r + 1, k + 1), at(r + 1, k)
            tris.append((a, c, b))
            tris.append((a, d, c))
    last = len(rings) - 1
    for k in range(n):
        tris.append((top, at(last, k + 1), at(last, k)))
    return verts, tris


def check(verts, tris):
    """Every edge in exactly two triangles, once each way; the volume positive (outward)."""
    directed = {}
    for t in tris:
        for i in range(3):
            e = (t[i], t[(i + 1) % 3])
            directed[e] = directed.get(e, 0) + 1
    for (u, v), count in directed.items():
        if count != 1 or directed.get((v, u)) != 1:
            raise SystemExit(f"edge {u}-{v} is not shared by exactly two triangles")
    volume = 0.0
    for i, j, k in tris:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = verts[i], verts[j], verts[k]
        volume += (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0
    if volume <= 0.0:
        raise SystemExit(f"volume {volume:.6f} m^3: the triangles face inwards")
    return len(directed) // 2, volume


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join("assets", "meshes", "mannequin.obj")
    verts, tris = build()
    edges, volume = check(verts, tris)
    with open(path, "w", encoding="ascii") as f:
        f.write("# mannequin: a dress form, torso, neck and head, 0.37 m across the shoulders, "
                f"from y = {BOTTOM} to {TOP}, front +z\n")
        f.write("# written by scripts/make_mannequin.py; lofted superellipse rings, closed; y up\n")
        f.write(f"# vertices {len(verts)}, edges {edges}, triangles {len(tris)}, "
                f"volume {volume:.5f} m^3\n")
        f.write("o mannequin\n")
        for x, y, z in verts:
            f.write(f"v {x:.6f} {y:.6f} {z:.6f}\n")
        for t in tris:
            f.write("f %d %d %d\n" % tuple(k + 1 for k in t))
    print(f"{path}: {len(verts)} vertices, {edges} edges, {len(tris)} triangles, volume {volume:.5f} m^3")


if __name__ == "__main__":
    main()
