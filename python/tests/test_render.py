"""The renderer's image as a numpy array and as a PNG file, whose decoded pixels are the
array's."""

import struct
import zlib

import numpy as np

import clothvk
from conftest import SCENES, SMALL


def png_pixels(data):
    """An 8-bit, non-interlaced RGB or RGBA PNG's pixels (rows, columns, channels), decoded
    here: the IDAT chunks inflated, each row's filter (PNG spec 9.2) undone."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    at, idat, header = 8, b"", None
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        header = body if kind == b"IHDR" else header
        idat += body if kind == b"IDAT" else b""
        at += 12 + length
    width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", header)
    assert depth == 8 and colour in (2, 6) and interlace == 0, header
    channels = 3 if colour == 2 else 4
    raw, stride = zlib.decompress(idat), width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up, up_left = prev[i], prev[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 255
            elif kind == 2:
                line[i] = (line[i] + up) & 255
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - up_left
                near = min((abs(p - left), 0, left), (abs(p - up), 1, up),
                           (abs(p - up_left), 2, up_left))  # Paeth: ties to left, then up
                line[i] = (line[i] + near[2]) & 255
        rows.append(bytes(line))
        prev = line
    return np.frombuffer(b"".join(rows), dtype=np.uint8).reshape(height, width, channels)


def test_render_small_image(ctx, tmp_path):
    overrides = {**SMALL, "render.size": [64, 48], "render.shadow_map_size": 256}
    with clothvk.Scene.load(SCENES / "hanging.json", overrides=overrides) as scene, \
            clothvk.Simulation(ctx, scene) as sim, clothvk.Renderer(sim, scene) as renderer:
        first = renderer.image()
        sim.step(10)
        image = renderer.draw()
        assert image.shape == (48, 64, 4) and image.dtype == np.uint8, image.shape
        assert (image[..., 3] == 255).all(), "alpha is not 255 everywhere"
        colours = np.unique(image.reshape(-1, 4), axis=0)
        assert len(colours) > 10, f"only {len(colours)} colours: the image is (nearly) uniform"
        assert not np.array_equal(first, image), "the image did not change after 10 frames"
        png = tmp_path / "frame.png"
        renderer.write_png(png)
        data = png.read_bytes()
        assert struct.unpack(">II", data[16:24]) == (64, 48)
        pixels = png_pixels(data)
        assert np.array_equal(pixels, image[..., :pixels.shape[2]]), \
            "the PNG's pixels are not the image's"
