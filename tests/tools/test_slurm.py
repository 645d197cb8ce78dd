#!/usr/bin/env python3
"""scripts/slurm-render.sh on a real single-node Slurm cluster: every image equals a local render's.

    python3 tests/tools/test_slurm.py PATH/TO/clothvk-sim PATH/TO/clothvk-render PATH/TO/slurm-render.sh

The test starts a single-node cluster on localhost (slurm_cluster.py: munged, slurmctld and
slurmd, everything in a temporary folder). It bakes a small scene for 6 frames twice (--every 1 and --every 2), submits each
bake with slurm-render.sh --chunk 2 (4 and 2 array tasks: frames 0 to 6, and 0, 2, 4, 6), waits for the arrays, and checks that
every task COMPLETED and that the images are exactly the frames each bake holds, each equal byte
for byte to the one a local `clothvk-render SCENE --frames 6` writes. Then it stops every daemon
it started and removes the folder, and fails if any of its processes is still running.

Skipped (exit 77, with the reason) when Slurm or munge is not installed or when not run as root
(the daemons run as root: SlurmUser=root, and slurmd must start tasks as the submitting user).
"""
import json
import os
import subprocess
import sys
import time

import slurm_cluster

if len(sys.argv) != 4:
    sys.exit("usage: test_slurm.py PATH/TO/clothvk-sim PATH/TO/clothvk-render PATH/TO/slurm-render.sh")
SIM, RENDER, SCRIPT = (os.path.abspath(p) for p in sys.argv[1:])
os.environ.setdefault("CLOTHVK_VALIDATION", "1")

FRAMES = 6
CHUNK = 2
CLOTH = {"name": "flag", "grid": [16, 16], "size": [0.5, 0.4], "origin": [-0.25, 1.0, 0.0],
         "u_axis": [1, 0, 0], "v_axis": [0, -1, 0], "mass": 0.1,
         "stiffness": {"structural": 1e4, "shear": 1e3, "bend": 10}, "pins": [[0, 0], [15, 0]]}
SCENE = {"name": "flag", "dt": 0.004, "substeps": 4, "frames": FRAMES,
         "solver": {"linear": "rbgs", "outer_iterations": 2, "inner_iterations": 2},
         "render": {"size": [96, 64]}, "cloths": [CLOTH]}
JOB_WAIT_S = 400     # for both arrays to finish (lavapipe on 2 cores, validation on)

failures = []


def check(cond, message):
    if not cond:
        failures.append(message)
        print("FAILED:", message, file=sys.stderr)
    return cond


def submit(env, scene, bake, out, logs):
    r = subprocess.run([SCRIPT, scene, bake, out, "--chunk", str(CHUNK), "--",
                        f"--output={logs}/slurm-%A_%a.out"], env=env, capture_output=True,
                       text=True)
    job = r.stdout.strip()
    ok = check(r.returncode == 0 and job.isdigit(),
               f"slurm-render.sh {bake}: exit {r.returncode}, stdout {r.stdout!r}, "
               f"expected 0 and a job id: {r.stderr.strip()}")
    return job if ok else None


def check_tasks(cluster, job, tasks, logs):
    fields = cluster.job_fields(job)
    check(len(fields) == tasks, f"job {job}: {len(fields)} array tasks, expected {tasks}")
    for f in fields:
        task = f.get("ArrayTaskId", "?")
        if not check(f.get("JobState") == "COMPLETED" and f.get("ExitCode") == "0:0",
                     f"job {job} task {task}: {f.get('JobState')} exit {f.get('ExitCode')}"):
            print(slurm_cluster.tail(os.path.join(logs, f"slurm-{job}_{task}.out")),
                  file=sys.stderr)


def images(folder):
    if not os.path.isdir(folder):
        return {}
    out = {}
    for name in sorted(os.listdir(folder)):
        with open(os.path.join(folder, name), "rb") as f:
            out[name] = f.read()
    return out


def compare(what, got, frames, direct):
    want = [f"frame_{f:04d}.png" for f in frames]
    check(sorted(got) == want, f"{what}: images {sorted(got)}, expected {want}")
    for name, data in got.items():
        ref = direct.get(name)
        check(ref is not None and data == ref,
              f"{what}: {name} differs from the local render's ({len(data)} bytes against "
              f"{len(ref) if ref else 0})")


def run_local(args, what):
    r = subprocess.run(args, capture_output=True, text=True)
    check(r.returncode == 0, f"{what}: exit {r.returncode}: {r.stderr.strip()}")


def render_on_cluster(cluster):
    tmp = cluster.tmp
    env = dict(cluster.env, CLOTHVK_RENDER=RENDER)  # the build folder need not be build/ next to the script
    scene = os.path.join(tmp, "flag.json")
    with open(scene, "w") as f:
        json.dump(SCENE, f)
    run_local([RENDER, scene, "-o", os.path.join(tmp, "direct"), "--frames", str(FRAMES),
               "--quiet"], "local clothvk-render --frames 6")
    direct = images(os.path.join(tmp, "direct"))
    cases = []   # (every, job, frames held, tasks)
    for every in (1, 2):
        bake = os.path.join(tmp, f"bake{every}")
        run_local([SIM, scene, "--bake", bake, "--every", str(every)], f"bake --every {every}")
        held = list(range(0, FRAMES + 1, every))  # the start, then every K-th frame to the last
        job = submit(env, scene, bake, os.path.join(tmp, f"out{every}"), os.path.join(tmp, "logs"))
        if job:
            cases.append((every, job, held, -(-len(held) // CHUNK)))
    start = time.monotonic()
    if not cases or not cluster.wait_jobs([c[1] for c in cases], JOB_WAIT_S):
        return
    print(f"slurm: {sum(c[3] for c in cases)} array tasks in {len(cases)} jobs finished "
          f"{time.monotonic() - start:.1f} s after submission")
    for every, job, held, tasks in cases:
        check_tasks(cluster, job, tasks, os.path.join(tmp, "logs"))
        compare(f"job {job} (bake --every {every})", images(os.path.join(tmp, f"out{every}")),
                held, direct)


def main():
    slurm_cluster.preflight()
    with slurm_cluster.running(check, lambda: bool(failures)) as cluster:
        if cluster:
            render_on_cluster(cluster)
    if failures:
        print(f"{len(failures)} check(s) failed", file=sys.stderr)
        return 1
    print("slurm: every image from the job arrays equals the local render's")
    return 0


if __name__ == "__main__":
    sys.exit(main())
