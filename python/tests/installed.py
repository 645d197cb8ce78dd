"""Run by scripts/test-pip.sh with a virtual environment's python, from outside the repository,
after pip install: the package and its library come from the environment, and a scene steps
and reads back as a numpy array. Not a pytest module (no test_ prefix)."""

import pathlib
import sys

import numpy as np

import clothvk
from clothvk import _ffi

package = pathlib.Path(clothvk.__file__).resolve().parent
assert pathlib.Path(sys.prefix).resolve() in package.parents, \
    f"clothvk imported from {package}, not from the environment {sys.prefix}"
library = pathlib.Path(_ffi.library_candidates()[0])
assert library == package / "libclothvk.so", f"opened {library}, not the package's own library"

scene = clothvk.Scene.load(sys.argv[1], overrides={"cloths.0.grid": [8, 8],
                                                   "cloths.0.pins": [[0, 0], [7, 0]]})
with clothvk.Context() as ctx, clothvk.Simulation(ctx, scene) as sim:
    start = sim.positions()
    sim.step(3)
    xyz = sim.positions()
assert isinstance(xyz, np.ndarray) and (xyz.shape, xyz.dtype) == ((64, 3), np.float32)
assert np.isfinite(xyz).all() and not np.array_equal(xyz, start), "the cloth did not move"
print(f"installed clothvk {clothvk.__version__}: {len(xyz)} positions after 3 frames, "
      f"library {library}")
