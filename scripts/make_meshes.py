#!/usr/bin/env python3
"""Writes the example cloth meshes assets/meshes/poncho.obj and assets/meshes/flag.obj, and the
collider mesh assets/meshes/chair.obj.

Both lie in the x-y plane (z = 0), y up, facing +z (triangles counter-clockwise seen from +z),
so a scene hangs them by pinning their top edge (y = 1) with a pin_box. They are irregularly
triangulated: Poisson-disk points (Bridson's method, minimum distance h) with the boundary
sampled at spacing h, joined by a Delaunay triangulation (Bowyer-Watson). Such a triangulation
has edges between h and about 2h, so springs of similar length everywhere.

- poncho.obj: a 1 m x 1 m square, x in [-0.5, 0.5], y in [0, 1], with a round head opening
  of radius 0.13 m at its centre (seed 002, fig. 6.19).
- flag.obj: a 1.5 m x 1 m rectangle, x in [-0.75, 0.75], y in [0, 1].

- chair.obj: a closed chair for mesh colliders (see chair() below).

Vertices are written in the order the faces first use them and faces sorted top row first, so
particle i of the cloth is the file's vertex i + 1 (OBJ counts from 1) and low indices lie along
the top edge. The header comment gives the vertex, edge and triangle counts, which the tests
hold the reader to. Deterministic: a fixed seed, the Python standard library only.

    python3 scripts/make_meshes.py [OUTDIR]     (default: assets/meshes)
"""
import math
import os
import random
import sys


def boundary_square(x0, y0, x1, y1, h):
    """Points along the rectangle's border, spacing about h, corners included."""
    pts = []
    nx = max(1, round((x1 - x0) / h))
    ny = max(1, round((y1 - y0) / h))
    for i in range(nx):
        pts.append((x0 + (x1 - x0) * i / nx, y0))
    for j in range(ny):
        pts.append((x1, y0 + (y1 - y0) * j / ny))
    for i in range(nx):
        pts.append((x1 - (x1 - x0) * i / nx, y1))
    for j in range(ny):
        pts.append((x0, y1 - (y1 - y0) * j / ny))
    return pts


def boundary_circle(cx, cy, r, h):
    n = max(6, round(2 * math.pi * r / h))
    return [(cx + r * math.cos(2 * math.pi * k / n), cy + r * math.sin(2 * math.pi * k / n))
            for k in range(n)]


