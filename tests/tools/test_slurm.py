#!/usr/bin/env python3
"""scripts/slurm-render.sh on a real single-node Slurm cluster: every image equals a local render's.

    python3 tests/tools/test_slurm.py PATH/TO/clothvk-sim PATH/TO/clothvk-render PATH/TO/slurm-render.sh

The test starts munged, slurmctld and slurmd (Debian's munge and slurm-wlm) on localhost, with a
generated key and slurm.conf and every socket, pid, log and state file in a temporary folder
(SLURM_CONF points sbatch and the daemons at it; the controller and the node are 127.0.0.1, on
free ports; slurmd listens on 127.0.0.1 only, slurmctld on every address since Slurm 22.05 has no
bind address for it, but every message needs this run's random munge key). It bakes a small scene for 6 frames twice (--every 1 and --every 2), submits each
bake with slurm-render.sh --chunk 2 (4 and 2 array tasks: frames 0 to 6, and 0, 2, 4, 6), waits for the arrays, and checks that
every task COMPLETED and that the images are exactly the frames each bake holds, each equal byte
for byte to the one a local `clothvk-render SCENE --frames 6` writes. Then it stops every daemon
it started and removes the folder, and fails if any of its processes is still running.

Skipped (exit 77, with the reason) when Slurm or munge is not installed or when not run as root
(the daemons run as root: SlurmUser=root, and slurmd must start tasks as the submitting user).
"""
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

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
DAEMONS = ["munged", "slurmctld", "slurmd"]
TOOLS = ["sbatch", "squeue", "sinfo", "scontrol", "scancel"]
NODE_WAIT_S = 90     # for the node to register idle
JOB_WAIT_S = 400     # for both arrays to finish (lavapipe on 2 cores, validation on)

failures = []


def check(cond, message):
    if not cond:
        failures.append(message)
        print("FAILED:", message, file=sys.stderr)
    return cond


