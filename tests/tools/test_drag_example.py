#!/usr/bin/env python3
"""The picking and dragging example (examples/drag.c) runs clean under the validation layer: its
click picks the particle it aimed at (the middle of the bottom edge of the 32x32 sheet, index
31 * 32 + 16), its first frames of the drag (10 to 13 of 14; the whole pull takes 80) step
without an error, and it writes one PNG per frame. How far a grab moves a particle is checked
by tests/features/test_pick.c."""
import os
import re
import subprocess
import sys
import tempfile

EXAMPLE = os.path.abspath(sys.argv[1])
env = dict(os.environ, CLOTHVK_VALIDATION="1")
with tempfile.TemporaryDirectory(prefix="clothvk-drag-") as workdir:
    p = subprocess.run([EXAMPLE, workdir, "14"], env=env, capture_output=True, text=True,
                       timeout=240)
    if p.returncode != 0 or p.stderr:
        print(f"FAILED: the example exited {p.returncode}:\n{p.stderr}")
        sys.exit(1)
    m = re.search(r"cloth (\d+) particle (\d+)", p.stdout)
    if not m or (int(m.group(1)), int(m.group(2))) != (0, 31 * 32 + 16):
        print(f"FAILED: the click did not pick particle {31 * 32 + 16} of cloth 0:\n{p.stdout}")
        sys.exit(1)
    pngs = sorted(f for f in os.listdir(workdir) if f.endswith(".png"))
    if pngs != [f"frame_{i:04d}.png" for i in range(14)]:
        print(f"FAILED: wrote {pngs}")
        sys.exit(1)
    with open(os.path.join(workdir, pngs[-1]), "rb") as f:
        if f.read(8) != b"\x89PNG\r\n\x1a\n":
            print("FAILED: the last frame is not a PNG")
            sys.exit(1)
    print(p.stdout.strip())
    print(f"drag example: {len(pngs)} PNGs, no validation message")
