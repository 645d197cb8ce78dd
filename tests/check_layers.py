#!/usr/bin/env python3
"""The library's layer rule, read from its #include lines.

lib/ is in folders by layer (docs/architecture.md). A file may include from its own folder and
from folders below it, never from one above; and no two modules include each other, directly
or around a circle, where a module is a .c file with its .h (x.c and x.h are one node). The
public headers (lib/include) sit below everything; "shared/..." and shader_list.h are the
shaders' declarations shared with C, also below everything. Every folder of lib/ is a layer or
lib/include, and a layer is one flat folder: a folder of lib/ that is not a layer, or a folder
inside a layer that holds sources, would escape the rule, so each is a break.

Usage: check_layers.py [LIB_DIR]. Exit 0 when the rule holds; 1 with one line per break.
check_layers.py --self-test first checks that a small tree with an upward include, a circle,
a stray file, a folder that is not a layer and a folder inside a layer is refused with exactly
those breaks, then checks LIB_DIR."""
import os
import re
import sys

import house

LAYERS = ["core", "scene", "topology", "plan", "contact", "features", "solvers", "sim", "render"]
BELOW_ALL = ("include/", "shared/", "shader_list.h")
# The library's sources: C, and one C++ file (topology/assimp_import.cpp).
SOURCE_SUFFIXES = (".c", ".h", ".cpp")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def modules(lib):
    """{module: [(line, included path)]} for every source under the layer folders."""
    found = {}
    for layer in LAYERS:
        folder = os.path.join(lib, layer)
        if not os.path.isdir(folder):
            continue
        for name in sorted(os.listdir(folder)):
            if not name.endswith(SOURCE_SUFFIXES):
                continue
            path = os.path.join(folder, name)
            text = open(path, encoding="utf-8").read()
            node = layer + "/" + os.path.splitext(name)[0]
            for m in INCLUDE.finditer(text):
                line = text.count("\n", 0, m.start()) + 1
                found.setdefault(node, []).append((f"{layer}/{name}:{line}", m.group(1)))
            found.setdefault(node, [])
    return found


def folders(lib):
    """One line for each folder the rule would not read: a folder of lib/ that is neither a
    layer nor include/, and a folder inside a layer that holds sources."""
    errors = []
    for name in sorted(os.listdir(lib)):
        if os.path.isdir(os.path.join(lib, name)) and name not in LAYERS + ["include"]:
            errors.append(f"lib/{name}/: a folder that is not a layer (docs/architecture.md "
                          "names the layers); the layer rule does not read it")
    for layer in LAYERS:
        top = os.path.join(lib, layer)
        for folder, subs, names in os.walk(top):
            subs.sort()
            if folder != top and any(n.endswith(SOURCE_SUFFIXES) for n in names):
                rel = os.path.relpath(folder, lib).replace(os.sep, "/")
                errors.append(f"lib/{rel}/: a folder inside the layer {layer}/; the layer rule "
                              "does not read it (a layer is one flat folder)")
    return errors


def check(lib):
    errors = folders(lib)
    mods = modules(lib)
    stray = [n for n in os.listdir(lib) if n.endswith(SOURCE_SUFFIXES)]
    for n in stray:
        errors.append(f"lib/{n}: a source outside the layer folders")
    edges = {m: set() for m in mods}
    for node, incs in mods.items():
        rank = LAYERS.index(node.split("/")[0])
        for where, inc in incs:
            if inc.startswith(BELOW_ALL) or "/" not in inc and inc in ("clothvk.h", "shader_list.h"):
                continue
            top = inc.split("/")[0]
            if top not in LAYERS:
                errors.append(f"lib/{where}: includes \"{inc}\", which names no layer folder")
                continue
            if LAYERS.index(top) > rank:
                errors.append(f"lib/{where}: {node.split('/')[0]}/ includes \"{inc}\" from "
                              f"{top}/, a layer above it")
            target = inc[:-2]
            if not os.path.isfile(os.path.join(lib, inc)):
                errors.append(f"lib/{where}: includes \"{inc}\", which does not exist")
            elif target != node:
                edges[node].add(target)
    # Circles: depth-first search, reporting each circle once by its smallest node.
    seen_cycles = set()
    state = {}

    def visit(node, stack):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(edges[node]):
            if state.get(nxt) == 1:
                cycle = stack[stack.index(nxt):]
                key = frozenset(cycle)
                if key not in seen_cycles:
                    seen_cycles.add(key)
                    errors.append("include circle: " + " -> ".join(cycle + [nxt]))
            elif nxt not in state:
                visit(nxt, stack)
        stack.pop()
        state[node] = 2

    for node in sorted(edges):
        if node not in state:
            visit(node, [])
    return errors


def self_test():
    """The check refuses what it must: an upward include, a circle within a folder, a circle
    across folders through a header, a missing header, a file outside the folders, a folder
    that is not a layer and a folder inside a layer (include/ and a subfolder holding no
    source pass)."""
    files = {
        "core/a.h": '#include "core/b.h"\n',
        "core/b.h": '#include "core/a.h"\n',            # circle a <-> b
        "core/c.c": '#include "scene/d.h"\n',           # upward: core -> scene
        "scene/d.h": '#include "clothvk.h"\n#include "shared/layout.h"\n',
        "core/c.h": "",
        "scene/d.c": '#include "scene/d.h"\n#include "core/c.h"\n#include "core/zz.h"\n',
        "stray.c": "",
        "include/clothvk/base.h": "",
        "extra/e.c": '#include "core/c.h"\n',           # a folder that is not a layer
        "scene/deep/f.h": '#include "core/b.h"\n',      # a folder inside a layer
        "scene/notes/readme.txt": "",                   # holds no source: passes
    }
    want = [
        "lib/stray.c: a source outside the layer folders",
        "lib/extra/: a folder that is not a layer (docs/architecture.md names the layers); the "
        "layer rule does not read it",
        "lib/scene/deep/: a folder inside the layer scene/; the layer rule does not read it "
        "(a layer is one flat folder)",
        'lib/core/c.c:1: core/ includes "scene/d.h" from scene/, a layer above it',
        'lib/scene/d.c:3: includes "core/zz.h", which does not exist',
        "include circle: core/a -> core/b -> core/a",
        "include circle: core/c -> scene/d -> core/c",
    ]
    return house.self_test("layers", check, files, want)


def main():
    lib = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lib")
    return house.main("layers", check, lib, lambda root: (
        f"layers: {len(modules(root))} modules in {len(LAYERS)} layers, no upward include, "
        "no circle"), self_test)


if __name__ == "__main__":
    sys.exit(main())
