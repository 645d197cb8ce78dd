"""A single-node Slurm cluster for the tests of the Slurm scripts (test_slurm.py, test_wedge.py).

    with slurm_cluster.running(check) as cluster:
        if cluster:
            ... sbatch with env=cluster.env ..., cluster.wait_jobs([...], seconds)

running() starts munged, slurmctld and slurmd (Debian's munge and slurm-wlm) on localhost, with a
generated key and slurm.conf and every socket, pid, log and state file in a temporary folder
(SLURM_CONF points sbatch and the daemons at it; the controller and the node are 127.0.0.1, on
free ports; slurmd listens on 127.0.0.1 only, slurmctld on every address since Slurm 22.05 has no
bind address for it, but every message needs this run's random munge key), and waits for the
node to be idle. On leaving it cancels every job, stops every daemon it started, removes the
folder, and reports (through `check`) any of its processes still running. When something went
wrong it prints the daemons' last log lines.

preflight() exits 77 (skipped, with the reason) when Slurm or munge is not installed or when not
run as root (the daemons run as root: SlurmUser=root, and slurmd must start tasks as the
submitting user). Call it before anything else.
"""
import contextlib
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

DAEMONS = ["munged", "slurmctld", "slurmd"]
TOOLS = ["sbatch", "squeue", "sinfo", "scontrol", "scancel"]
NODE_WAIT_S = 90     # for the node to register idle


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
    """This process's environment without any Slurm job's variables, with our SLURM_CONF."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("SLURM_", "SBATCH_"))}
    env["SLURM_CONF"] = os.path.join(tmp, "slurm.conf")
    return env


def tail(path, lines=15):
    try:
        with open(path, errors="replace") as f:
            return "".join(f.readlines()[-lines:])
    except OSError as e:
        return f"({e})"


def start_cluster(tmp, env, check):
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
        check(r.returncode == 0, f"{os.path.basename(cmd[0])}: exit {r.returncode}: "
              f"{(r.stdout + r.stderr).strip()}")
        if r.returncode != 0:
            return False
    return True


def pid_files(tmp):
    return [os.path.join(tmp, "slurmd.pid"), os.path.join(tmp, "slurmctld.pid"),
            os.path.join(tmp, "munge", "munged.pid")]


def wait_node_idle(env, check):
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


class Cluster:
    """The running cluster: its folder (tmp) and the environment its clients need (env)."""

    def __init__(self, tmp, env, check):
        self.tmp = tmp
        self.env = env
        self.check = check

    def job_lines(self, job):
        """`scontrol -o show job JOB`: one line per array task."""
        r = slurm([tool("scontrol"), "-o", "show", "job", job], self.env)
        return r.stdout.splitlines() if r.returncode == 0 else []

    def job_fields(self, job):
        """Each line of job_lines as a dict of its KEY=VALUE fields."""
        return [dict(f.split("=", 1) for f in line.split() if "=" in f)
                for line in self.job_lines(job)]

    def wait_jobs(self, jobs, wait_s):
        """Polls squeue until none of the jobs is queued or running; True if they all left."""
        deadline = time.monotonic() + wait_s
        while time.monotonic() < deadline:
            r = slurm([tool("squeue"), "-h", "-j", ",".join(jobs), "-o", "%i %T"], self.env)
            if r.returncode == 0 and not r.stdout.strip():
                return True
            time.sleep(0.5)
        self.check(False, f"jobs {jobs} still queued or running after {wait_s} s")
        return False


@contextlib.contextmanager
def running(check, failed=lambda: False):
    """Yields a Cluster, or None when it did not start (check has been told why). `failed`
    says whether the test failed, for the daemons' logs. check(cond, message) records a failed
    check; what it returns is not used."""
    tmp = tempfile.mkdtemp(prefix="clothvk-slurm-")
    env = slurm_env(tmp)
    try:
        started = start_cluster(tmp, env, check) and wait_node_idle(env, check)
        yield Cluster(tmp, env, check) if started else None
        if failed() or not started:
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
