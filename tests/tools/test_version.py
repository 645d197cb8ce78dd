#!/usr/bin/env python3
"""--version on every tool: "TOOL VERSION" on stdout, nothing on stderr, exit status 0, where
VERSION is the project version in meson.build (the one the library is built as).

    python3 tests/tools/test_version.py MESON_BUILD TOOL...
"""
import os
import re
import subprocess
import sys

if len(sys.argv) < 3:
    sys.exit("usage: test_version.py MESON_BUILD TOOL...")


def project_version(path):
    with open(path) as f:
        text = f.read()
    m = re.search(r"project\([^)]*?version\s*:\s*'([^']+)'", text, re.S)
    if not m:
        sys.exit(f"no version: '...' in the project() call of {path}")
    return m.group(1)


def main():
    version = project_version(sys.argv[1])
    failed = 0
    for path in sys.argv[2:]:
        name = os.path.basename(path)
        p = subprocess.run([path, "--version"], capture_output=True, text=True, timeout=60)
        expected = f"{name} {version}\n"
        if (p.returncode, p.stdout, p.stderr) != (0, expected, ""):
            failed += 1
            print(f"FAIL {name} --version: exit status {p.returncode}, stdout {p.stdout!r}, "
                  f"stderr {p.stderr!r}; expected 0, {expected!r} and nothing")
    print(f"version {version}: {len(sys.argv) - 2 - failed} of {len(sys.argv) - 2} tools print it")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
