#!/usr/bin/env python3
"""The public headers stand on their own: each of lib/include/clothvk.h and
lib/include/clothvk/*.h compiles as the only include of a C11 file (and of a C++ file, when a
C++ compiler is found) with every warning an error; each is at most 800 lines; and
lib/meson.build installs each one, so an installed clothvk.h finds every header it includes.

Usage: check_headers.py [--self-test] SOURCE_ROOT. Exit 0 when all hold; 1 with one line per
break (a compile error's line is followed by the compiler's message). --self-test first checks
that a small tree with a header that does not compile alone, a header over 800 lines and a
header lib/meson.build does not install is refused with exactly those breaks."""
import os
import re
import shutil
import subprocess
import sys
import tempfile

import house

MAX_LINES = 800
FLAGS = ["-Wall", "-Wextra", "-Wpedantic", "-Werror", "-fsyntax-only"]


def headers(include):
    found = ["clothvk.h"]
    sub = os.path.join(include, "clothvk")
    found += ["clothvk/" + n for n in sorted(os.listdir(sub)) if n.endswith(".h")]
    return found


def compilers():
    """(compiler, standard, suffix) for C11, and C++11 when a C++ compiler is found."""
    found = [(os.environ.get("CC", "cc"), "c11", ".c")]
    cxx = os.environ.get("CXX", "c++")
    if shutil.which(cxx):
        found.append((cxx, "c++11", ".cpp"))
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


def check(root):
    """One finding per break, for the public headers of the tree at `root`; a compile error's
    finding is its first line, a newline, then the compiler's message."""
    include = os.path.join(root, "lib", "include")
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
            for compiler, std, suffix in compilers():
                ok, message = compiles(compiler, std, suffix, include, h, work)
                if not ok:
                    errors.append(f"lib/include/{h}: does not compile alone with {compiler} "
                                  f"-std={std}:\n{message}")
    return errors


def self_test():
    """A clothvk.h including a good header and one that uses size_t without <stddef.h>, a
    header of MAX_LINES + 1 lines, and a lib/meson.build that leaves the good header out:
    exactly the bad header and clothvk.h not compiling (with each compiler), the long header
    and the header not installed. A compile error is compared on its first line, the
    compiler's message being the compiler's."""
    files = {
        "lib/include/clothvk.h": '#include "clothvk/base.h"\n#include "clothvk/bad.h"\n',
        "lib/include/clothvk/base.h": "#ifndef BASE_H\n#define BASE_H\ntypedef int cvk_int;\n"
                                      "#endif\n",
        "lib/include/clothvk/bad.h": "size_t cvk_count(void);\n",
        "lib/include/clothvk/long.h": "/* long */\n" * (MAX_LINES + 1),
        "lib/meson.build": "install_headers('include/clothvk.h')\n"
                           "install_headers('include/clothvk/bad.h', 'include/clothvk/long.h',\n"
                           "  subdir: 'clothvk')\n",
    }
    want = [f"lib/include/clothvk/long.h: {MAX_LINES + 1} lines, more than {MAX_LINES}",
            "lib/include/clothvk/base.h: not installed by lib/meson.build (install_headers)"]
    for compiler, std, _ in compilers():
        for h in ("clothvk.h", "clothvk/bad.h"):
            want.append(f"lib/include/{h}: does not compile alone with {compiler} -std={std}:")
    return house.self_test("headers", lambda root: [e.split("\n")[0] for e in check(root)],
                           files, want)


def main():
    args = sys.argv[1:]
    if "--self-test" in args:
        args.remove("--self-test")
        if not self_test():
            return 1
    if len(args) != 1:
        sys.exit("usage: check_headers.py [--self-test] SOURCE_ROOT")
    root = args[0]
    errors = check(root)
    for e in errors:
        print(e)
    count = len(headers(os.path.join(root, "lib", "include")))
    print(f"{count} public headers, {count - len({e.split(':')[0] for e in errors})} stand "
          f"on their own ({', '.join(c for c, _, _ in compilers())})")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