def poisson_fill(fixed, inside, x0, y0, x1, y1, h, rng):
    """Bridson's Poisson-disk sampling of the region `inside`, no point closer than h to
    another or to the fixed boundary points."""
    cell = h / math.sqrt(2)
    grid = {}

    def key(p):
        return (int((p[0] - x0) // cell), int((p[1] - y0) // cell))

    def far_enough(p):
        gx, gy = key(p)
        for dx in range(-2, 3):
            for dy in range(-2, 3):
                for q in grid.get((gx + dx, gy + dy), ()):
                    if (p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 < h * h:
                        return False
        return True

    for p in fixed:
        grid.setdefault(key(p), []).append(p)
    samples = []
    start = ((x0 + x1) / 2 + 0.3 * h, y0 + 0.25 * (y1 - y0))
    active = [start] if inside(start) and far_enough(start) else []
    for p in active:
        grid.setdefault(key(p), []).append(p)
        samples.append(p)
    while active:
        i = rng.randrange(len(active))
        base = active[i]
        for _ in range(30):
            a = rng.uniform(0, 2 * math.pi)
            d = rng.uniform(h, 2 * h)
            p = (base[0] + d * math.cos(a), base[1] + d * math.sin(a))
            if inside(p) and far_enough(p):
                grid.setdefault(key(p), []).append(p)
                samples.append(p)
                active.append(p)
                break
        else:
            active.pop(i)
    return samples


def circumcircle(a, b, c):
    d = 2 * (a[0] * (b[1] - c[1]) + b[0] * (c[1] - a[1]) + c[0] * (a[1] - b[1]))
    ux = ((a[0] ** 2 + a[1] ** 2) * (b[1] - c[1]) + (b[0] ** 2 + b[1] ** 2) * (c[1] - a[1])
          + (c[0] ** 2 + c[1] ** 2) * (a[1] - b[1])) / d
    uy = ((a[0] ** 2 + a[1] ** 2) * (c[0] - b[0]) + (b[0] ** 2 + b[1] ** 2) * (a[0] - c[0])
          + (c[0] ** 2 + c[1] ** 2) * (b[0] - a[0])) / d
    return ux, uy, (a[0] - ux) ** 2 + (a[1] - uy) ** 2


def delaunay(points):
    """Bowyer-Watson: triangles as index triples into points, counter-clockwise."""
    pts = list(points)
    n = len(pts)
    pts += [(-1e3, -1e3), (1e3, -1e3), (0.0, 1e3)]
    tris = {(n, n + 1, n + 2): circumcircle(*pts[n:n + 3])}
    for i in range(n):
        p = pts[i]
        bad = [t for t, (ux, uy, r2) in tris.items() if (p[0] - ux) ** 2 + (p[1] - uy) ** 2 < r2]
        edges = {}
        for t in bad:
            for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                k = (min(e), max(e))
                edges[k] = None if k in edges else e
            del tris[t]
        for e in edges.values():
            if e is not None:
                t = (e[0], e[1], i)
                tris[t] = circumcircle(pts[t[0]], pts[t[1]], pts[t[2]])
    out = []
    for t in tris:
        if max(t) >= n:
            continue
        a, b, c = (pts[k] for k in t)
        if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0:
            t = (t[0], t[2], t[1])
        out.append(t)
    return out


def edges_of(tris):
    count = {}
    for t in tris:
        for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            k = (min(e), max(e))
            count[k] = count.get(k, 0) + 1
    return count


def boundary_loops(count):
    """Number of closed loops the boundary edges (those of one triangle) form."""
    nbr = {}
    for (a, b), c in count.items():
        if c == 1:
            nbr.setdefault(a, []).append(b)
            nbr.setdefault(b, []).append(a)
    assert all(len(v) == 2 for v in nbr.values()), "a boundary vertex is not on one loop"
    seen, loops = set(), 0
    for v in nbr:
        if v in seen:
            continue
        loops += 1
        stack = [v]
        while stack:
            u = stack.pop()
            if u not in seen:
                seen.add(u)
                stack.extend(nbr[u])
    return loops


def check(pts, tris, holes, h):
    count = edges_of(tris)
    assert max(count.values()) <= 2, "non-manifold edge"
    used = {v for t in tris for v in t}
    assert len(used) == len(pts), "unused vertex"
    assert boundary_loops(count) == 1 + holes
    assert len(pts) - len(count) + len(tris) == 1 - holes, "Euler characteristic"
    lengths = [math.dist(pts[a], pts[b]) for a, b in count]
    for t in tris:
        a, b, c = (pts[k] for k in t)
        area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        assert area > 0.1 * h * h, "sliver triangle"
    return len(count), min(lengths), max(lengths)


def write_obj(path, title, pts, tris, holes, h):
    # Faces top row first, left to right; vertices renumbered in order of first use.
    def order(t):
        cx = sum(pts[k][0] for k in t) / 3
        cy = sum(pts[k][1] for k in t) / 3
        return (-math.floor(cy / h), cx)
    tris = sorted(tris, key=order)
    new = {}
    for t in tris:
        for k in t:
            new.setdefault(k, len(new))
    pts = [p for _, p in sorted((i, pts[k]) for k, i in new.items())]
    tris = [tuple(new[k] for k in t) for t in tris]
    edges, shortest, longest = check(pts, tris, holes, h)
    with open(path, "w", encoding="ascii") as f:
        f.write(f"# {title}\n# written by scripts/make_meshes.py; x-y plane, y up, front +z\n")
        f.write(f"# vertices {len(pts)}, edges {edges}, triangles {len(tris)}, holes {holes}; "
                f"edges {shortest:.4f} to {longest:.4f} m\n")
        f.write(f"o {os.path.splitext(os.path.basename(path))[0]}\n")
        for x, y in pts:
            f.write(f"v {x:.6f} {y:.6f} 0\n")
        for t in tris:
            f.write("f %d %d %d\n" % tuple(k + 1 for k in t))
    print(f"{path}: {len(pts)} vertices, {edges} edges, {len(tris)} triangles, "
          f"edges {shortest:.4f} to {longest:.4f} m")


def poncho(path):
    h, r = 0.03, 0.13
    rng = random.Random(2)
    fixed = boundary_square(-0.5, 0.0, 0.5, 1.0, h) + boundary_circle(0.0, 0.5, r, h)
    margin = 0.5 * h

    def inside(p):
        return (-0.5 + margin < p[0] < 0.5 - margin and margin < p[1] < 1.0 - margin
                and math.dist(p, (0.0, 0.5)) > r + margin)
    pts = fixed + poisson_fill(fixed, inside, -0.5, 0.0, 0.5, 1.0, h, rng)
    tris = [t for t in delaunay(pts)
            if math.dist((sum(pts[k][0] for k in t) / 3, sum(pts[k][1] for k in t) / 3),
                         (0.0, 0.5)) > r]
    write_obj(path, "poncho: 1 m x 1 m with a round head opening of radius 0.13 m",
              pts, tris, 1, h)


def flag(path):
    h = 0.04
    rng = random.Random(3)
    fixed = boundary_square(-0.75, 0.0, 0.75, 1.0, h)
    margin = 0.5 * h

    def inside(p):
        return -0.75 + margin < p[0] < 0.75 - margin and margin < p[1] < 1.0 - margin
    pts = fixed + poisson_fill(fixed, inside, -0.75, 0.0, 0.75, 1.0, h, rng)
    write_obj(path, "flag: 1.5 m x 1 m", pts, delaunay(pts), 0, h)


# The chair as the union of boxes (x0, y0, z0, x1, y1, z1), m: seat 0.45 m x 0.45 m, top at
# y = 0.45; four legs of 0.04 m x 0.04 m from the floor (y = 0) up into the seat; at the back
# (-z) two posts and a panel between them up to y = 0.9. Centred on x = z = 0, the front faces
# +z. The file holds the union's surface only, one closed manifold with no faces inside the
# solid: overlapping closed boxes would leave faces inside, which no signed distance can tell
# from the real surface by distance alone.
CHAIR_BOXES = [
    (-0.225, 0.40, -0.225, 0.225, 0.45, 0.225),      # seat
    (-0.21, 0.0, 0.165, -0.17, 0.42, 0.205),         # front left leg
    (0.17, 0.0, 0.165, 0.21, 0.42, 0.205),           # front right leg
    (-0.21, 0.0, -0.205, -0.17, 0.42, -0.165),       # back left leg
    (0.17, 0.0, -0.205, 0.21, 0.42, -0.165),         # back right leg
    (-0.21, 0.43, -0.215, -0.17, 0.9, -0.175),       # back post, left
    (0.17, 0.43, -0.215, 0.21, 0.9, -0.175),         # back post, right
    (-0.185, 0.6, -0.21, 0.185, 0.88, -0.185),       # back panel between the posts
]


def box_union_surface(boxes):
    """The boundary of a union of axis-aligned boxes as quads on the grid of every box's
    coordinates: a cell of that grid is solid when a box covers it, and each face between a
    solid and an empty cell is a quad, counter-clockwise seen from the empty side. Faces meet
    whole edge to whole edge (no T-junctions), so the surface is closed."""
    axes = [sorted({b[k] for b in boxes} | {b[k + 3] for b in boxes}) for k in range(3)]
    size = [len(a) - 1 for a in axes]

    def solid(c):
        if any(c[k] < 0 or c[k] >= size[k] for k in range(3)):
            return False
        mid = [(axes[k][c[k]] + axes[k][c[k] + 1]) / 2 for k in range(3)]
        return any(all(b[k] < mid[k] < b[k + 3] for k in range(3)) for b in boxes)

    index = {}
    xyz = []
    quads = []

    def vertex(g):
        if g not in index:
            index[g] = len(xyz)
            xyz.append(tuple(axes[k][g[k]] for k in range(3)))
        return index[g]

    for i in range(size[0]):
        for j in range(size[1]):
            for k in range(size[2]):
                c = (i, j, k)
                if not solid(c):
                    continue
                for axis in range(3):
                    for side in (0, 1):
                        n = list(c)
                        n[axis] += 1 if side else -1
                        if solid(tuple(n)):
                            continue
                        u, v = (axis + 1) % 3, (axis + 2) % 3
                        base = list(c)
                        base[axis] += side
                        corners = []
                        for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                            g = list(base)
                            g[u] += du
                            g[v] += dv
                            corners.append(vertex(tuple(g)))
                        # (u, v, axis) is right-handed: u then v turns counter-clockwise seen
                        # from +axis.
                        quads.append(corners if side else corners[::-1])
    return xyz, quads


def chair(path):
    xyz, quads = box_union_surface(CHAIR_BOXES)
    edges = {}
    for q in quads:
        for a, b in zip(q, q[1:] + q[:1]):
            edges[(min(a, b), max(a, b))] = edges.get((min(a, b), max(a, b)), 0) + 1
    assert all(n == 2 for n in edges.values()), "the chair's surface is not a closed manifold"
    with open(path, "w", encoding="ascii") as f:
        f.write("# chair: seat 0.45 m x 0.45 m at y = 0.45, back to y = 0.9, front +z\n")
        f.write("# written by scripts/make_meshes.py; the surface of %d boxes' union, closed; "
                "y up, resting on y = 0\n" % len(CHAIR_BOXES))
        f.write("# vertices %d, quads %d\n" % (len(xyz), len(quads)))
        f.write("o chair\n")
        for p in xyz:
            f.write("v %g %g %g\n" % p)
        for q in quads:
            f.write("f %s\n" % " ".join(str(k + 1) for k in q))
    print("%s: %d vertices, %d quads" % (path, len(xyz), len(quads)))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.normpath(os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "assets", "meshes"))
    os.makedirs(out, exist_ok=True)
    poncho(os.path.join(out, "poncho.obj"))
    flag(os.path.join(out, "flag.obj"))
    chair(os.path.join(out, "chair.obj"))


if __name__ == "__main__":
    main()
