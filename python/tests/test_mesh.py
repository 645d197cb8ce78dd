"""A mesh cloth (poncho.json: an OBJ file) through Simulation.mesh()."""

import numpy as np

import clothvk
from conftest import SCENES


def test_poncho_mesh(ctx):
    with clothvk.Scene.load(SCENES / "poncho.json") as scene, \
            clothvk.Simulation(ctx, scene) as sim:
        xyz, normals, triangles = sim.mesh()
        assert xyz.shape == (755, 3), xyz.shape
        assert normals.shape == (755, 3), normals.shape
        assert triangles.shape == (1351, 3) and triangles.dtype == np.uint32, triangles.shape
        assert triangles.max() < 755
        assert np.array_equal(xyz, sim.positions())
        lengths = np.linalg.norm(normals, axis=1)
        assert np.allclose(lengths, 1, atol=1e-5), f"normal lengths {lengths.min()}..{lengths.max()}"
        cloths = sim.cloths()
        assert len(cloths) == 1 and cloths[0]["mesh"], cloths
        assert (cloths[0]["particle_count"], cloths[0]["triangle_count"]) == (755, 1351)
