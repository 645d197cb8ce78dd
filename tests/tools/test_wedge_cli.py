#!/usr/bin/env python3
"""clothvk-sim wedges on one machine: --wedge-count, --jobs, --wedge-index, --wedge-gather, and
bad wedge specifications.

    python3 tests/tools/test_wedge_cli.py PATH/TO/clothvk-sim PATH/TO/slurm-wedge.sh

Good input (wedge_cases.py's scene and wedges):
- --wedge-count of the 2 x 3 wedge prints 6 and writes nothing;
- the wedge with --jobs 2 and --wedge-preview: wedges.csv equals six plain `clothvk-sim --set ...
  --json` runs of the same variants in every column but the timing ones (values, status, frames,
  every statistic), each variant folder holds status.json, scene.json, stats.json, log.txt and
  last.png, and the contact sheet is 3 x 2 tiles (804 x 442 pixels);
- --wedge-index 4 --wedge-bake alone into a new folder: the manifest and v0004 only, with its
  bake of frames 0 to 4, its stats.json the same as the --jobs run's but for the timings;
- the failing wedge (--wedges FILE, --jobs 3, --wedge-time-limit wedge_cases.TIME_LIMIT_S: 6 s,
  30 s under the sanitizers): a row that ran, a row that diverged in frame 0 with its message,
  and a row that timed out with the frames it ran;
- --wedge-gather on a folder whose variants did not end by themselves: a variant whose status
  still says running with a Slurm state TIMEOUT is a timed-out row quoting the state; one with
  no state is crashed, quoting the end of its log; one whose folder is gone is not-started; the
  others keep their rows.
Bad input: exit 2, exactly one line on stderr (compared whole), nothing on stdout and nothing
written, for an unknown key path, a value of the wrong type, an empty list, an empty value, a
key varied twice (two --wedge, or --wedge and the file), more variants than --wedge-limit and
than the default 1000, an index out of range in a key path, a wrong array length, bad --wedges
files (not JSON, empty, not a list of objects, a value of the wrong type), options a wedge does
not take, a missing -o, --wedge-index past the last variant, --jobs with --wedge-index, wedge
options without a wedge, --wedge-gather with more arguments or on a folder with no manifest, a
folder that holds another wedge, and slurm-wedge.sh with an unknown key (clothvk-sim's line,
before sbatch is looked for).
"""
import json
import os
import shutil
import sys
import tempfile

import tooltest
import wedge_cases

SIM, SCRIPT = tooltest.tool_paths("clothvk-sim", "slurm-wedge.sh")
CHECKS = tooltest.Checks()
check = CHECKS.check

SCENE_KEYS = ("name, dt, substeps, frames, integrate, gravity, damping, solver, cloths, render, "
              "collision, colliders, attachments, wind, air_density, instances")

# (arguments after the scene, files to write first {name: text}, the one stderr line)
BAD = [
    (["--wedge", "dtx=1,2"], {}, f"flag.json: dtx (from --wedge): unknown key (expected one of: "
     f"{SCENE_KEYS})"),
    (["--wedge", "dt=0.002,abc"], {},
     'flag.json: dt (from --wedge): expected a number, got the string "abc"'),
    (["--wedge", "dt="], {}, "--wedge dt=: no values (expected key.path=v1,v2,...)"),
    (["--wedge", "dt=0.002,,0.004"], {}, "--wedge dt=0.002,,0.004: value 2 is empty"),
    (["--wedge", "dt"], {}, "--wedge dt: expected key.path=v1,v2,..."),
    (["--wedge", "dt=0.002", "--wedge", "dt=0.004"], {}, "--wedge dt=0.004: dt is varied twice"),
    (["--wedge", "dt=0.001,0.002,0.003", "--wedge", "frames=1,2,3,4", "--wedge-limit", "10"], {},
     "--wedge: more than 10 variants (the limit; raise it with --wedge-limit N)"),
    (["--wedge", "frames=" + ",".join(str(f) for f in range(1, 41)), "--wedge",
      "substeps=" + ",".join(str(s) for s in range(1, 27))], {},
     "--wedge: more than 1000 variants (the limit; raise it with --wedge-limit N)"),
    (["--wedge", "cloths.3.mass=0.1"], {},
     "flag.json: --wedge cloths.3.mass: index 3 is out of range (cloths has 1 element)"),
    (["--wedge", "cloths.0.grid=[8,8],[4,4,4]"], {}, "flag.json: cloths.0.grid (from --wedge): "
     "expected an array of 2 whole numbers, got an array of 3"),
    (["--set", "dtx=1", "--wedge", "dt=0.002"], {},
     f"flag.json: dtx (from --set): unknown key (expected one of: {SCENE_KEYS})"),
    (["--wedges", "w.json"], {"w.json": "[]"},
     "--wedges w.json: expected a list of one or more objects (key.path -> value)"),
    (["--wedges", "w.json"], {"w.json": '{"dt": 0.002}'},
     "--wedges w.json: expected a list of one or more objects (key.path -> value)"),
    (["--wedges", "w.json"], {"w.json": "[1]"},
     "--wedges w.json: entry 0: expected an object (key.path -> value)"),
    (["--wedges", "w.json"], {"w.json": "[{"},
     "--wedges w.json: not JSON: string or '}' expected near end of file (line 1)"),
    (["--wedges", "w.json"], {"w.json": '[{"dt": 0.002}, {"dt": "x"}]'},
     'flag.json: dt (from --wedges w.json, entry 1): expected a number, got the string "x"'),
    (["--wedges", "w.json", "--wedge", "dt=0.002"], {"w.json": '[{"dt": 0.004}]'},
     "--wedge dt=0.002: dt is also varied in --wedges w.json"),
    (["--wedges", "none.json"], {},
     "--wedges none.json: unable to open none.json: No such file or directory"),
    (["--wedge", "dt=0.002", "--json"], {},
     "a wedge writes each variant's statistics into its folder: --json, --dump, --obj, --pc2, "
     "--bake, --resume, --every and --plan do not go with --wedge (see --wedge-bake)"),
    (["--wedge", "dt=0.002", "--jobs", "2", "--wedge-index", "0"], {},
     "--wedge-index, --jobs and --wedge-count: give one"),
    (["--wedge", "dt=0.002,0.004", "--wedge-index", "2"], {},
     "--wedge-index 2: the wedge has 2 variants (0 to 1)"),
    (["--wedge-preview"], {},
     "the wedge options need --wedge key.path=v1,v2,... or --wedges FILE"),
]


