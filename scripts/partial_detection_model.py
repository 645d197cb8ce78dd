"""A model of detecting only near the particles that ask (docs/limits.md, Collisions).

Replays a run substep by substep from its PC2 point cache (clothvk-sim --set substeps=1 with
the scene's substep as dt, --pc2) and counts the detections and the particles each one measures
under two schemes, on the same trajectory:

- whole: as the engine does, every particle measured at each detection;
- region: only the particles of a region around those that ask are measured; every other
  particle keeps its ball. A measured particle's bound is 0.45 (D - U - floor) over every pair
  of features it is a corner of, D the pair's distance now and U the farthest the pair's
  untouched corners may still move (a corner's offset from its ball's centre plus its bound,
  the larger of each side's corners, the two sides summed), capped at 0.45 of the contact
  radius; such a bound keeps every pair apart (limits.md).

A particle asks when its move since its ball was made plus its last substep's move, less the
shift common to all, passes 0.9 of its bound (contact_check.comp's extrapolation and
contact_decide.comp's shift, without its rule of no shift near a collider; the floor is 0.001
thicknesses, without its part relative to the coordinates). The model does
not feed the bounds back into the motion: the trajectory is the engine's, made with whole
detections. It counts work, not cost: the measured particles stand for the walks of detection.

    python3 scripts/partial_detection_model.py RUN.pc2 --thickness T [--region rings:2 ...]
"""
import argparse
import csv
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pc2  # noqa: E402

GAMMA = 0.45
REDETECT = 0.9


def read_run(path):
    header, samples = pc2.read(path)
    points = header[2]
    frames = np.array([np.frombuffer(s, dtype=np.float32).reshape(points, 3) for s in samples],
                      dtype=np.float64)
    tris = []
    with open(os.path.splitext(path)[0] + ".obj") as f:
        for line in f:
            if line.startswith("f "):
                tris.append([int(w.split("/")[0]) - 1 for w in line.split()[1:4]])
    tris = np.array(tris, dtype=np.int64)
    e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    edges = np.unique(e, axis=0)
    return frames, tris, edges


def seg_point(p, a, b):
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


def point_triangle(p, a, b, c):
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1)[:, None]
    h = np.einsum("ij,ij->i", p - a, n)
    q = p - h[:, None] * n
    inside = np.ones(len(p), dtype=bool)
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= np.einsum("ij,ij->i", np.cross(v - u, q - u), n) >= 0.0
    edge = np.minimum(np.minimum(seg_point(p, a, b), seg_point(p, b, c)), seg_point(p, c, a))
    return np.where(inside, np.abs(h), edge)


def seg_seg(p1, q1, p2, q2):
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    f = np.einsum("ij,ij->i", d2, r)
    c = np.einsum("ij,ij->i", d1, r)
    b = np.einsum("ij,ij->i", d1, d2)
    denom = a * e - b * b
    s = np.where(denom > 1e-12 * a * e, np.clip((b * f - c * e) / np.maximum(denom, 1e-300), 0, 1), 0.0)
    t = (b * s + f) / e
    low, high = t < 0.0, t > 1.0
    s = np.where(low, np.clip(-c / a, 0, 1), np.where(high, np.clip((b - c) / a, 0, 1), s))
    t = np.clip(t, 0.0, 1.0)
    return np.linalg.norm((p1 + s[:, None] * d1) - (p2 + t[:, None] * d2), axis=1)


def close_pairs(pa, pb, reach):
    """Index pairs (i, j) with |pa_i - pb_j| < reach, in row blocks."""
    out_i, out_j = [np.zeros(0, dtype=np.int64)], [np.zeros(0, dtype=np.int64)]
    nb = np.einsum("ij,ij->j", pb.T, pb.T)
    for lo in range(0, len(pa), 1024):
        a = pa[lo:lo + 1024]
        d2 = np.einsum("ij,ij->i", a, a)[:, None] + nb[None, :] - 2.0 * (a @ pb.T)
        i, j = np.nonzero(d2 < reach * reach)
        out_i.append(i + lo)
        out_j.append(j)
    return np.concatenate(out_i), np.concatenate(out_j)


