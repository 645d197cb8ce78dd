"""Scene load, step, positions against clothvk-sim --dump, state, cloths, statistics, plan."""

import gc
import json
import subprocess

import numpy as np
import pytest

import clothvk
from conftest import BUILD, SCENES, SMALL

FRAMES = 5


def read_dump(path):
    """clothvk-sim --dump: one "x,y,z" line per particle, each %.9g (round-trips a float)."""
    rows = [line.split(",") for line in path.read_text().splitlines()]
    return np.array(rows, dtype=np.float64).astype(np.float32)


def test_positions_equal_clothvk_sim_dump(ctx, small_scene, tmp_path):
    with clothvk.Simulation(ctx, small_scene) as sim:
        start = sim.positions()
        sim.step(FRAMES)
        xyz = sim.positions()
    assert xyz.shape == (256, 3) and xyz.dtype == np.float32
    dump = tmp_path / "dump.csv"
    sets = [a for k, v in SMALL.items() for a in ("--set", f"{k}={v}".replace(" ", ""))]
    subprocess.run([str(BUILD / "apps" / "clothvk-sim"), str(SCENES / "hanging.json"), *sets,
                    "--frames", str(FRAMES), "--dump", str(dump)],
                   check=True, stdout=subprocess.DEVNULL)
    expected = read_dump(dump)
    assert expected.shape == xyz.shape
    differ = np.argwhere(xyz != expected)
    assert differ.size == 0, (f"{len(differ)} coordinates differ from --dump, first at "
                              f"{differ[0]}: {xyz[tuple(differ[0])]!r} vs "
                              f"{expected[tuple(differ[0])]!r}")
    # the free particles hang below where they started: the comparison is of a moving cloth
    assert xyz[:, 1].min() < start[:, 1].min() - 1e-3, "the cloth did not fall"


def test_positions_fill_the_given_array(ctx, small_scene):
    with clothvk.Simulation(ctx, small_scene) as sim:
        out = np.zeros((256, 3), dtype=np.float32)
        assert sim.positions(out) is out
        assert out[15].tolist() == [0.5, 1.0, -0.5], f"particle [15, 0] at {out[15]}"
        with pytest.raises(ValueError) as caught:
            sim.positions(np.zeros((256, 3), dtype=np.float64))
        assert str(caught.value) == ("positions: expected a writable C-contiguous float32 array "
                                     "of shape (256, 3), got float64 (256, 3)")


def test_state_written_back_continues_the_same_motion(ctx, small_scene):
    with clothvk.Simulation(ctx, small_scene) as a, clothvk.Simulation(ctx, small_scene) as b:
        a.step(3)
        xyz, vel = a.state()
        assert np.abs(vel).max() > 0, "velocities are all zero after 3 frames of falling"
        b.write_state(xyz, vel)
        got_xyz, got_vel = b.state()
        assert np.array_equal(got_xyz, xyz) and np.array_equal(got_vel, vel)
        # Both run on: the velocity goes through v = u/h + hg/2 and back, a float rounding of
        # the displacement per particle (tests/sim/test_state.c), so the same motion to 5e-7 m.
        a.step(5)
        b.step(5)
        apart = np.abs(a.positions() - b.positions()).max()
        moved = np.abs(a.positions() - xyz).max()
        assert apart < 5e-7 and moved > 1e-3, f"{apart} m apart after the cloth moved {moved} m"


def test_cloths_stats_and_plan(ctx, small_scene):
    with clothvk.Simulation(ctx, small_scene) as sim:
        sim.step(2)
        assert sim.cloths() == [{"name": "sheet", "first_particle": 0, "particle_count": 256,
                                 "first_triangle": 0, "triangle_count": 2 * 15 * 15,
                                 "mesh": False}]
        st = sim.stats()
        assert (st["particles"], st["pinned"], st["frames"]) == (256, 2, 2)
        assert st["springs"] == [2 * 15 * 16, 0, 0]
        assert st["nan_count"] == 0
        assert [p["name"] for p in st["passes"]][:2] == ["predict", "solve"], st["passes"]
        assert "solver: pd / rbgs" in sim.plan()


def test_fused_memory_reaches_the_plan(ctx):
    """solver.fuse on: the fused sweeps' iterate in global memory by default on lavapipe (a CPU
    device), in shared memory when asked, and in either the same positions."""
    scene = clothvk.Scene.load(SCENES / "hanging.json",
                               overrides={**SMALL, "solver.fuse": "on"})
    ends = []
    for shared, memory in ((None, "global memory"), (True, "shared memory 4.0 KB"),
                           (False, "global memory")):
        with clothvk.Simulation(ctx, scene, fused_shared_memory=shared) as sim:
            assert f"one workgroup of 1024, {memory};" in sim.plan(), sim.plan()
            sim.step(3)
            ends.append(sim.positions())
    assert all((end == ends[0]).all() for end in ends)
    with pytest.raises(TypeError) as caught:
        clothvk.Simulation(ctx, scene, fused_shared_memory=1)
    assert str(caught.value) == "fused_shared_memory must be None (the library's choice), True " \
        "or False, got 1"


