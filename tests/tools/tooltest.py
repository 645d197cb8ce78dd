"""What the scripts that test the command-line tools share: running a tool, the one stderr line
of bad input, "nothing written", --dump CSVs, and the closing "N of M cases passed" line.

The scripts run as `python3 tests/tools/test_x.py TOOL...`, so this folder is on sys.path and
`import tooltest` finds this file. Plain standard library, like the scripts.

A case is a function that returns a list of problems, each a sentence saying what was expected
and what came instead; an empty list is a pass. The scripts that collect failures as they go
instead use Checks.
"""
import os
import re
import subprocess
import sys
import tempfile
import struct
import time
import zlib

# The source tree, for its scenes and assets: meson says where; by hand, the folder above this one.
ROOT = os.environ.get("CLOTHVK_SOURCE_ROOT") or os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# The one part of a tool's message that depends on the machine: lavapipe's device name, which
# carries the LLVM version and the vector width, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
LLVMPIPE = "{llvmpipe}"
LLVMPIPE_PATTERN = r"llvmpipe \(LLVM [0-9.]+, [0-9]+ bits\)"
HEAP_SIZE = "<heap size>"
HEAP_SIZE_PATTERN = r"[0-9]+ bytes \([0-9.]+ GiB\)"


def tool_paths(*names):
    """The absolute paths of the tools a script is given on its command line, one per name (it
    exits with its usage line otherwise). Turns the validation layer on, as meson does, when the
    script is run by hand, so that it checks the same things."""
    if len(sys.argv) != len(names) + 1:
        sys.exit(f"usage: {os.path.basename(sys.argv[0])} " + " ".join(f"PATH/TO/{n}" for n in names))
    os.environ.setdefault("CLOTHVK_VALIDATION", "1")
    return [os.path.abspath(path) for path in sys.argv[1:]]


def tool_line(tool, message):
    """The line a tool prints on stderr for bad input: its name, a colon, the message."""
    return f"{tool}: {message}"


def run_tool(tool, argv, cwd=None, env=None, timeout=None):
    """Runs `tool argv` and captures its stdout and stderr as text. env: a whole environment
    (None: this one)."""
    return subprocess.run([tool] + list(argv), cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout)


def line_matches(got, expected):
    """Whether a line equals `expected`, where LLVMPIPE in `expected` stands for any lavapipe
    device name and HEAP_SIZE for a memory heap's size ("2147483648 bytes (2.0 GiB)")."""
    if LLVMPIPE not in expected and HEAP_SIZE not in expected:
        return got == expected
    pattern = re.escape(expected).replace(re.escape(LLVMPIPE), LLVMPIPE_PATTERN)
    pattern = pattern.replace(re.escape(HEAP_SIZE), HEAP_SIZE_PATTERN)
    return re.fullmatch(pattern, got) is not None


def listing(folder):
    """Every file and folder under `folder`, as sorted paths relative to it."""
    found = []
    for base, dirs, files in os.walk(folder):
        for name in dirs + files:
            found.append(os.path.relpath(os.path.join(base, name), folder))
    return sorted(found)


def contents(folder):
    """{name: bytes} of every file in `folder` ({} when it does not exist): a folder's state, to
    compare byte for byte before and after."""
    if not os.path.isdir(folder):
        return {}
    out = {}
    for name in sorted(os.listdir(folder)):
        with open(os.path.join(folder, name), "rb") as f:
            out[name] = f.read()
    return out


def nothing_written(before, after):
    """Problems when the listing `after` a refused run differs from the one `before` it."""
    if after == before:
        return []
    return [f"expected nothing written, found {sorted(set(after) - set(before))}"]


def stderr_mismatch(expected, lines):
    """The two problem lines for a stderr that is not the expected one: expected, then got."""
    return [f"expected stderr: {expected}",
            "got stderr:      " + "\n                 ".join(lines or ["(nothing)"])]