def slurm(args, env):
    """Runs a Slurm client; a client that hangs on a dead controller counts as exit 124."""
    try:
        return subprocess.run(args, env=env, capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        return subprocess.CompletedProcess(args, 124, "", f"{args[0]}: timed out after 60 s")


def skip(reason):
    print(f"skipped: {reason}")
    sys.exit(77)


def preflight():
    missing = [t for t in DAEMONS + TOOLS if shutil.which(t) is None
               and not os.access(f"/usr/sbin/{t}", os.X_OK)]
    if missing:
        skip(f"{', '.join(missing)} not installed (Debian packages slurm-wlm and munge; "
             "scripts/setup.sh installs them)")
    if os.geteuid() != 0:
        skip("the single-node cluster runs slurmctld and slurmd as root (SlurmUser=root; slurmd "
             "starts each task as the submitting user), and this test is not run as root")


def tool(name):
    return shutil.which(name) or f"/usr/sbin/{name}"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def slurm_conf(tmp, munge_socket):
    ports = free_port(), free_port()
    cpus = min(2, os.cpu_count() or 1)
    return f"""# Single-node test cluster: controller and node are this machine only (127.0.0.1).
ClusterName=clothvktest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort={ports[0]}
SlurmdPort={ports[1]}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket={munge_socket}
CredType=cred/munge
StateSaveLocation={tmp}/state
SlurmdSpoolDir={tmp}/spool
SlurmctldPidFile={tmp}/slurmctld.pid
SlurmdPidFile={tmp}/slurmd.pid
SlurmctldLogFile={tmp}/slurmctld.log
SlurmdLogFile={tmp}/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
MailProg=/bin/true
CommunicationParameters=NoInAddrAny
NodeName=localhost NodeAddr=127.0.0.1 NodeHostname=localhost CPUs={cpus} State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
"""


def slurm_env(tmp):
    """This process's environment without any Slurm job's variables, with our SLURM_CONF and the
    clothvk-render under test."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("SLURM_", "SBATCH_"))}
    env["SLURM_CONF"] = os.path.join(tmp, "slurm.conf")
    env["CLOTHVK_RENDER"] = RENDER   # the build folder need not be build/ next to the script
    return env


def tail(path, lines=15):
    try:
        with open(path, errors="replace") as f:
            return "".join(f.readlines()[-lines:])
    except OSError as e:
        return f"({e})"


def start_cluster(tmp, env):
    """munged, slurmctld, slurmd, all daemonizing and writing their pid files under tmp."""
    munge = os.path.join(tmp, "munge")
    os.makedirs(munge, mode=0o700)
    for d in ("state", "spool", "logs"):
        os.makedirs(os.path.join(tmp, d))
    key = os.path.join(munge, "munge.key")
    with open(key, "wb") as f:
        f.write(os.urandom(1024))
    os.chmod(key, 0o400)
    sock = os.path.join(munge, "munge.socket")
    with open(env["SLURM_CONF"], "w") as f:
        f.write(slurm_conf(tmp, sock))
    # --force: munged refuses to run as root, or with a socket folder others cannot enter.
    commands = [
        [tool("munged"), "--force", f"--socket={sock}", f"--key-file={key}",
         f"--pid-file={munge}/munged.pid", f"--log-file={munge}/munged.log",
         f"--seed-file={munge}/munged.seed"],
        [tool("slurmctld")],
        [tool("slurmd"), "-N", "localhost"],
    ]
    for cmd in commands:
        r = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if not check(r.returncode == 0, f"{os.path.basename(cmd[0])}: exit {r.returncode}: "
                     f"{(r.stdout + r.stderr).strip()}"):
            return False
    return True


def pid_files(tmp):
    return [os.path.join(tmp, "slurmd.pid"), os.path.join(tmp, "slurmctld.pid"),
            os.path.join(tmp, "munge", "munged.pid")]


def wait_node_idle(env):
    deadline = time.monotonic() + NODE_WAIT_S
    state = ""
    while time.monotonic() < deadline:
        r = slurm([tool("sinfo"), "-h", "-n", "localhost", "-o", "%t"], env)
        state = (r.stdout + r.stderr).strip()
        if r.returncode == 0 and state == "idle":
            return True
        time.sleep(0.5)
    check(False, f"the node did not become idle in {NODE_WAIT_S} s (sinfo: {state!r})")
    return False


def submit(env, scene, bake, out, logs):
    r = subprocess.run([SCRIPT, scene, bake, out, "--chunk", str(CHUNK), "--",
                        f"--output={logs}/slurm-%A_%a.out"], env=env, capture_output=True,
                       text=True)
    job = r.stdout.strip()
    ok = check(r.returncode == 0 and job.isdigit(),
               f"slurm-render.sh {bake}: exit {r.returncode}, stdout {r.stdout!r}, "
               f"expected 0 and a job id: {r.stderr.strip()}")
    return job if ok else None


def job_lines(env, job):
    r = slurm([tool("scontrol"), "-o", "show", "job", job], env)
    return r.stdout.splitlines() if r.returncode == 0 else []


def wait_jobs(env, jobs):
    """Polls squeue until none of the jobs is queued or running; True if they all left."""
    deadline = time.monotonic() + JOB_WAIT_S
    while time.monotonic() < deadline:
        r = slurm([tool("squeue"), "-h", "-j", ",".join(jobs), "-o", "%i %T"], env)
        if r.returncode == 0 and not r.stdout.strip():
            return True
        time.sleep(1)
    check(False, f"jobs {jobs} still queued or running after {JOB_WAIT_S} s")
    return False


def check_tasks(env, job, tasks, logs):
    lines = job_lines(env, job)
    check(len(lines) == tasks, f"job {job}: {len(lines)} array tasks, expected {tasks}")
    for line in lines:
        fields = dict(f.split("=", 1) for f in line.split() if "=" in f)
        task = fields.get("ArrayTaskId", "?")
        if not check(fields.get("JobState") == "COMPLETED" and fields.get("ExitCode") == "0:0",
                     f"job {job} task {task}: {fields.get('JobState')} exit "
                     f"{fields.get('ExitCode')}"):
            print(tail(os.path.join(logs, f"slurm-{job}_{task}.out")), file=sys.stderr)


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


def render_on_cluster(tmp, env):
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
    if not cases or not wait_jobs(env, [c[1] for c in cases]):
        return
    print(f"slurm: {sum(c[3] for c in cases)} array tasks in {len(cases)} jobs finished "
          f"{time.monotonic() - start:.1f} s after submission")
    for every, job, held, tasks in cases:
        check_tasks(env, job, tasks, os.path.join(tmp, "logs"))
        compare(f"job {job} (bake --every {every})", images(os.path.join(tmp, f"out{every}")),
                held, direct)


def stop(pid_file):
    """SIGTERM to the pid in pid_file, then waits (SIGKILL after 20 s)."""
    try:
        with open(pid_file) as f:
            pid = int(f.read().split()[0])
    except (OSError, ValueError, IndexError):
        return
    for sig, wait_s in ((signal.SIGTERM, 20), (signal.SIGKILL, 5)):
        try:
            os.kill(pid, sig)
        except ProcessLookupError:
            return
        deadline = time.monotonic() + wait_s
        while time.monotonic() < deadline:
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                return
            time.sleep(0.1)


def ours(pid, tmp):
    """True if the process's command line or environment names the temporary folder."""
    for part in ("cmdline", "environ"):
        try:
            with open(f"/proc/{pid}/{part}", "rb") as f:
                if tmp.encode() in f.read():
                    return True
        except OSError:
            pass
    return False


def left_running(tmp):
    left = []
    for name in DAEMONS + ["slurmstepd"]:
        r = subprocess.run(["pgrep", "-x", name], capture_output=True, text=True)
        left += [f"{name} {pid}" for pid in r.stdout.split() if ours(pid, tmp)]
    return left


def main():
    preflight()
    tmp = tempfile.mkdtemp(prefix="clothvk-slurm-")
    env = slurm_env(tmp)
    try:
        if start_cluster(tmp, env) and wait_node_idle(env):
            render_on_cluster(tmp, env)
        if failures:
            for log in ("slurmctld.log", "slurmd.log", "munge/munged.log"):
                print(f"--- {log} (last lines)\n{tail(os.path.join(tmp, log))}", file=sys.stderr)
    finally:
        slurm([tool("scancel"), "--full", "-u", "root"], env)
        for pid_file in pid_files(tmp):
            stop(pid_file)
        left = left_running(tmp)
        shutil.rmtree(tmp, ignore_errors=True)
    check(not left, f"still running after the cluster was stopped: {', '.join(left)}")
    check(not os.path.exists(tmp), f"{tmp} was not removed")
    if failures:
        print(f"{len(failures)} check(s) failed", file=sys.stderr)
        return 1
    print("slurm: every image from the job arrays equals the local render's")
    return 0


if __name__ == "__main__":
    sys.exit(main())
