#!/usr/bin/env python3
"""scripts/slurm-wedge.sh on a real single-node Slurm cluster: the wedge's table equals local runs.

    python3 tests/tools/test_slurm_wedge.py PATH/TO/clothvk-sim PATH/TO/slurm-wedge.sh

The test starts a single-node cluster on localhost (slurm_cluster.py) and submits two wedges of
wedge_cases.py's 8 x 8 flag with slurm-wedge.sh, each one job array and a dependent gather job:
- the 2 x 3 wedge (dt x structural stiffness): every task and the gather COMPLETED; wedges.csv
  equals six plain `clothvk-sim --set ... --json` runs of the same variants in every column but
  the timing ones, and the table of the same wedge run with --jobs 2 on this machine; the gather
  wrote each task's Slurm state to states.tsv and a 3 x 2 contact sheet;
- the failing wedge (--wedges FILE, --wedge-time-limit wedge_cases.TIME_LIMIT_S: 6 s, 30 s under
  the sanitizers): three rows, one that ran, one that diverged in frame 0 (its task FAILED with
  exit 3) and one that timed out with the frames it ran (its task FAILED with exit 1), and the
  gather COMPLETED.
Then it stops every daemon it started and removes the folder, and fails if any of its processes
is still running.

Skipped (exit 77, with the reason) when Slurm or munge is not installed or when not run as root.
"""
import os
import re
import subprocess
import sys
import time

import slurm_cluster
import tooltest
import wedge_cases

SIM, SCRIPT = tooltest.tool_paths("clothvk-sim", "slurm-wedge.sh")
JOB_WAIT_S = 300     # for both wedges to finish (lavapipe on 2 cores, validation on)
CHECKS = tooltest.Checks()
check = CHECKS.check


def submit(cluster, args):
    """slurm-wedge.sh ARGS in the cluster's folder: (array job, gather job), or None."""
    env = dict(cluster.env, CLOTHVK_SIM=SIM)
    r = subprocess.run([SCRIPT] + args, cwd=cluster.tmp, env=env, capture_output=True, text=True,
                       timeout=120)
    gather = r.stdout.strip()
    array = re.match(r"slurm-wedge\.sh: job array ([0-9]+): ", r.stderr)
    check(r.returncode == 0 and gather.isdigit() and array,
          f"slurm-wedge.sh {' '.join(args)}: exit {r.returncode}, stdout {r.stdout!r}, expected 0 "
          f"and a job id: {r.stderr.strip()}")
    return (array.group(1), gather) if r.returncode == 0 and gather.isdigit() and array else None


def states(cluster, job):
    """{task: (JobState, ExitCode)} of a job (task "" for a job that is no array)."""
    return {f.get("ArrayTaskId", ""): (f.get("JobState"), f.get("ExitCode"))
            for f in cluster.job_fields(job)}


def check_states(cluster, what, job, want):
    got = states(cluster, job)
    check(got == want, f"{what}: job {job}: task states {got}, expected {want}")
    if got != want:
        for task in got:
            log = os.path.join(cluster.tmp, what, f"slurm-{job}_{task}.out")
            print(slurm_cluster.tail(log), file=sys.stderr)


def wedges_on_cluster(cluster):
    tmp = cluster.tmp
    wedge_cases.write_inputs(tmp)
    plain = submit(cluster, ["flag.json", "-o", "plain"] + wedge_cases.WEDGE)
    failing = submit(cluster, ["flag.json", "-o", "failing", "--wedges", "failing.json",
                               "--wedge-time-limit", str(wedge_cases.TIME_LIMIT_S)])
    start = time.monotonic()
    # While the cluster works: the references, on this machine.
    want = wedge_cases.local_rows(SIM, "flag.json", check, tmp)
    r = tooltest.run_tool(SIM, ["flag.json"] + wedge_cases.WEDGE + ["-o", "jobs", "--jobs", "2",
                                                                     "--wedge-preview"], tmp,
                          timeout=300)
    check(r.returncode == 0, f"--jobs 2: exit {r.returncode}: {r.stderr.strip()}")
    jobs = [j for pair in (plain, failing) if pair for j in pair]
    if not jobs or not cluster.wait_jobs(jobs, JOB_WAIT_S):
        return
    print(f"slurm-wedge: 2 wedges (9 array tasks, 2 gather jobs) finished "
          f"{time.monotonic() - start:.1f} s after submission")
    if plain:
        check_states(cluster, "plain", plain[0], {str(k): ("COMPLETED", "0:0") for k in range(6)})
        check_states(cluster, "plain", plain[1], {"": ("COMPLETED", "0:0")})
        table = os.path.join(tmp, "plain", "wedges.csv")
        wedge_cases.same_table("slurm", table, want, check)
        check(wedge_cases.without_timing(table) ==
              wedge_cases.without_timing(os.path.join(tmp, "jobs", "wedges.csv")),
              "slurm: wedges.csv differs from --jobs 2's (timings left out)")
        with open(os.path.join(tmp, "plain", "states.tsv")) as f:
            lines = f.read().splitlines()
        check([line.split("\t")[:2] for line in lines] ==
              [[str(k), "COMPLETED"] for k in range(6)], f"slurm: states.tsv holds {lines}")
        try:
            size = tooltest.png_info(os.path.join(tmp, "plain", "contact-sheet.png"))[:2]
            check(size == (804, 442), f"slurm: contact sheet {size}, expected (804, 442)")
        except (OSError, ValueError) as e:
            check(False, f"slurm: contact sheet: {e}")
    if failing:
        check_states(cluster, "failing", failing[0], {"0": ("COMPLETED", "0:0"),
                                                      "1": ("FAILED", "3:0"),
                                                      "2": ("FAILED", "1:0")})
        check_states(cluster, "failing", failing[1], {"": ("COMPLETED", "0:0")})
        wedge_cases.check_failing("slurm (failing wedge)", os.path.join(tmp, "failing"), check)


def main():
    slurm_cluster.preflight()
    with slurm_cluster.running(check, lambda: bool(CHECKS.failures)) as cluster:
        if cluster:
            wedges_on_cluster(cluster)
    return CHECKS.finish("slurm-wedge: the wedge's table from the cluster equals local runs; "
                         "the diverged and timed-out variants are rows")


if __name__ == "__main__":
    sys.exit(main())
