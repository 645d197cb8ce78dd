"""The renderer's image as a numpy array and as a PNG file, whose decoded pixels are the
array's."""

import struct
import sys

import numpy as np

import clothvk
from conftest import ROOT, SCENES, SMALL

sys.path.insert(0, str(ROOT / "tests" / "tools"))
import tooltest  # noqa: E402  (its PNG decoder: zlib and the row filters, PNG spec 9.2)


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
        width, channels, samples = tooltest.png_pixels(png)
        pixels = np.frombuffer(samples, dtype=np.uint8).reshape(48, width, channels)
        assert np.array_equal(pixels, image[..., :channels]), "the PNG's pixels are not the image's"