def touching(rows, cols, rows_in, cols_in, reach):
    """The pairs of close_pairs(rows, cols) with a row or a column in the region, each once."""
    if rows_in.all():
        return close_pairs(rows, cols, reach)
    ri = np.nonzero(rows_in)[0]
    ci = np.nonzero(cols_in)[0]
    i1, j1 = close_pairs(rows[ri], cols, reach)
    i2, j2 = close_pairs(rows, cols[ci], reach)
    i = np.concatenate([ri[i1], i2])
    j = np.concatenate([j1, ci[j2]])
    key = np.unique(i * len(cols) + j)
    return key // len(cols), key % len(cols)


def touching_same(points, inside, reach):
    """The pairs (i < j) of points within reach of each other with i or j in the region."""
    ri = np.nonzero(inside)[0]
    i, j = close_pairs(points[ri], points, reach)
    i = ri[i]
    low, high = np.minimum(i, j), np.maximum(i, j)
    key = np.unique(low[low < high] * len(points) + high[low < high])
    return key // len(points), key % len(points)


class Model:
    def __init__(self, tris, edges, radius, thickness, n):
        self.tris, self.edges, self.radius = tris, edges, radius
        self.floor = 1e-3 * thickness
        self.n = n
        self.centre = np.zeros((n, 3))
        self.bound = np.zeros(n)

    def measure(self, x, region, shift=0.0):
        """New balls for the particles in region (a boolean mask), at positions x; the others'
        balls are centred at their centres plus shift."""
        reach_left = np.where(region, 0.0,
                              np.linalg.norm(x - self.centre - shift, axis=1) + self.bound)
        slack = 2.0 * reach_left.max()
        d = np.full(self.n, self.radius)
        tris, edges = self.tris, self.edges
        # vertex against triangle: pairs with a measured particle at either side
        cen = x[tris].mean(axis=1)
        spread = np.linalg.norm(x[tris] - cen[:, None, :], axis=2).max()
        reach = self.radius + slack + spread
        tri_in = region[tris].any(axis=1)
        vi, ti = touching(x, cen, region, tri_in, reach)
        keep = (tris[ti] != vi[:, None]).all(axis=1)
        vi, ti = vi[keep], ti[keep]
        t = tris[ti]
        dist = point_triangle(x[vi], x[t[:, 0]], x[t[:, 1]], x[t[:, 2]])
        val = dist - reach_left[vi] - reach_left[t].max(axis=1)
        for m in (vi, t[:, 0], t[:, 1], t[:, 2]):
            np.minimum.at(d, m, val)
        # edge against edge, sharing no end
        mid = 0.5 * (x[edges[:, 0]] + x[edges[:, 1]])
        half = 0.5 * np.linalg.norm(x[edges[:, 0]] - x[edges[:, 1]], axis=1).max()
        edge_in = region[edges].any(axis=1)
        ei, fi = touching_same(mid, edge_in, self.radius + slack + 2.0 * half)
        a, b = edges[ei], edges[fi]
        keep = (a[:, :, None] != b[:, None, :]).all(axis=(1, 2))
        a, b = a[keep], b[keep]
        dist = seg_seg(x[a[:, 0]], x[a[:, 1]], x[b[:, 0]], x[b[:, 1]])
        val = dist - reach_left[a].max(axis=1) - reach_left[b].max(axis=1)
        for m in (a[:, 0], a[:, 1], b[:, 0], b[:, 1]):
            np.minimum.at(d, m, val)
        new = GAMMA * np.maximum(np.minimum(d, self.radius) - self.floor, 0.0)
        self.centre[region] = x[region] - shift
        self.bound[region] = new[region]


def rings(edges, region, k):
    """region and the particles within k edges of the mesh of it."""
    for _ in range(k):
        grow = region.copy()
        grow[edges[region[edges[:, 0]], 1]] = True
        grow[edges[region[edges[:, 1]], 0]] = True
        region = grow
    return region


