#!/usr/bin/env python3
"""A detection that lavapipe's loop limit cuts short stops the run with an error, never silently.

    python3 tests/tools/test_loop_budget.py PATH/TO/clothvk-sim

lavapipe ends a shader's loops after 65,535 iterations in all, counted over every item an
invocation runs (docs/limits.md, lavapipe's loop budget). 500 cloths of 4 x 4 stacked 0.04 mm
apart put every triangle of the stack in one cell of the detection's hash, so an item of
detection walks thousands of entries, and the eight items an invocation takes on a CPU device
pass the limit. On lavapipe (CLOTHVK_DEVICE=llvmpipe) the run must then exit 1 with the one line
that names the frame and the device, write nothing, and with --max-workgroups (one item an
invocation) run the same stack whole: exit 0, no cut, no intersecting pair.
"""
import json
import os
import sys
import tempfile

import crowded_stack
import tooltest

[SIM] = tooltest.tool_paths("clothvk-sim")
DUMP = "out.csv"
CUT = tooltest.tool_line(
    "clothvk-sim",
    f"contact detection was cut short by frame 1: {tooltest.LLVMPIPE} ends a shader's loops after a "
    "fixed number of iterations (lavapipe: 65,535 an invocation) and the cloths lie too crowded "
    "for it, so pairs were missed and the guarantee that no cloth passes through cloth no longer "
    "holds; a larger cvk_sim_desc.max_workgroups (clothvk-sim --max-workgroups 65535) gives "
    "detection one item an invocation")


def lavapipe_env():
    env = dict(os.environ)
    env["CLOTHVK_DEVICE"] = "llvmpipe"
    return env


def cut_short(scene):
    problems = []
    with tempfile.TemporaryDirectory(prefix="clothvk-budget-") as work:
        result = tooltest.run_tool(SIM, [scene, "--dump", DUMP], cwd=work, env=lavapipe_env(),
                                   timeout=600)
        if result.returncode != 1:
            problems.append(f"exit status {result.returncode}, expected 1")
        lines = result.stderr.splitlines()
        if len(lines) != 1 or not tooltest.line_matches(lines[0], CUT):
            problems.append(f"stderr {result.stderr!r}, expected the one line {CUT!r}")
        if os.listdir(work):
            problems.append(f"left {sorted(os.listdir(work))} in its folder, expected nothing")
    return problems


def one_item_an_invocation(scene):
    problems = []
    result = tooltest.run_tool(SIM, [scene, "--max-workgroups", "65535", "--json"],
                               env=lavapipe_env(), timeout=600)
    if result.returncode != 0 or result.stderr:
        return [f"exit status {result.returncode}, stderr {result.stderr!r}; expected 0 and nothing"]
    contacts = json.loads(result.stdout)["contacts"]
    for key, expected in (("cut_short", False), ("searches", 1), ("intersecting_pairs", 0)):
        if contacts.get(key) != expected:
            problems.append(f"contacts.{key} {contacts.get(key)!r}, expected {expected!r}")
    return problems


def main():
    cases = tooltest.Cases("loop-budget")
    with tempfile.TemporaryDirectory(prefix="clothvk-budget-scene-") as folder:
        scene = os.path.join(folder, "crowded-stack.json")
        with open(scene, "w") as f:
            json.dump(crowded_stack.scene(), f)
        return cases.run([
            ("eight items an invocation: cut short, exit 1, nothing written", lambda: cut_short(scene)),
            ("one item an invocation: whole, no cut", lambda: one_item_an_invocation(scene)),
        ])


if __name__ == "__main__":
    sys.exit(main())
