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
        # the file's triangles, as its faces list them (1-based "f a b c", a/t/n allowed)
        faces = [[int(v.split("/")[0]) - 1 for v in line.split()[1:4]]
                 for line in (SCENES.parent / "meshes" / "poncho.obj").read_text().splitlines()
                 if line.startswith("f ")]
        assert np.array_equal(triangles, np.array(faces, dtype=np.uint32)), \
            "the triangles are not the OBJ file's faces"
        assert np.array_equal(xyz, sim.positions())
        # unit normals, along the area-weighted sum of the normals of the faces around a vertex
        a, b, c = (xyz[triangles[:, k]].astype(np.float64) for k in range(3))
        summed = np.zeros((755, 3))
        for k in range(3):
            np.add.at(summed, triangles[:, k], np.cross(b - a, c - a))
        want = summed / np.linalg.norm(summed, axis=1, keepdims=True)
        lengths = np.linalg.norm(normals, axis=1)
        assert np.allclose(lengths, 1, atol=1e-5), f"normal lengths {lengths.min()}..{lengths.max()}"
        along = np.einsum("ij,ij->i", normals, want)
        assert along.min() > 1 - 1e-5, f"a normal is {np.degrees(np.arccos(along.min()))} deg off"
        cloths = sim.cloths()
        assert len(cloths) == 1 and cloths[0]["mesh"], cloths
        assert (cloths[0]["particle_count"], cloths[0]["triangle_count"]) == (755, 1351)
