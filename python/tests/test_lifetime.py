"""Objects are destroyed children first whatever releases them: close(), a with block, the
garbage collector finalizing a reference cycle (weak references already cleared, finalizers in
any order) or the interpreter's exit. Each case runs in its own interpreter, so that a
use-after-free shows as a crash (a non-zero exit) rather than taking the test run down."""

import os
import subprocess
import sys

import pytest

from conftest import ROOT, SCENES, SMALL

SETUP = f"""
import gc, clothvk
scene = clothvk.Scene.load({str(SCENES / 'hanging.json')!r},
                           overrides={dict(SMALL, **{'render.size': [32, 24]})!r})
ctx = clothvk.Context()
sim = clothvk.Simulation(ctx, scene)
renderer = clothvk.Renderer(sim, scene)
sim.step(1)
"""

CASES = {
    "context closed first": "ctx.close(); assert sim.closed and renderer.closed",
    "a cycle collected": "ctx.cycle = (ctx, sim, renderer, scene)\n"
                         "del ctx, sim, renderer, scene\ngc.collect()",
    "left to the interpreter's exit": "ctx.cycle = ctx",
    "the simulation closed twice": "sim.close(); sim.close(); renderer.close(); ctx.close()",
}


@pytest.mark.parametrize("ending", CASES.values(), ids=CASES.keys())
def test_release_order(ending):
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python"))
    run = subprocess.run([sys.executable, "-c", SETUP + ending + "\nprint('done')"],
                         env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and run.stdout.strip() == "done", \
        f"exit status {run.returncode}, stdout {run.stdout!r}, stderr {run.stderr[-2000:]!r}"
