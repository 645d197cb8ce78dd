#!/usr/bin/env python3
"""The embedding example (examples/embed.c) runs with the validation layer on its own instance,
exits 0, and writes a PNG that shows something: a cloth over the background, not one colour."""
import os
import struct
import subprocess
import sys
import tempfile
import zlib

EXAMPLE = os.path.abspath(sys.argv[1])
env = dict(os.environ, CLOTHVK_VALIDATION="1")
with tempfile.TemporaryDirectory(prefix="clothvk-embed-") as workdir:
    out = os.path.join(workdir, "embed.png")
    p = subprocess.run([EXAMPLE, out, "20"], env=env, capture_output=True, text=True, timeout=240)
    if p.returncode != 0 or p.stderr:
        print(f"FAILED: the example exited {p.returncode}:\n{p.stderr}")
        sys.exit(1)
    with open(out, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        print("FAILED: the example's output is not a PNG")
        sys.exit(1)
    at, idat, width, height, colour = 8, b"", 0, 0, 0
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            width, height, _, colour = struct.unpack(">IIBB", body[:10])
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    channels = {2: 3, 6: 4}[colour]
    raw = zlib.decompress(idat)
    stride = 1 + width * channels
    # Row filters aside, an image with a cloth on a plain background has many distinct rows.
    rows = {raw[y * stride + 1:(y + 1) * stride] for y in range(height)}
    if (width, height) != (640, 480) or len(rows) < 20:
        print(f"FAILED: {width}x{height} image with {len(rows)} distinct rows")
        sys.exit(1)
    print(p.stdout.strip())
    print(f"embed example: {width}x{height} PNG, {len(rows)} distinct rows, no validation message")
