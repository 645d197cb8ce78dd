#!/usr/bin/env python3
"""clothvk-sim and clothvk-render on a scene too large for the memory they may use: under an
address-space limit (RLIMIT_AS) of 900 MB, a 1500 x 1500 grid is refused before it is built,
with exit status 1, one line naming the key, the figure and the limit, nothing on stdout and
no file written -- not an out-of-memory kill or a crash half-way through creation. And
clothvk-sim --json reports the memory a run held.

    python3 tests/tools/test_memory_cli.py PATH/TO/clothvk-sim PATH/TO/clothvk-render

Under AddressSanitizer (which reserves terabytes of address space) the limit cannot be
imposed: the refusal cases are skipped there and the --json case still runs.
"""
import json
import os
import re
import resource
import subprocess
import sys
import tempfile

import tooltest

SIM, RENDER = tooltest.tool_paths("clothvk-sim", "clothvk-render")
SMALL = os.path.join(tooltest.ROOT, "tests", "scenes", "small.json")
LIMIT = 900 * 1000 * 1000
GRID = ["--set", "cloths.0.grid=[1500,1500]", "--set", "cloths.0.pins=[[0,0]]"]


def limited():
    resource.setrlimit(resource.RLIMIT_AS, (LIMIT, resource.getrlimit(resource.RLIMIT_AS)[1]))


def refusal(tool, name, argv):
    with tempfile.TemporaryDirectory(prefix="clothvk-memory-") as workdir:
        before = tooltest.listing(workdir)
        p = subprocess.run([tool] + argv, cwd=workdir, capture_output=True, text=True,
                           timeout=120, preexec_fn=limited)
        pattern = (rf"{name}: {re.escape(SMALL)}: cloths\.0\.grid: 2250000 particles need about "
                   r"[0-9.]+ GiB of host memory( \(the device's memory included: it is the "
                   r"host's\))?; [0-9.]+ GiB is free \(bound by the address-space limit "
                   r"\(RLIMIT_AS\)\)")
        ok = lambda lines: len(lines) == 1 and re.fullmatch(pattern, lines[0]) is not None
        return tooltest.refusal_problems(p, pattern, before, tooltest.listing(workdir), status=1,
                                         stderr_ok=ok)


def json_memory():
    p = tooltest.run_tool(SIM, [SMALL, "--frames", "2", "--json"], timeout=120)
    if p.returncode != 0:
        return [f"--json run: exit {p.returncode}: {p.stderr.strip()}"]
    m = json.loads(p.stdout).get("memory", {})
    problems = []
    for key in ("device_bytes", "device_peak_bytes", "host_peak_rss_bytes"):
        if not isinstance(m.get(key), int) or m[key] <= 0:
            problems.append(f"--json memory.{key}: {m.get(key)!r}")
    if not problems and m["device_peak_bytes"] < m["device_bytes"]:
        problems.append(f"--json memory: peak {m['device_peak_bytes']} below now {m['device_bytes']}")
    return problems


def main():
    cases = [("json memory", json_memory)]
    if "ASAN_OPTIONS" not in os.environ:
        cases += [
            ("clothvk-sim, 1500 x 1500 under 900 MB",
             lambda: refusal(SIM, "clothvk-sim", [SMALL, "--frames", "1", "--dump", "out.csv"] + GRID)),
            ("clothvk-render, 1500 x 1500 under 900 MB",
             lambda: refusal(RENDER, "clothvk-render", [SMALL, "--frames", "1", "-o", "frames"] + GRID)),
        ]
    return tooltest.run_cases(cases)


if __name__ == "__main__":
    sys.exit(main())
