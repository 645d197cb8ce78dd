"""A detection that lavapipe's loop limit cuts short fails the step with CVK_ERROR_DEVICE_LIMIT,
shows in the stats, and is cleared by a new state (as a divergence is): docs/limits.md,
lavapipe's loop budget. The crowded stack is tests/tools/crowded_stack.py's, as the tool's test
has it."""

import json
import sys

import numpy as np
import pytest

import clothvk
from conftest import ROOT

sys.path.insert(0, str(ROOT / "tests" / "tools"))
import crowded_stack  # noqa: E402


def stack_scene(tmp_path):
    path = tmp_path / "crowded-stack.json"
    path.write_text(json.dumps(crowded_stack.scene()))
    return clothvk.Scene.load(path)


def test_a_cut_detection_fails_the_step_until_a_state_is_written(ctx, tmp_path):
    if "llvmpipe" not in ctx.info()["device_name"]:
        pytest.skip("the loop limit is lavapipe's; this device runs every loop to its end")
    sim = clothvk.Simulation(ctx, stack_scene(tmp_path))
    with pytest.raises(clothvk.Error) as caught:
        sim.step(1)
    def cut_short(frame):
        return (f"contact detection was cut short by frame {frame}: {ctx.info()['device_name']} "
                "ends a shader's loops after a fixed number of iterations (lavapipe: 65,535 an "
                "invocation) and the cloths lie too crowded for it, so pairs were missed and the "
                "guarantee that no cloth passes through cloth no longer holds; a larger "
                "cvk_sim_desc.max_workgroups (clothvk-sim --max-workgroups 65535) gives "
                "detection one item an invocation")

    assert caught.value.result == "CVK_ERROR_DEVICE_LIMIT", caught.value.result
    assert caught.value.message == cut_short(1), caught.value.message
    assert sim.stats()["contact_cut"] is True
    with pytest.raises(clothvk.Error) as again:
        sim.step(1)  # still cut: nothing cleared it
    assert again.value.result == "CVK_ERROR_DEVICE_LIMIT" and again.value.message == cut_short(2), \
        again.value.message
    # The same layers 5 cm apart: nothing crowds a detection, and the new state clears the flag.
    spread = sim.positions()
    spread[:, 1] = 0.3 + np.repeat(np.arange(crowded_stack.LAYERS),
                                    crowded_stack.PARTICLES_PER_LAYER) * 0.05
    sim.write_positions(spread)
    sim.step(1)
    stats = sim.stats()
    assert stats["contact_cut"] is False
    assert stats["intersecting_pairs"] == 0
