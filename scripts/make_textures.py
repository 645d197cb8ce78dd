#!/usr/bin/env python3
"""Writes the example textures, 8-bit sRGB, made with the Python standard library only:
assets/textures/plaid.png, a 256 x 256 cloth tartan that tiles (its stripes repeat with the
image), and for colliders assets/textures/wood.png, a 256 x 256 wood grain, and
assets/textures/tiles.png, 2 x 2 stone floor tiles, both tiling.

The sett (the stripe pattern, the same across the warp and the weft) is a list of
(colour, width in texels) summing to 256; where a warp and a weft stripe cross, the weave
shows one or the other in a 2/2 twill: texel (x, y) takes the warp's colour when
(x + y) // 2 is even, the weft's otherwise, which gives tartan its fine diagonal.

    python3 scripts/make_textures.py [OUTDIR]     (default: assets/textures)
"""
import os
import struct
import sys
import zlib

SIZE = 256
SETT = [
    ((28, 48, 92), 48),     # navy
    ((24, 82, 52), 40),     # green
    ((28, 48, 92), 16),
    ((168, 32, 36), 8),     # red
    ((28, 48, 92), 16),
    ((24, 82, 52), 40),
    ((28, 48, 92), 48),
    ((214, 190, 96), 4),    # yellow
    ((24, 82, 52), 28),
    ((214, 190, 96), 4),
    ((28, 48, 92), 4),
]


def stripes():
    colours = []
    for colour, width in SETT:
        colours += [colour] * width
    assert len(colours) == SIZE, len(colours)
    return colours


def png(width, height, rows):
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    raw = b"".join(b"\0" + bytes(row) for row in rows)
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9))
            + chunk(b"IEND", b""))


def plaid():
    s = stripes()
    rows = []
    for y in range(SIZE):
        row = []
        for x in range(SIZE):
            row += s[x] if ((x + y) // 2) % 2 == 0 else s[y]
        rows.append(row)
    return rows


# Wood: four planks across v (64 texels, 0.25 of a repeat, each) with the grain along u. Each
# plank has its own tone, growth-ring spacing and phase; the rings wander gently with sines
# whose periods divide the image (so the texture tiles), and fine streaks along u come from a
# fixed pseudo-random shade per row. Colours are sRGB.
WOOD_DARK = (96, 58, 30)
WOOD_LIGHT = (172, 118, 66)
PLANKS = [(1.00, 3.0, 0.3), (0.88, 4.0, 1.7), (1.05, 2.5, 4.1), (0.94, 3.5, 2.6)]  # tone, rings, phase


def wood():
    import math
    import random
    rng = random.Random(7)
    streak = [rng.random() for _ in range(SIZE)]
    streak = [(streak[y - 1] + 2 * streak[y] + streak[(y + 1) % SIZE]) / 4 for y in range(SIZE)]
    rows = []
    tau = 2.0 * math.pi
    width = SIZE // len(PLANKS)
    for y in range(SIZE):
        tone, rings, phase = PLANKS[y // width]
        across = (y % width + 0.5) / width
        row = []
        for x in range(SIZE):
            u = x / SIZE
            wander = 0.06 * math.sin(tau * u + phase) + 0.025 * math.sin(tau * 3 * u + 2 * phase)
            ring = (0.5 + 0.5 * math.sin(tau * rings * (across + wander) + phase)) ** 4
            t = 0.8 - 0.45 * ring - 0.3 * (streak[y] - 0.5)
            if y % width in (0, width - 1):  # the seam between planks
                t *= 0.4
            t = min(1.0, max(0.0, t))
            row += [min(255, round(tone * (d + t * (l - d)))) for d, l in zip(WOOD_DARK, WOOD_LIGHT)]
        rows.append(row)
    return rows


# Floor tiles: 2 x 2 square stone tiles per repeat, each its own shade of a warm grey with a
# soft mottle (bilinear value noise on an 8 x 8 lattice that wraps, so the texture tiles), and
# a darker grout line 4 texels wide between them. Colours are sRGB.
TILE_COLOR = (196, 188, 172)
GROUT_COLOR = (120, 114, 104)


def tiles():
    import random
    rng = random.Random(11)
    lattice = [[rng.random() for _ in range(8)] for _ in range(8)]
    shade = [[0.92 + 0.16 * rng.random() for _ in range(2)] for _ in range(2)]

    def noise(x, y):
        fx, fy = x * 8 / SIZE, y * 8 / SIZE
        i, j = int(fx), int(fy)
        tx, ty = fx - i, fy - j
        a, b = lattice[j % 8][i % 8], lattice[j % 8][(i + 1) % 8]
        c, d = lattice[(j + 1) % 8][i % 8], lattice[(j + 1) % 8][(i + 1) % 8]
        return (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty

    half = SIZE // 2
    rows = []
    for y in range(SIZE):
        row = []
        for x in range(SIZE):
            grout = min(x % half, half - 1 - x % half) < 2 or min(y % half, half - 1 - y % half) < 2
            if grout:
                row += list(GROUT_COLOR)
                continue
            k = shade[y // half][x // half] * (0.94 + 0.12 * noise(x, y))
            row += [min(255, round(k * v)) for v in TILE_COLOR]
        rows.append(row)
    return rows


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "assets", "textures")
    os.makedirs(out, exist_ok=True)
    for name, rows in (("plaid.png", plaid), ("wood.png", wood), ("tiles.png", tiles)):
        path = os.path.join(out, name)
        with open(path, "wb") as f:
            f.write(png(SIZE, SIZE, rows()))
        print(path)


if __name__ == "__main__":
    main()
