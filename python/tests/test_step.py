"""Simulation.step for any frame count: memory stays bounded, Ctrl-C stops it between chunks
with the frames done kept, and chunks change no bit. Also the package's public names."""

import os
import re
import signal
import subprocess
import sys
import time

import numpy as np

import clothvk
from conftest import ROOT, SCENES, SMALL

# Steps 2**31 - 1 frames of the small scene; on KeyboardInterrupt, says how many were done.
CHILD = f"""
import clothvk
ctx = clothvk.Context()
scene = clothvk.Scene.load({str(SCENES / "hanging.json")!r}, overrides={SMALL!r})
sim = clothvk.Simulation(ctx, scene)
print("stepping", flush=True)
try:
    sim.step(2**31 - 1)
except KeyboardInterrupt:
    print("interrupted after", sim.stats()["frames"], "frames", flush=True)
"""


def resident_mib(pid):
    status = open(f"/proc/{pid}/status").read()
    return int(re.search(r"VmRSS:\s+(\d+) kB", status)[1]) / 1024


def test_a_huge_step_stays_bounded_and_stops_on_ctrl_c():
    # One cvk_sim_step of 2**31 - 1 frames grew by about 900 MiB a second on lavapipe (queued
    # submissions) and ignored SIGINT until it ran out of memory.
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python"))
    child = subprocess.Popen([sys.executable, "-c", CHILD], env=env, text=True,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        assert child.stdout.readline() == "stepping\n", child.stderr.read()
        time.sleep(1)
        before = resident_mib(child.pid)
        time.sleep(2)
        grown = resident_mib(child.pid) - before
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=10)
    finally:
        child.kill()
        child.wait()
    assert grown < 32, f"stepping grew by {grown:.0f} MiB in 2 s"
    assert child.returncode == 0, err
    frames = int(re.fullmatch(r"interrupted after (\d+) frames\n", out)[1])
    assert frames > 0


def test_chunks_change_no_bit(ctx, small_scene):
    with clothvk.Simulation(ctx, small_scene) as whole, \
            clothvk.Simulation(ctx, small_scene) as single:
        whole.step(100)
        for _ in range(100):
            single.step()
        assert whole.stats()["frames"] == single.stats()["frames"] == 100
        assert np.array_equal(whole.positions(), single.positions())


def test_public_names():
    names = ["Context", "Error", "Renderer", "Scene", "SceneNotFoundError", "ScenePathError",
             "SceneValueError", "Simulation"]
    assert dir(clothvk) == names + ["__version__"]
    assert sorted(clothvk.__all__) == names
    assert all(getattr(clothvk, name) is not None for name in names)
    project = re.search(r"version: '([^']+)'", (ROOT / "meson.build").read_text())[1]
    assert clothvk.__version__ == project == "0.1.0"
