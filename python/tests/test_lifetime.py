"""Objects are destroyed children first whatever releases them: close(), a with block, the
garbage collector finalizing a reference cycle (weak references already cleared, finalizers in
any order) or the interpreter's exit. Each case runs in its own interpreter, so that a
use-after-free shows as a crash (a non-zero exit) rather than taking the test run down. The
context runs with the validation layer on, and where the case ends before the interpreter does,
every handle is destroyed and the layer reported nothing (an object destroyed after its device,
or a device destroyed with objects left, is a validation message)."""

import os
import subprocess
import sys

import pytest

from conftest import ROOT, SCENES, SMALL

SETUP = f"""
import gc, clothvk
scene = clothvk.Scene.load({str(SCENES / 'hanging.json')!r},
                           overrides={dict(SMALL, **{'render.size': [32, 24]})!r})
ctx = clothvk.Context(validation=True)
msgs = ctx.messages  # the list the layer's callback appends to, alive after the context
sim = clothvk.Simulation(ctx, scene)
renderer = clothvk.Renderer(sim, scene)
handles = (renderer._h, sim._h, ctx._h)
sim.step(1)
"""

# After the case's ending, where the interpreter is still running: all destroyed, no message.
DESTROYED = "\nassert all(h.ptr is None for h in handles), [h.ptr for h in handles]" \
            "\nassert msgs == [], msgs"

CASES = {
    "context closed first": "ctx.close(); assert sim.closed and renderer.closed" + DESTROYED,
    "a cycle collected": "ctx.cycle = (ctx, sim, renderer, scene)\n"
                         "del ctx, sim, renderer, scene\ngc.collect()" + DESTROYED,
    "left to the interpreter's exit": "ctx.cycle = ctx",
    "the simulation closed twice": "sim.close(); sim.close(); renderer.close(); ctx.close()"
                                   + DESTROYED,
}


@pytest.mark.parametrize("ending", CASES.values(), ids=CASES.keys())
def test_release_order(ending):
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python"))
    run = subprocess.run([sys.executable, "-c", SETUP + ending + "\nprint('done')"],
                         env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and run.stdout.strip() == "done", \
        f"exit status {run.returncode}, stdout {run.stdout!r}, stderr {run.stderr[-2000:]!r}"
