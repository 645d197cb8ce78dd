#!/usr/bin/env python3
"""shaders/no_contraction.py (the build's -Dfloat_exact=true): for shaders of the tree, the
header it writes holds the module glslang made plus one NoContraction decoration for every float
arithmetic result that had none, in the annotations, and spirv-val accepts it; a file that is not
SPIR-V is refused with its reason and no header.

    test_no_contraction.py GLSLANG SPIRV_VAL SHADERS_DIR"""
import os
import re
import struct
import subprocess
import sys
import tempfile

GLSLANG, SPIRV_VAL, SHADERS = sys.argv[1:4]
sys.path.insert(0, SHADERS)
import no_contraction  # noqa: E402

failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what)
    failures += 0 if ok else 1


def words_of(path):
    data = open(path, "rb").read()
    return list(struct.unpack(f"<{len(data) // 4}I", data))


def instructions(words):
    at = 5
    while at < len(words):
        count = words[at] >> 16
        yield words[at] & 0xffff, words[at:at + count]
        at += count


with tempfile.TemporaryDirectory() as tmp:
    for shader in ("solvers/pd_fused.comp", "solvers/pd_contact.comp", "render/lit_cloth.frag"):
        name = os.path.basename(shader).replace(".", "_")
        spv, header = os.path.join(tmp, name + ".spv"), os.path.join(tmp, name + ".h")
        subprocess.run([GLSLANG, "--quiet", "-V", "--target-env", "vulkan1.0", "-I" + SHADERS,
                        "-o", spv, os.path.join(SHADERS, shader)], check=True)
        before = words_of(spv)
        subprocess.run([sys.executable, os.path.join(SHADERS, "no_contraction.py"), spv, header,
                        "cvk_spv_" + name], check=True)
        text = open(header).read()
        check(text.startswith("#pragma once\nconst uint32_t cvk_spv_" + name + "[] = {"),
              f"{shader}: the header names its array")
        after = [int(w, 16) for w in re.findall(r"0x[0-9a-f]{8}", text)]
        patched = os.path.join(tmp, name + ".patched.spv")
        open(patched, "wb").write(struct.pack(f"<{len(after)}I", *after))
        val = subprocess.run([SPIRV_VAL, "--target-env", "vulkan1.0", patched],
                             capture_output=True, text=True)
        check(val.returncode == 0, f"{shader}: spirv-val accepts it {val.stderr.strip()}")
        floats = [i[2] for op, i in instructions(before) if op in no_contraction.FLOAT_OPS]
        had = {i[1] for op, i in instructions(before) if op == 71 and i[2] == 42}
        marked = [i[1] for op, i in instructions(after) if op == 71 and i[2] == 42]
        check(len(floats) > 100, f"{shader}: {len(floats)} float results")
        check(sorted(marked) == sorted(had | set(floats)),
              f"{shader}: each float result marked once ({len(marked)} marks, {len(had)} before)")
        added = [i for op, i in instructions(after) if op == 71 and i[2] == 42 and i[1] not in had]
        rest = [w for op, i in instructions(after) if not (op == 71 and i[2] == 42 and
                                                           i[1] not in had) for w in i]
        check(rest == before[5:] and after[:5] == before[:5],
              f"{shader}: the module otherwise unchanged ({len(added)} decorations added)")
        first_type = next(k for k, (op, _) in enumerate(instructions(after))
                          if op not in no_contraction.PREAMBLE)
        last_mark = max(k for k, (op, i) in enumerate(instructions(after))
                        if op == 71 and i[2] == 42)
        check(last_mark < first_type, f"{shader}: the decorations among the annotations")

    bad, header = os.path.join(tmp, "bad.spv"), os.path.join(tmp, "bad.h")
    open(bad, "wb").write(b"\0" * 40)
    r = subprocess.run([sys.executable, os.path.join(SHADERS, "no_contraction.py"), bad, header,
                        "x"], capture_output=True, text=True)
    check(r.returncode == 1 and r.stderr == f"{bad}: not a SPIR-V module (no magic number)\n" and
          not os.path.exists(header), f"a file that is not SPIR-V: refused, no header {r.stderr!r}")

print(f"{failures} failed" if failures else "all passed")
sys.exit(1 if failures else 0)
