#!/usr/bin/env python3
"""clothvk-ab as a user runs it: the library built here against itself on a small scene (every
pass timed in both, the ratios printed, the positions the same bits; options as --name VALUE
and --name=VALUE), and bad arguments refused with one line and exit status 2, a control
character in them written as \\xNN.

    python3 tests/tools/test_ab.py PATH/TO/clothvk-ab PATH/TO/libclothvk.so
"""
import os
import re
import sys

import tooltest

AB, LIB = tooltest.tool_paths("clothvk-ab", "libclothvk.so")
SMALL = os.path.join(tooltest.ROOT, "tests", "scenes", "small.json")
LIBM = "/lib/x86_64-linux-gnu/libm.so.6"


def same_build():
    """The build against itself: a table row per timed pass and the frame, each build's sum
    positive, and the same bits at the end."""
    p = tooltest.run_tool(AB, [LIB, LIB, SMALL, "--rounds", "3", "--frames-per-turn=2",
                               "--warm-up", "1", "--set=solver.inner_iterations=3"], timeout=300)
    if p.returncode != 0:
        return [f"exit {p.returncode}: {p.stderr.strip()}"]
    problems = [f"stderr: {line}" for line in p.stderr.splitlines()]
    lines = p.stdout.splitlines()
    if not lines or lines[0] != (f"{SMALL}: 6 frames each after 1 untimed, 3 rounds of 2 a turn, "
                                 "GPU ms from timestamps"):
        problems.append(f"first line: {lines[:1]}")
    rows = {}
    for line in lines:
        m = re.fullmatch(r"(\S+)\s+([0-9.]+)\s+([0-9.]+)\s+([0-9.]+)\s+([0-9.]+)", line)
        if m:
            rows[m.group(1)] = [float(v) for v in m.groups()[1:]]
    for name in ("frame", "solve"):
        if name not in rows:
            problems.append(f"no row for {name} in:\n{p.stdout}")
        elif rows[name][0] <= 0 or rows[name][1] <= 0:
            problems.append(f"{name}: sums {rows[name][:2]}")
    if "positions: the same bits (12 particles)" not in lines:
        problems.append(f"no 'the same bits' line in:\n{p.stdout}")
    return problems


REFUSALS = [
    ([], "usage: clothvk-ab BEFORE.so AFTER.so SCENE [--rounds N] [--frames-per-turn F] "
         "[--warm-up W] [--set KEY=VALUE]... [--version]"),
    (["--version=2"], "clothvk-ab: unknown option --version=2 (see --help)"),
    (["bad\x1bname.so", LIB, SMALL], "clothvk-ab: bad\\x1bname.so: cannot open shared object "
                                      "file: No such file or directory"),
    (["missing.so", LIB, SMALL], "clothvk-ab: missing.so: cannot open shared object file: "
                                 "No such file or directory"),
    ([LIB, LIB, "missing.json"], "clothvk-ab: missing.json: cannot open: No such file or directory"),
    ([LIB, LIB, SMALL, "--rounds", "0"],
     "clothvk-ab: --rounds: expected a whole number from 1 to 100000, got 0"),
    ([LIB, LIB, SMALL, "--warm-up=-1"],
     "clothvk-ab: --warm-up: expected a whole number from 0 to 10000, got -1"),
    ([LIB, LIB, SMALL, "--set", "mass"], "clothvk-ab: --set mass: expected key.path=value"),
    ([LIB, LIB, SMALL, "--set", "cloths.0.mass=-1"],
     f"clothvk-ab: {SMALL}: cloths.0.mass (from --set): must be greater than 0, got -1"),
    ([LIB, LIB, SMALL, "--fast"], "clothvk-ab: unknown option --fast (see --help)"),
    ([LIB, LIB, SMALL, SMALL], f"clothvk-ab: one argument too many: {SMALL}"),
]
if os.path.exists(LIBM):
    REFUSALS.append(([LIBM, LIB, SMALL], f"clothvk-ab: {LIBM}: no function "
                                         "cvk_default_context_desc (not a build of clothvk)"))


def main():
    cases = [("the build against itself", same_build)]
    for argv, expected in REFUSALS:
        shown = " ".join(argv).encode("unicode_escape").decode("ascii")
        cases.append((f"refused: {shown or '(no arguments)'}",
                      lambda a=argv, e=expected: tooltest.refused_run(AB, a, e)))
    return tooltest.run_cases(cases)


if __name__ == "__main__":
    sys.exit(main())