def refusal_problems(p, expected, before, after, status=2, stderr_ok=None):
    """Problems with a run `p` that must refuse bad input: exit `status`, stderr the one line
    `expected` (or lines that stderr_ok accepts), nothing on stdout, and the working folder's
    listing `after` the run as it was `before`."""
    problems = []
    if p.returncode != status:
        problems.append(f"expected exit status {status}, got {p.returncode}")
    lines = p.stderr.splitlines()
    if not (stderr_ok(lines) if stderr_ok else lines == [expected]):
        problems += stderr_mismatch(expected, lines)
    if p.stdout:
        problems.append(f"expected nothing on stdout, got: {p.stdout.strip()[:300]}")
    return problems + nothing_written(before, after)


def run_cases(cases):
    """Runs each (name, function returning a list of problems) case, prints "ok" or "FAIL" and
    the problems for each and a count; returns the exit status: 1 when any failed."""
    failed = 0
    for name, run in cases:
        problems = run()
        print(f"{'FAIL' if problems else 'ok  '} {name}")
        for problem in problems:
            print(f"     {problem}")
        failed += bool(problems)
    print(f"{len(cases)} cases, {failed} failed")
    return 1 if failed else 0


def make_files(folder, names):
    """Puts into a case's working folder what it names: "NAME" a file, "NAME/" a folder,
    "NAME/!" a folder nobody may write into."""
    for name in names:
        if "/" in name:
            path = os.path.join(folder, name.split("/")[0])
            os.makedirs(path)
            if name.endswith("!"):
                os.chmod(path, 0o555)
        else:
            with open(os.path.join(folder, name), "w") as f:
                f.write("not a folder\n")


def refused_run(tool, argv, expected, files=(), prefix="clothvk-"):
    """Runs `tool argv` in a fresh folder holding `files` (see make_files): the problems with it
    as a run that must refuse bad input (see refusal_problems)."""
    with tempfile.TemporaryDirectory(prefix=prefix) as workdir:
        make_files(workdir, files)
        before = listing(workdir)
        p = run_tool(tool, argv, workdir, timeout=120)
        return refusal_problems(p, expected, before, listing(workdir))


def accepted_problems(p, status, workdir, check=None, stderr_lines=()):
    """Problems with a run `p` of good input: exit `status`, nothing on stderr but
    `stderr_lines` (the notes a scene earns, each compared whole), and what check(stdout,
    workdir) finds when the run exited with 0."""
    problems = []
    if p.returncode != status:
        problems.append(f"expected exit status {status}, got {p.returncode}")
    if p.stderr.splitlines() != list(stderr_lines):
        problems.append(f"expected {len(stderr_lines)} lines on stderr {list(stderr_lines)!r}, "
                        "got:\n    " + "\n    ".join(p.stderr.splitlines()))
    if check and p.returncode == 0:
        problems += check(p.stdout, workdir)
    return problems


def read_csv(path, number=float):
    """The rows of a --dump CSV (one particle's "x,y,z" a line), each value through `number`."""
    with open(path) as f:
        return [[number(float(x)) for x in line.split(",")] for line in f.read().splitlines()]


def worst(a, b):
    """The largest difference between matching coordinates of two lists of points (0 for none)."""
    return max((abs(x - y) for p, q in zip(a, b) for x, y in zip(p, q)), default=0.0)


def unwritable_folder():
    """A folder that takes no new file, and the reason, for a user who may be root (who writes
    into any folder whatever its mode): /sys refuses even root. None when there is none."""
    try:
        fd = os.open("/sys/clothvk-probe", os.O_CREAT | os.O_WRONLY, 0o600)
    except OSError as e:
        return "/sys", os.strerror(e.errno)
    os.close(fd)
    os.unlink("/sys/clothvk-probe")
    return None


def locked_folder():
    """(folder, files for make_files, reason) for a case whose output folder takes no new file:
    a folder made read-only, or for root (who writes into any folder whatever its mode) /sys;
    None when there is none."""
    if os.geteuid() != 0:
        return "locked", ["locked/!"], "Permission denied"
    found = unwritable_folder()
    return (found[0], [], found[1]) if found else None


