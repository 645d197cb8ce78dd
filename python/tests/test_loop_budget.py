"""A detection that lavapipe's loop limit cuts short fails the step with CVK_ERROR_DEVICE_LIMIT,
shows in the stats, and is cleared by a new state (as a divergence is): docs/limits.md,
lavapipe's loop budget. The crowded stack is tests/tools/test_loop_budget.py's."""

import json

import numpy as np
import pytest

import clothvk

LAYERS = 500
SPACING = 0.00004  # m


def stack_scene(tmp_path):
    cloths = [{"name": f"layer{i}", "grid": [4, 4], "size": [0.2, 0.2],
               "origin": [-0.1, 0.3 + i * SPACING, -0.1], "u_axis": [1, 0, 0],
               "v_axis": [0, 0, 1], "mass": 0.05} for i in range(LAYERS)]
    path = tmp_path / "crowded-stack.json"
    path.write_text(json.dumps({
        "name": "crowded-stack", "dt": 0.002, "substeps": 1, "frames": 1, "gravity": [0, 0, 0],
        "solver": {"linear": "rbgs", "outer_iterations": 1, "inner_iterations": 1},
        "collision": {"self": True, "thickness": 0.00002}, "cloths": cloths}))
    return clothvk.Scene.load(path)


def test_a_cut_detection_fails_the_step_until_a_state_is_written(ctx, tmp_path):
    if "llvmpipe" not in ctx.info()["device_name"]:
        pytest.skip("the loop limit is lavapipe's; this device runs every loop to its end")
    sim = clothvk.Simulation(ctx, stack_scene(tmp_path))
    with pytest.raises(clothvk.Error) as caught:
        sim.step(1)
    assert caught.value.result == "CVK_ERROR_DEVICE_LIMIT", caught.value.result
    assert caught.value.message.startswith("contact detection was cut short by frame 1: llvmpipe")
    assert sim.stats()["contact_cut"] is True
    with pytest.raises(clothvk.Error):
        sim.step(1)  # still cut: nothing cleared it
    # The same layers 5 cm apart: nothing crowds a detection, and the new state clears the flag.
    spread = sim.positions()
    spread[:, 1] = 0.3 + np.repeat(np.arange(LAYERS), 16) * 0.05
    sim.write_positions(spread)
    sim.step(1)
    stats = sim.stats()
    assert stats["contact_cut"] is False
    assert stats["intersecting_pairs"] == 0