def refused(argv, files, expected, tool=SIM, out=True):
    """Runs in a fresh folder holding flag.json and `files`: exit 2, the one line, nothing
    written."""
    with tempfile.TemporaryDirectory(prefix="clothvk-wedge-") as workdir:
        wedge_cases.write_inputs(workdir)
        for name, text in files.items():
            with open(os.path.join(workdir, name), "w") as f:
                f.write(text)
        before = tooltest.listing(workdir)
        args = argv + (["-o", "out"] if out else [])
        env = dict(os.environ, CLOTHVK_SIM=SIM)  # for slurm-wedge.sh: the clothvk-sim under test
        p = tooltest.run_tool(tool, args, workdir, env=env, timeout=120)
        problems = tooltest.refusal_problems(p, expected, before, tooltest.listing(workdir))
        check(not problems, f"{' '.join(args)}: " + "; ".join(problems))


def bad_input():
    for args, files, line in BAD:
        refused(["flag.json"] + args, files, f"clothvk-sim: {line}")
    refused(["flag.json", "--wedge", "dt=0.002"], {},
            "clothvk-sim: a wedge needs an output folder (-o DIR)", out=False)
    refused(["--wedge-gather", "out", "flag.json"], {},
            "clothvk-sim: --wedge-gather DIR takes no other arguments", out=False)
    refused(["--wedge-gather", "nowhere"], {},
            "clothvk-sim: nowhere/wedge.json: unable to open nowhere/wedge.json: No such file or "
            "directory (the wedge's manifest; a run with --wedge-index or --jobs writes it)",
            out=False)
    refused(["flag.json", "--wedge", "dtx=1"], {}, f"clothvk-sim: flag.json: dtx (from --wedge): "
            f"unknown key (expected one of: {SCENE_KEYS})", tool=SCRIPT)


def good_input(tmp, scene, failing):
    r = tooltest.run_tool(SIM, [scene] + wedge_cases.WEDGE + ["--wedge-count"], tmp)
    check((r.returncode, r.stdout, r.stderr) == (0, "6\n", ""),
          f"--wedge-count: exit {r.returncode}, stdout {r.stdout!r}, stderr {r.stderr!r}")
    check(sorted(os.listdir(tmp)) == ["failing.json", "flag.json"],
          f"--wedge-count wrote {sorted(os.listdir(tmp))}")

    want = wedge_cases.local_rows(SIM, scene, check, tmp)
    out = os.path.join(tmp, "jobs")
    r = tooltest.run_tool(SIM, [scene] + wedge_cases.WEDGE + ["-o", out, "--jobs", "2",
                                                               "--wedge-preview"], tmp, timeout=300)
    check(r.returncode == 0 and r.stdout == f"clothvk-sim: 6 variants, 6 ok, 0 not: "
          f"{out}/wedges.csv, {out}/contact-sheet.png\n",
          f"--jobs 2: exit {r.returncode}, stdout {r.stdout!r}: {r.stderr.strip()}")
    wedge_cases.same_table("--jobs 2", os.path.join(out, "wedges.csv"), want, check)
    for k in range(6):
        folder = os.path.join(out, f"v{k:04d}")
        files = sorted(os.listdir(folder)) if os.path.isdir(folder) else []
        check(files == ["last.png", "log.txt", "scene.json", "stats.json", "status.json"],
              f"--jobs 2: v{k:04d} holds {files}")
    try:
        size = tooltest.png_info(os.path.join(out, "contact-sheet.png"))[:2]
        check(size == (804, 442), f"--jobs 2: contact sheet {size}, expected (804, 442)")
    except (OSError, ValueError) as e:
        check(False, f"--jobs 2: contact sheet: {e}")

    one = os.path.join(tmp, "one")
    r = tooltest.run_tool(SIM, [scene] + wedge_cases.WEDGE + ["-o", one, "--wedge-index", "4",
                                                               "--wedge-bake"], tmp, timeout=120)
    check(r.returncode == 0 and r.stdout == "" and r.stderr == "",
          f"--wedge-index 4: exit {r.returncode}: {r.stdout!r} {r.stderr!r}")
    want_files = ["v0004", "v0004/bake", "v0004/bake/cache.json"] + \
        [f"v0004/bake/frame_{f:04d}.snap" for f in range(5)] + \
        [f"v0004/{name}" for name in ("log.txt", "scene.json", "stats.json", "status.json")] + \
        ["wedge.json"]
    check(tooltest.listing(one) == sorted(want_files),
          f"--wedge-index 4 --wedge-bake wrote {tooltest.listing(one)}")
    stats = []
    for d in (one, out):
        with open(os.path.join(d, "v0004", "stats.json")) as f:
            stats.append(json.load(f))
    for s in stats:
        for key in ("wall_ms_per_frame", "gpu_ms_per_frame", "memory"):
            s.pop(key, None)
        for p in s.get("passes", []):
            p.pop("gpu_ms", None)
    check(stats[0] == stats[1], "--wedge-index 4: stats.json differs from the --jobs run's")

    failed = os.path.join(tmp, "failing")
    r = tooltest.run_tool(SIM, [scene, "--wedges", failing, "-o", failed, "--jobs", "3",
                                "--wedge-preview", "--wedge-time-limit",
                                str(wedge_cases.TIME_LIMIT_S)], tmp, timeout=300)
    check(r.returncode == 0, f"the failing wedge: exit {r.returncode}: {r.stderr.strip()}")
    wedge_cases.check_failing("the failing wedge (--jobs 3)", failed, check)
    gather_unfinished(out, want)


