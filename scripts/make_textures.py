#!/usr/bin/env python3
"""Writes the example cloth texture assets/textures/plaid.png: a 256 x 256 tartan that tiles
(its stripes repeat with the image), 8-bit sRGB, made with the Python standard library only.

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


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "assets", "textures")
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "plaid.png")
    with open(path, "wb") as f:
        f.write(png(SIZE, SIZE, plaid()))
    print(path)


if __name__ == "__main__":
    main()
