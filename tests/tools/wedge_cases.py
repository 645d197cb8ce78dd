"""What the wedge tests share (test_wedge_cli.py, test_slurm_wedge.py): the scene, the two wedges,
the table a wedge must give (from plain local runs of its variants) and the comparison of tables.

    WEDGE: a 2 x 3 wedge (dt x structural stiffness) of an 8 x 8 flag, 4 frames each;
    FAILING: an explicit list of three variants: one that runs, one that diverges in its first
    frame (explicit Euler at dt 0.1) and one of 10^8 frames that passes its time limit.
"""
import csv
import json
import os

import tooltest

CLOTH = {"name": "flag", "grid": [8, 8], "size": [0.5, 0.4], "origin": [-0.25, 1.0, 0.0],
         "u_axis": [1, 0, 0], "v_axis": [0, -1, 0], "mass": 0.1,
         "stiffness": {"structural": 1e4, "shear": 1e3, "bend": 10}, "pins": [[0, 0], [7, 0]]}
SCENE = {"name": "flag", "dt": 0.004, "substeps": 4, "frames": 4,
         "solver": {"linear": "rbgs", "outer_iterations": 2, "inner_iterations": 2},
         "render": {"size": [96, 64]}, "cloths": [CLOTH]}

AXES = [("dt", ["0.004", "0.002"]), ("cloths.0.stiffness.structural", ["1e3", "1e4", "1e5"])]
WEDGE = [a for key, values in AXES for a in ("--wedge", f"{key}={','.join(values)}")]

FAILING = [{"dt": 0.004}, {"dt": 0.1, "solver.method": "explicit"}, {"frames": 100000000}]
# The limit counts from the variant's start, set-up included: under the sanitizers (tests/
# sanitize-tools.sh sets CLOTHVK_SANITIZED=1), with the validation layer and three variants on two
# cores, creating the device and pipelines alone has taken over 2 s, so variant 0 must have room.
TIME_LIMIT_S = 30 if os.environ.get("CLOTHVK_SANITIZED") else 6

# The columns that hold times: they differ from run to run and are left out of comparisons.
TIMING = {"wall_ms_per_frame", "gpu_ms_per_frame"}
# Statistics columns and where each is in clothvk-sim --json's object.
STATS = [("residual", "residual"), ("residual_normalized", "residual_normalized"),
         ("max_stretch", "max_stretch"), ("p99_stretch", "p99_stretch"),
         ("torn_springs", "torn_springs"), ("nan_count", "nan_count"),
         ("intersecting_pairs", "contacts.intersecting_pairs"),
         ("max_penetration", "contacts.max_penetration"),
         ("iterations_per_substep", "linear_solver.iterations_per_substep"),
         ("wall_ms_per_frame", "wall_ms_per_frame"), ("gpu_ms_per_frame", "gpu_ms_per_frame")]


def write_inputs(folder):
    """flag.json and failing.json in `folder`; returns their paths."""
    scene = os.path.join(folder, "flag.json")
    with open(scene, "w") as f:
        json.dump(SCENE, f)
    failing = os.path.join(folder, "failing.json")
    with open(failing, "w") as f:
        json.dump(FAILING, f)
    return scene, failing


def variants():
    """The wedge's variants in its order (the first axis slowest): [(key, value text), ...]."""
    out = [[]]
    for key, values in AXES:
        out = [v + [(key, value)] for v in out for value in values]
    return out