def tree(folder):
    """Every file under `folder` with its bytes: a folder's state, to compare before and after."""
    found = {}
    for name in tooltest.listing(folder):
        path = os.path.join(folder, name)
        if os.path.isfile(path):
            with open(path, "rb") as f:
                found[name] = f.read()
        else:
            found[name] = None
    return found


def gather_unfinished(out, want):
    """Variants that never wrote their end: the gather says so, row by row."""
    for k in (1, 2):
        with open(os.path.join(out, f"v{k:04d}", "status.json"), "w") as f:
            json.dump({"state": "running", "variant": k}, f)
    with open(os.path.join(out, "v0002", "log.txt"), "a") as f:
        f.write("clothvk-sim: the last words\n")
    shutil.rmtree(os.path.join(out, "v0003"))
    with open(os.path.join(out, "states.tsv"), "w") as f:
        f.write("1\tTIMEOUT\tSlurm job 7_1: TIMEOUT, reason TimeLimit, exit code 0:0\n")
    r = tooltest.run_tool(SIM, ["--wedge-gather", out], timeout=120)
    check(r.returncode == 0 and r.stdout == f"clothvk-sim: 6 variants, 3 ok, 3 not: "
          f"{out}/wedges.csv, {out}/contact-sheet.png\n",
          f"--wedge-gather: exit {r.returncode}, stdout {r.stdout!r}: {r.stderr.strip()}")
    _, rows = wedge_cases.read_table(os.path.join(out, "wedges.csv"))
    expect = {
        1: ("timed-out", "TIMEOUT: Slurm job 7_1: TIMEOUT, reason TimeLimit, exit code 0:0"),
        2: ("crashed", "no end status (status.json still says running): crashed or killed; its "
            "log ends: clothvk-sim: the last words"),
        3: ("not-started", "no status.json: the variant never started"),
    }
    for k, row in enumerate(rows):
        if k in expect:
            got = (row["status"], row["error"], row["frames_run"])
            check(got == expect[k] + ("",), f"--wedge-gather: variant {k}: {got}, expected "
                  f"{expect[k] + ('',)}")
            check(row["dt"] == want[k]["dt"], f"--wedge-gather: variant {k}: its values are gone")
        else:
            check(row["status"] == "ok" and row["residual"] == want[k]["residual"],
                  f"--wedge-gather: variant {k}: {row}")
    check(len(rows) == 6, f"--wedge-gather: {len(rows)} rows, expected 6")

    # Another wedge into the same folder is refused, and the folder stays as it was.
    before = tree(out)
    r = tooltest.run_tool(SIM, ["flag.json", "--wedge", "dt=0.003", "-o", out, "--jobs", "2"],
                          os.path.dirname(out), timeout=120)
    problems = tooltest.refusal_problems(
        r, f"clothvk-sim: {out}/wedge.json: holds another wedge (its scene, settings or variants "
        "differ); give another -o folder or remove it", before, tree(out))
    check(not problems, "another wedge in the folder: " + "; ".join(problems))


def main():
    bad_input()
    with tempfile.TemporaryDirectory(prefix="clothvk-wedge-") as tmp:
        wedge_cases.write_inputs(tmp)
        good_input(tmp, "flag.json", "failing.json")
    return CHECKS.finish("wedge-cli: every case passed")


if __name__ == "__main__":
    sys.exit(main())
