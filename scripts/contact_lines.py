#!/usr/bin/env python3
"""The contact code's size at given revisions (docs/figures/contact-ogc/lines.csv): lines of the
files that make contact — lib/contact/, lib/sim/sim_contact.c, shaders/contact/ and the solvers'
contact passes (shaders/solvers/pd_contact.*, implicit_contact.comp, implicit_self.comp) — read
from git, split into code, comment and blank lines (a line is a comment when it starts with //,
/* or * after its indentation, or lies inside a /* */ block).

    python3 scripts/contact_lines.py OUT.csv LABEL=REV [LABEL=REV ...]

One row per revision and part (host C, shaders, the solvers' contact passes) and a total.
"""
import csv
import re
import subprocess
import sys

PARTS = (("host C (lib/contact/, lib/sim/sim_contact.c)",
          re.compile(r"^lib/contact/|^lib/sim/sim_contact\.c$")),
         ("shaders (shaders/contact/)", re.compile(r"^shaders/contact/")),
         ("the solvers' contact passes (shaders/solvers/)",
          re.compile(r"^shaders/solvers/(pd_contact\.|implicit_contact\.comp$|implicit_self\.comp$)")))
COLUMNS = ["build", "part", "files", "lines", "code lines", "comment lines", "blank lines"]


def git(*args):
    return subprocess.run(["git", *args], capture_output=True, text=True, check=True).stdout


def split(text):
    """(code, comment, blank) lines of a C or GLSL file."""
    code = comment = blank = 0
    in_block = False
    for line in text.splitlines():
        s = line.strip()
        if in_block:
            comment += 1
            in_block = "*/" not in s
        elif not s:
            blank += 1
        elif s.startswith("//") or s.startswith("*"):
            comment += 1
        elif s.startswith("/*"):
            comment += 1
            in_block = "*/" not in s
        else:
            code += 1
    return code, comment, blank


def rows(label, rev):
    files = git("ls-tree", "-r", "--name-only", rev).splitlines()
    total = [0, 0, 0, 0]
    out = []
    for name, pattern in PARTS:
        counts = [0, 0, 0, 0]
        for f in (f for f in files if pattern.search(f)):
            code, comment, blank = split(git("show", f"{rev}:{f}"))
            for i, v in enumerate((1, code, comment, blank)):
                counts[i] += v
        total = [a + b for a, b in zip(total, counts)]
        out.append([label, name, counts[0], sum(counts[1:]), *counts[1:]])
    out.append([label, "all", total[0], sum(total[1:]), *total[1:]])
    return out


def main():
    if len(sys.argv) < 3 or any("=" not in a for a in sys.argv[2:]):
        sys.exit("usage: contact_lines.py OUT.csv LABEL=REV [LABEL=REV ...]")
    table = []
    for arg in sys.argv[2:]:
        label, rev = arg.split("=", 1)
        table += rows(label, rev)
    with open(sys.argv[1], "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        w.writerows(table)


if __name__ == "__main__":
    main()
