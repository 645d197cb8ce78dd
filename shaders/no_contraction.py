#!/usr/bin/env python3
"""Marks every floating-point arithmetic result of a SPIR-V module NoContraction (GLSL's
`precise` on every expression) and writes the module as the C header glslang's --vn writes:

    no_contraction.py IN.spv OUT.h ARRAY_NAME

A driver may otherwise fuse a multiply and an add into one rounding, and where it does so
differs between two shaders that share a function (contact/*.glsl in pd_contact.comp and in
pd_fused.comp), the two round alike no more. Used by the build with -Dfloat_exact=true
(meson_options.txt)."""
import struct
import sys

MAGIC = 0x07230203
OP_DECORATE = 71
NO_CONTRACTION = 42
# Result-producing float arithmetic: OpFNegate, OpFAdd, OpFSub, OpFMul, OpFDiv, OpFRem, OpFMod,
# OpVectorTimesScalar, OpMatrixTimesScalar, OpVectorTimesMatrix, OpMatrixTimesVector,
# OpMatrixTimesMatrix, OpOuterProduct, OpDot: [result type, result id, operands...].
FLOAT_OPS = {127, 129, 131, 133, 136, 137, 141, 142, 143, 144, 145, 146, 147, 148}
# What comes before the types in a module's logical layout: capabilities, extensions, imports,
# the memory model, entry points, execution modes, debug instructions and annotations.
PREAMBLE = {17, 10, 11, 14, 15, 16, 331, 7, 3, 2, 4, 5, 6, 330, 8, 317,
            71, 72, 73, 74, 75, 332, 5632, 5633}


def patch(words):
    if len(words) < 5 or words[0] != MAGIC:
        raise ValueError("not a SPIR-V module (no magic number)")
    marked, results, at, insert = set(), [], 5, None
    while at < len(words):
        count, op = words[at] >> 16, words[at] & 0xffff
        if count == 0 or at + count > len(words):
            raise ValueError(f"an instruction at word {at} runs past the module")
        if insert is None and op not in PREAMBLE:
            insert = at
        if op == OP_DECORATE and words[at + 2] == NO_CONTRACTION:
            marked.add(words[at + 1])
        if op in FLOAT_OPS:
            results.append(words[at + 2])
        at += count
    if insert is None:
        insert = len(words)
    extra = []
    for r in results:
        if r not in marked:
            extra += [(3 << 16) | OP_DECORATE, r, NO_CONTRACTION]
            marked.add(r)
    return words[:insert] + extra + words[insert:], len(extra) // 3


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: no_contraction.py IN.spv OUT.h ARRAY_NAME")
    data = open(sys.argv[1], "rb").read()
    if len(data) % 4:
        sys.exit(f"{sys.argv[1]}: not a whole number of words")
    try:
        words, _ = patch(list(struct.unpack(f"<{len(data) // 4}I", data)))
    except ValueError as e:
        sys.exit(f"{sys.argv[1]}: {e}")
    lines = []
    for i in range(0, len(words), 8):
        lines.append("\t" + ",".join(f"0x{w:08x}" for w in words[i:i + 8]))
    with open(sys.argv[2], "w") as f:
        f.write(f"#pragma once\nconst uint32_t {sys.argv[3]}[] = {{\n" + ",\n".join(lines) +
                "\n};\n")


if __name__ == "__main__":
    main()
