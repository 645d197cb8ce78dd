"""The structs the package declares to cffi (ABI mode: nothing checks them at build time) have
the sizes, field offsets and field sizes the C compiler gives them from lib/include/clothvk.h
(offsets alone miss a uint32_t declared as uint64_t where padding follows). A C program
generated from the declarations is compiled with the system compiler ($CC, else cc: gcc is a
build dependency) and prints them all."""

import os
import shutil
import subprocess

import pytest

from clothvk._ffi import STRUCTS, ffi
from conftest import ROOT


def c_program():
    lines = ["#include <stddef.h>", "#include <stdio.h>", '#include "clothvk.h"',
             "int main(void)", "{"]
    for s in STRUCTS:
        lines.append(f'    printf("{s} %zu\\n", sizeof({s}));')
        for field, _ in ffi.typeof(s).fields:
            lines.append(f'    printf("{s}.{field} %zu\\n", offsetof({s}, {field}));')
            lines.append(f'    printf("sizeof:{s}.{field} %zu\\n", sizeof((({s}*)0)->{field}));')
    lines += ["    return 0;", "}"]
    return "\n".join(lines) + "\n"


def python_layout():
    layout = {}
    for s in STRUCTS:
        layout[s] = ffi.sizeof(s)
        for field, ftype in ffi.typeof(s).fields:
            layout[f"{s}.{field}"] = ffi.offsetof(s, field)
            layout[f"sizeof:{s}.{field}"] = ffi.sizeof(ftype.type)
    return layout


def test_struct_layouts_match_c(tmp_path):
    cc = os.environ.get("CC", "cc")
    if not shutil.which(cc):
        pytest.fail(f"no C compiler ({cc}) to check the struct layouts with")
    source = tmp_path / "layout.c"
    source.write_text(c_program())
    exe = tmp_path / "layout"
    subprocess.run([cc, "-std=c11", "-I", str(ROOT / "lib" / "include"), str(source),
                    "-o", str(exe)], check=True)
    out = subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout
    c_layout = {k: int(v) for k, v in (line.split() for line in out.splitlines())}
    py_layout = python_layout()
    assert c_layout.keys() == py_layout.keys()
    wrong = [f"{k}: C {c_layout[k]}, cffi {py_layout[k]}" for k in c_layout
             if c_layout[k] != py_layout[k]]
    assert not wrong, "layouts differ: " + "; ".join(wrong)
    assert len(c_layout) > 200, f"only {len(c_layout)} sizes and offsets compared"