def cell(value):
    """A statistic as the table writes it: integers whole, reals in 9 significant digits."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    return "%.9g" % value


def stat(stats, path):
    for part in path.split("."):
        stats = stats.get(part) if isinstance(stats, dict) else None
    return stats


def local_rows(sim, scene, check, cwd=None):
    """The rows the wedge's table must hold, from one plain `clothvk-sim --set ... --json` run
    per variant."""
    rows = []
    for k, values in enumerate(variants()):
        args = [scene, "--json"] + [a for key, v in values for a in ("--set", f"{key}={v}")]
        r = tooltest.run_tool(sim, args, cwd, timeout=120)
        check(r.returncode == 0, f"local run {' '.join(args[1:])}: exit {r.returncode}: "
              f"{r.stderr.strip()}")
        if r.returncode != 0:
            rows.append({})
            continue
        stats = json.loads(r.stdout)
        row = {"variant": str(k), "status": "ok", "frames_run": str(stats["frames"]),
               "diverged": "false", "diverged_frame": "", "error": ""}
        row.update({key: v for key, v in values})
        row.update({column: cell(stat(stats, path)) for column, path in STATS})
        rows.append(row)
    return rows


def read_table(path):
    """(header, rows as dicts) of a wedges.csv; ([], []) when it cannot be read."""
    try:
        with open(path, newline="") as f:
            lines = list(csv.reader(f))
    except OSError:
        return [], []
    if not lines:
        return [], []
    return lines[0], [dict(zip(lines[0], line)) for line in lines[1:]]


def header():
    return (["variant"] + [key for key, _ in AXES] +
            ["status", "frames_run", "diverged", "diverged_frame"] +
            [column for column, _ in STATS] + ["error"])


def same_table(what, got_path, want_rows, check):
    """Checks a wedges.csv against rows, every column but the timing ones."""
    head, rows = read_table(got_path)
    check(head == header(), f"{what}: columns {head}, expected {header()}")
    check(len(rows) == len(want_rows), f"{what}: {len(rows)} rows, expected {len(want_rows)}")
    for got, want in zip(rows, want_rows):
        for column in header():
            if column in TIMING:
                check(got.get(column, "") != "", f"{what}: variant {want.get('variant')}: "
                      f"{column} is empty")
                continue
            check(got.get(column) == want.get(column),
                  f"{what}: variant {want.get('variant')}: {column} {got.get(column)!r}, "
                  f"expected {want.get(column)!r}")


def without_timing(path):
    head, rows = read_table(path)
    return head, [{k: v for k, v in row.items() if k not in TIMING} for row in rows]


def check_failing(what, folder, check, slurm_states=False):
    """The failing wedge's table: three rows, ok / diverged in frame 0 / timed-out."""
    head, rows = read_table(os.path.join(folder, "wedges.csv"))
    want_head = (["variant", "dt", "solver.method", "frames", "status", "frames_run", "diverged",
                  "diverged_frame"] + [column for column, _ in STATS] + ["error"])
    check(head == want_head, f"{what}: columns {head}, expected {want_head}")
    check(len(rows) == 3, f"{what}: {len(rows)} rows, expected 3")
    if len(rows) != 3:
        return
    ok, diverged, timed_out = rows
    check(ok["status"] == "ok" and ok["frames_run"] == "4" and ok["error"] == "",
          f"{what}: variant 0: {ok}")
    check((diverged["status"], diverged["diverged"], diverged["diverged_frame"], diverged["dt"],
           diverged["solver.method"]) == ("diverged", "true", "0", "0.1", "explicit"),
          f"{what}: variant 1: {diverged}")
    check(diverged["error"] == "flag.json: diverged in frame 0, cloth 0: a particle moved faster "
          "than 10000 m/s or a spring stretched past ten times its rest length; stopped there",
          f"{what}: variant 1's error: {diverged['error']!r}")
    frames = timed_out["frames_run"]
    check(timed_out["status"] == "timed-out" and frames.isdigit() and
          0 < int(frames) < 100000000 and timed_out["frames"] == "100000000",
          f"{what}: variant 2: {timed_out}")
    check(timed_out["error"] == f"flag.json: passed its time limit of {TIME_LIMIT_S} s after "
          f"{frames} of 100000000 frames; stopped there",
          f"{what}: variant 2's error: {timed_out['error']!r}")
    sheet = os.path.join(folder, "contact-sheet.png")
    try:
        width, height, _ = tooltest.png_info(sheet)
        # 2 columns of 256 + 12 pixels; rows of 256 * 64 / 96 = 170 pixels, 4 label lines of 11
        # and 18 of padding.
        check((width, height) == (536, 2 * 232), f"{what}: contact sheet {width} x {height}, "
              "expected 536 x 464")
    except (OSError, ValueError) as e:
        check(False, f"{what}: {sheet}: {e}")