def test_crowded_particles_are_counted(ctx):
    """Sixteen small layers 1.2 mm apart, each shifted across the one below (test_determinism's
    crowd): particles a corner of more pairs than their lists hold show in contact_crowded, and
    the fields after it in cvk_sim_stats read as they should."""
    layers = [{"grid": [6, 6], "size": [0.1, 0.1], "mass": 0.01,
               "origin": [-0.05 + 0.0073 * (i % 3), 0.05 + 0.0012 * i, -0.05 + 0.0047 * (i % 4)]}
              for i in range(16)]
    text = json.dumps({"dt": 0.002, "substeps": 4,
                       "solver": {"outer_iterations": 2, "inner_iterations": 4},
                       "collision": {"self": True}, "cloths": layers,
                       "colliders": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}]})
    with clothvk.Simulation(ctx, clothvk.Scene.parse(text, "crowd")) as sim:
        sim.step(6)
        st = sim.stats()
        assert st["contact_crowded"] > 0
        assert st["intersecting_pairs"] == 0
        assert st["solver_iterations"] == 4 * 2 * 4  # the last frame's sweeps
        assert st["solver_iterations_total"] == 6 * 4 * 2 * 4  # six frames of them
        assert st["solver_breakdowns"] == 0
        assert st["diverged"] is False and st["diverged_frame"] == 0
        assert st["diverged_nonfinite"] is False


def test_override_reaches_the_solver(ctx):
    scene = clothvk.Scene.load(SCENES / "hanging.json",
                               overrides={**SMALL, "solver.linear": "jacobi"})
    with clothvk.Simulation(ctx, scene) as sim:
        assert "solver: pd / jacobi" in sim.plan(), sim.plan()


def test_notes_name_keys_without_effect(ctx):
    scene = clothvk.Scene.load(SCENES / "hanging.json", overrides={**SMALL, "collision.edges": True})
    with clothvk.Simulation(ctx, scene) as sim:
        assert sim.notes == ["collision.edges has no effect: edge-edge contact is always on"]
    with clothvk.Simulation(ctx, clothvk.Scene.load(SCENES / "hanging.json", overrides=SMALL)) as sim:
        assert sim.notes == []


def test_close_order_and_use_after_close(ctx, small_scene):
    with clothvk.Context() as own:
        sim = clothvk.Simulation(own, small_scene)
    assert own.closed and sim.closed, "closing the context leaves its simulation open"
    with pytest.raises(ValueError, match="Simulation is closed"):
        sim.step(1)
    sim = clothvk.Simulation(ctx, small_scene)
    handle = sim._h
    del sim  # collected without close(): __del__ destroys it
    gc.collect()
    assert handle.ptr is None and handle not in ctx._h.children


def test_pick_grab_release(ctx, small_scene):
    with clothvk.Simulation(ctx, small_scene) as sim:
        sim.step(2)
        xyz = sim.positions()
        aim = xyz[7 * 16 + 5]
        origin = aim + np.array([0.0, 1.0, 0.0], dtype=np.float32)
        hit = sim.pick(origin, [0, -1, 0], 0.01)
        # numpy's answer: the nearest along the ray of those within 1 cm of it
        v = xyz - origin
        t = -v[:, 1]
        near = np.hypot(v[:, 0], v[:, 2]) <= 0.01
        want = int(np.flatnonzero(near & (t >= 0))[np.argmin(t[near & (t >= 0)])])
        assert hit is not None and (hit["cloth"], hit["index"]) == (0, want), hit
        assert abs(hit["distance"] - t[want]) < 1e-5 and hit["position"] == xyz[want].tolist()
        assert sim.pick(origin, [0, 1, 0], 0.01) is None, "the cloth behind the origin was hit"
        with pytest.raises(clothvk.Error) as caught:
            sim.pick(origin, [0, 0, 0], 0.01)
        assert caught.value.result == "CVK_ERROR_INVALID_ARGUMENT" and str(caught.value) == \
            "cvk_sim_pick: the ray's direction must be finite and not zero, got [0, 0, 0]"
        target = [float(aim[0]), float(aim[1]) + 0.1, float(aim[2])]
        sim.grab(0, want, target)
        sim.step(1)
        assert np.abs(sim.positions()[want] - target).max() < 1e-6
        sim.release()
        sim.step(3)
        assert np.abs(sim.positions()[want] - target).max() > 1e-3, "still held after release"
        with pytest.raises(clothvk.Error) as caught:
            sim.grab(0, 0, target)
        assert caught.value.result == "CVK_ERROR_INVALID_ARGUMENT" and str(caught.value) == (
            'cvk_sim_grab: particle 0 of cloth 0 ("sheet") is pinned; only free particles can '
            'be grabbed')
        # a hand: every free particle within 10 cm of it moves with it, at its offset
        xyz = sim.positions()
        near = np.flatnonzero(np.linalg.norm(xyz - xyz[want], axis=1) <= 0.1)
        assert len(near) > 1
        lifted = xyz[want] + np.array([0.0, 0.1, 0.0], dtype=np.float32)
        sim.grab(0, want, lifted.tolist(), radius=0.1)
        sim.step(1)
        moved = sim.positions()[near] - (xyz[near] - xyz[want])
        assert np.abs(moved - lifted).max() < 1e-5
        with pytest.raises(clothvk.Error) as caught:
            sim.grab(0, want, target, radius=-1.0)
        assert caught.value.result == "CVK_ERROR_INVALID_ARGUMENT" and str(caught.value) == \
            "cvk_sim_grab_within: the radius must be a finite number of metres, at least 0; got -1"