def replay(frames, tris, edges, radius, thickness, region_rule):
    """Detections, particles measured (in whole detections) and particles asking, over the run.
    Every ball is centred at its centre plus a shift common to all (a translation keeps every
    distance): at each substep the centre of the box of the extrapolated moves, as
    contact_decide.comp takes it (its rule of no shift near a collider left out)."""
    n = frames.shape[1]
    model = Model(tris, edges, radius, thickness, n)
    model.measure(frames[0], np.ones(n, dtype=bool))
    shift = np.zeros(3)
    detections, measured, asked = 1, n, 0
    for k in range(1, len(frames) - 1):
        x = frames[k]
        ahead = x + (x - frames[k - 1]) - model.centre
        shift = 0.5 * (ahead.min(axis=0) + ahead.max(axis=0))
        move = np.linalg.norm(ahead - shift, axis=1)
        asking = move > REDETECT * model.bound
        if not asking.any():
            continue
        region = region_rule(asking, move, model.bound)
        model.measure(x, region, shift)
        detections += 1
        measured += int(region.sum())
        asked += int(asking.sum())
    return detections, measured / n, asked


def pieces(tris, n):
    """Each particle's connected piece of cloth (the triangles' components)."""
    parent = np.arange(n)

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for t in tris:
        a = root(t[0])
        for v in t[1:]:
            b = root(v)
            if a != b:
                parent[b] = a
    return np.array([root(i) for i in range(n)])


def make_rule(text, tris, edges, n):
    """The region rule named by text: a function of (asking, move, bound) giving the region."""
    kind, _, value = text.partition(":")
    try:
        if kind == "whole" and not value:
            return lambda asking, move, bound: np.ones(n, dtype=bool)
        if kind == "cloth" and not value:
            piece = pieces(tris, n)
            return lambda asking, move, bound: np.isin(piece, piece[asking])
        if kind == "rings":
            k = int(value)
            return lambda asking, move, bound: rings(edges, asking, k)
        if kind == "ahead":
            # the particles past a fraction of their bounds, and k rings around them
            frac, _, k = value.partition(",")
            frac, k = float(frac), int(k or 0)
            return lambda asking, move, bound: rings(edges, asking | (move > frac * bound), k)
    except ValueError:
        pass
    raise SystemExit(f"partial_detection_model: --region {text}: expected whole, cloth, rings:K "
                     f"or ahead:F[,K]")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("pc2")
    ap.add_argument("--thickness", type=float, required=True)
    ap.add_argument("--radius", type=float, default=0.0, help="default 1.3 thicknesses")
    ap.add_argument("--region", action="append", default=None)
    ap.add_argument("--label", default=None)
    ap.add_argument("--csv", default=None, help="append rows to this file")
    args = ap.parse_args()
    try:
        frames, tris, edges = read_run(args.pc2)
    except (OSError, ValueError, IndexError) as e:
        raise SystemExit(f"partial_detection_model: {e}")
    if len(frames) < 3 or len(tris) == 0:
        raise SystemExit(f"partial_detection_model: {args.pc2}: needs 3 samples and a mesh, "
                         f"got {len(frames)} samples and {len(tris)} triangles")
    if not args.thickness > 0.0:
        raise SystemExit(f"partial_detection_model: --thickness must be positive, got {args.thickness}")
    radius = args.radius or 1.3 * args.thickness
    texts = args.region or ["whole", "rings:1", "rings:2", "rings:4"]
    rules = [make_rule(text, tris, edges, frames.shape[1]) for text in texts]
    out = csv.writer(sys.stdout, lineterminator="\n")
    rows = []
    for text, rule in zip(texts, rules):
        det, full, asked = replay(frames, tris, edges, radius, args.thickness, rule)
        rows.append([args.label or os.path.basename(args.pc2), frames.shape[1], len(frames) - 1,
                     text, det, f"{full:.1f}", f"{asked / max(det - 1, 1):.1f}"])
        out.writerow(rows[-1])
        sys.stdout.flush()
    if args.csv:
        new = not os.path.exists(args.csv)
        with open(args.csv, "a", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            if new:
                w.writerow(["scene", "particles", "substeps", "region", "detections",
                            "particles measured (in whole detections)",
                            "particles asking per detection"])
            w.writerows(rows)

if __name__ == "__main__":
    main()
