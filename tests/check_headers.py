#!/usr/bin/env python3
"""The public headers stand on their own: each of lib/include/clothvk.h and
lib/include/clothvk/*.h compiles as the only include of a C11 file (and of a C++ file, when a
C++ compiler is found) with every warning an error; each is at most 800 lines; and
lib/meson.build installs each one, so an installed clothvk.h finds every header it includes.

Usage: check_headers.py SOURCE_ROOT. Exit 0 when all hold; 1 with one line per break."""
import os
import re
import shutil
import subprocess
import sys
import tempfile

MAX_LINES = 800
FLAGS = ["-Wall", "-Wextra", "-Wpedantic", "-Werror", "-fsyntax-only"]


def headers(include):
    found = ["clothvk.h"]
    sub = os.path.join(include, "clothvk")
    found += ["clothvk/" + n for n in sorted(os.listdir(sub)) if n.endswith(".h")]
    return found


def compiles(compiler, std, suffix, include, header, work):
    source = os.path.join(work, "only" + suffix)
    with open(source, "w") as f:
        f.write(f'#include "{header}"\nint main(void) {{ return 0; }}\n')
    run = subprocess.run([compiler, "-std=" + std, *FLAGS, "-I", include, source],
                         capture_output=True, text=True)
    return run.returncode == 0, run.stderr.strip()


def installed(root):
    text = open(os.path.join(root, "lib", "meson.build"), encoding="utf-8").read()
    names = set()
    for call in re.finditer(r"install_headers\(([^)]*)\)", text):
        args = call.group(1)
        sub = re.search(r"subdir\s*:\s*'([^']*)'", args)
        prefix = sub.group(1) + "/" if sub else ""
        for path in re.findall(r"'(include/[^']+\.h)'", args):
            names.add(prefix + os.path.basename(path))
    return names


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: check_headers.py SOURCE_ROOT")
    root = sys.argv[1]
    include = os.path.join(root, "lib", "include")
    compilers = [(os.environ.get("CC", "cc"), "c11", ".c")]
    cxx = os.environ.get("CXX", "c++")
    if shutil.which(cxx):
        compilers.append((cxx, "c++11", ".cpp"))
    errors = []
    install = installed(root)
    with tempfile.TemporaryDirectory() as work:
        for h in headers(include):
            lines = open(os.path.join(include, h), encoding="utf-8").read().count("\n")
            if lines > MAX_LINES:
                errors.append(f"lib/include/{h}: {lines} lines, more than {MAX_LINES}")
            if h not in install:
                errors.append(f"lib/include/{h}: not installed by lib/meson.build "
                              f"(install_headers)")
            for compiler, std, suffix in compilers:
                ok, message = compiles(compiler, std, suffix, include, h, work)
                if not ok:
                    errors.append(f"lib/include/{h}: does not compile alone with {compiler} "
                                  f"-std={std}:\n{message}")
    for e in errors:
        print(e)
    count = len(headers(include))
    print(f"{count} public headers, {count - len({e.split(':')[0] for e in errors})} stand "
          f"on their own ({', '.join(c for c, _, _ in compilers)})")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