class Cases:
    """Counts cases as they are run, prints each failure with its problems, and ends with the
    closing line "LABEL: N of M cases passed (F failed) in S s". With CLOTHVK_CASE_SECONDS=1 in
    the environment it also prints each case's seconds (since the case before it ended), to find
    the slow ones (docs/testing.md)."""

    def __init__(self, label):
        self.label = label
        self.start = self.last = time.monotonic()
        self.timed = os.environ.get("CLOTHVK_CASE_SECONDS") == "1"
        self.total = self.failed = self.skipped = 0

    def add(self, heading, problems):
        """One case's problems; none is a pass."""
        if self.timed:
            now = time.monotonic()
            print(f"{now - self.last:7.2f} s  {heading}")
            self.last = now
        self.total += 1
        if problems:
            self.failed += 1
            print(f"FAIL {heading}")
            for problem in problems:
                print(f"    {problem}")

    def skip(self, line):
        """A case that cannot be run here: said, and counted apart."""
        self.skipped += 1
        print(f"skip {line}")

    def run(self, checks):
        """Runs (heading, function returning problems) pairs in order, then finishes."""
        for heading, check in checks:
            self.add(heading, check())
        return self.finish()

    def finish(self, note="", count_skipped=False, before_closing=None):
        """Prints the closing line (with the skipped count when asked; `note` after it, and the
        line `before_closing` before it); returns the exit status."""
        seconds = time.monotonic() - self.start
        if before_closing:
            print(before_closing)
        skipped = f", {self.skipped} skipped" if count_skipped else ""
        print(f"{self.label}: {self.total - self.failed} of {self.total} cases passed "
              f"({self.failed} failed{skipped}) in {seconds:.1f} s{note}")
        return 1 if self.failed else 0


class Checks:
    """check(cond, message) for scripts that check as they go: each failed message is printed
    on stderr at once and counted; finish says how many failed, or prints the pass line."""

    def __init__(self):
        self.failures = []

    def check(self, cond, message):
        if not cond:
            self.failures.append(message)
            print("FAILED:", message, file=sys.stderr)

    def finish(self, passed_line):
        if self.failures:
            print(f"{len(self.failures)} checks failed", file=sys.stderr)
            return 1
        print(passed_line)
        return 0


def png_info(path):
    """(width, height, colour type) of a complete PNG file; raises ValueError otherwise."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("no PNG signature")
    at, header, idat, ended = 8, None, b"", False
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        crc = struct.unpack(">I", data[at + 8 + length:at + 12 + length])[0]
        if zlib.crc32(kind + body) != crc:
            raise ValueError(f"bad CRC in chunk {kind!r}")
        if kind == b"IHDR":
            header = struct.unpack(">IIBB", body[:10])
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            ended = True
        at += 12 + length
    if not header or not ended:
        raise ValueError("no IHDR or no IEND: truncated")
    width, height, depth, colour = header
    channels = {2: 3, 6: 4}[colour]
    if len(zlib.decompress(idat)) != height * (1 + width * channels):
        raise ValueError("the image data has the wrong size")
    return width, height, colour


def png_pixels(path):
    """An 8-bit RGB(A) PNG's samples, decoded here: the IDAT chunks inflated and each row's
    filter undone (PNG spec 9.2); (width, channels, bytes), rows one after another."""
    with open(path, "rb") as f:
        data = f.read()
    at, idat, header = 8, b"", None
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBB", body[:10])
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    width, height, _, colour = header
    n = {2: 3, 6: 4}[colour]
    raw = zlib.decompress(idat)
    stride = width * n
    out = bytearray()
    prev = bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - n] if i >= n else 0
            b = prev[i]
            c = prev[i - n] if i >= n else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out += line
        prev = line
    return width, n, bytes(out)
