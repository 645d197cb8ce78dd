#!/usr/bin/env python3
"""Sizes a newcomer can read: no file of lib/ or shaders/ over MAX_FILE lines, no function
(C, C++ or GLSL) over MAX_FUNCTION lines in lib/, shaders/, apps/ and examples/.

A function is counted from its first line at column 0 (the line with its name) to its closing
brace at column 0, both included.

Usage: check_sizes.py [ROOT] [--self-test]. Exit 0 when every size holds; 1 with one line per
file or function over its limit."""
import os
import re
import sys

import house

MAX_FILE = 800
MAX_FUNCTION = 80
FILE_DIRS = ("lib", "shaders")
FUNCTION_DIRS = ("lib", "shaders", "apps", "examples")
SOURCES = (".c", ".h", ".cpp", ".comp", ".glsl", ".vert", ".frag")
# A definition's first line: at column 0, a name followed by '(', not a statement or macro.
HEAD = re.compile(r"^[A-Za-z_][\w \t\*]*?\b(\w+)\s*\(")
NOT_HEAD = ("typedef", "struct", "enum", "union", "return", "if", "for", "while", "switch")


def functions(lines):
    """(name, first line, line count) of every function definition in `lines`."""
    found = []
    i = 0
    while i < len(lines):
        m = HEAD.match(lines[i])
        if m and not lines[i].startswith(NOT_HEAD) and not lines[i].rstrip().endswith(";"):
            j = i
            while j < len(lines) and "{" not in lines[j] and not lines[j].rstrip().endswith(";"):
                j += 1
            if j < len(lines) and "{" in lines[j] and (lines[j].startswith("{") or
                                                       lines[j].rstrip().endswith("{")):
                k = j
                while k < len(lines) and not lines[k].startswith("}"):
                    k += 1
                found.append((m.group(1), i + 1, k - i + 1))
                i = k + 1
                continue
        i += 1
    return found


def sources(root, dirs):
    for top in dirs:
        for folder, _, names in os.walk(os.path.join(root, top)):
            for name in sorted(names):
                if name.endswith(SOURCES):
                    path = os.path.join(folder, name)
                    yield os.path.relpath(path, root), path


def check(root):
    errors = []
    for rel, path in sources(root, FILE_DIRS):
        with open(path, encoding="utf-8") as f:
            count = sum(1 for _ in f)
        if count > MAX_FILE:
            errors.append(f"{rel}: {count} lines, more than {MAX_FILE}")
    for rel, path in sources(root, FUNCTION_DIRS):
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
        for name, first, count in functions(lines):
            if count > MAX_FUNCTION:
                errors.append(f"{rel}:{first}: {name} is {count} lines, more than {MAX_FUNCTION}")
    return errors


def self_test():
    """A long function, a long file and a short function: exactly the two long ones."""
    long_body = "\n".join(["    x++;"] * MAX_FUNCTION)
    files = {
        "lib/core/long.c": "static int longest(int x)\n{\n" + long_body + "\n}\n",
        "shaders/short.comp": "void main()\n{\n}\n",
        "lib/core/big.h": "\n" * (MAX_FILE + 1),
    }
    want = [
        f"lib/core/big.h: {MAX_FILE + 1} lines, more than {MAX_FILE}",
        f"lib/core/long.c:1: longest is {MAX_FUNCTION + 3} lines, more than {MAX_FUNCTION}",
    ]
    return house.self_test("sizes", check, files, want)


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    return house.main("sizes", check, root, lambda _: (
        f"sizes: no file of {', '.join(FILE_DIRS)} over {MAX_FILE} lines, no function over "
        f"{MAX_FUNCTION}"), self_test)


if __name__ == "__main__":
    sys.exit(main())
