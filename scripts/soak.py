#!/usr/bin/env python3
"""Soak: one scene stepped for many frames in one process, through the Python package, with
the process's resident memory (from /proc/self/statm), the device memory the context holds
(cvk_context_info.device_bytes) and the simulation's statistics sampled as it goes. Memory must
be flat after warm-up and the final state finite; the script says whether it was and exits 1
when not.

    PYTHONPATH=python python3 scripts/soak.py assets/scenes/drape.json --frames 100000 \
        --every 1000 --set cloths.0.grid=[24,24] --csv docs/figures/soak/soak.csv

CSV columns: frame, seconds (wall), rss_mb, device_mb, max_stretch, kinetic_energy_j, nan_count.
"Flat" means: the largest resident set after the first tenth of the run is within 2 MB (plus
1 %) of the one at the end of that tenth, and device memory never changes after creation.
"""
import argparse
import csv
import json
import os
import sys
import time

import numpy as np

import clothvk


def rss_mb():
    with open("/proc/self/statm") as f:
        pages = int(f.read().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE") / 1e6


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--frames", type=int, default=100000)
    ap.add_argument("--every", type=int, default=1000, help="frames between samples")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="scene override, as clothvk-sim --set")
    ap.add_argument("--csv", help="where to write the samples")
    args = ap.parse_args()
    overrides = {}
    for item in args.set:
        key, _, value = item.partition("=")
        overrides[key] = json.loads(value)

    rows = []
    start = time.monotonic()
    with clothvk.Context() as ctx:
        scene = clothvk.Scene.load(args.scene, overrides=overrides)
        sim = clothvk.Simulation(ctx, scene)
        done = 0
        while True:
            st = sim.stats()
            info = ctx.info()
            rows.append([done, round(time.monotonic() - start, 2), round(rss_mb(), 2),
                         round(info["device_bytes"] / 1e6, 3), st["max_stretch"],
                         st.get("kinetic_energy", float("nan")), st["nan_count"]])
            print(",".join(str(v) for v in rows[-1]), flush=True)
            if done >= args.frames:
                break
            n = min(args.every, args.frames - done)
            try:
                sim.step(n)
            except clothvk.Error as e:
                print(f"soak: stopped at frame {done}: {e}", file=sys.stderr)
                return 1
            done += n
        final = sim.positions()
        finite = bool(np.isfinite(final).all())

    header = ["frame", "seconds", "rss_mb", "device_mb", "max_stretch", "kinetic_energy_j",
              "nan_count"]
    if args.csv:
        os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(header)
            w.writerows(rows)
    warm = max(1, len(rows) // 10)
    base = rows[warm][2]
    peak = max(r[2] for r in rows[warm:])
    devices = {r[3] for r in rows}
    flat = peak <= base + 2 + 0.01 * base and len(devices) == 1
    print(f"soak: {args.frames} frames in {time.monotonic() - start:.0f} s; resident memory "
          f"{rows[0][2]:.1f} MB at the start, {base:.1f} MB after warm-up (frame {rows[warm][0]}), "
          f"at most {peak:.1f} MB after it, {rows[-1][2]:.1f} MB at the end; device memory "
          f"{', '.join(f'{d:.3f}' for d in sorted(devices))} MB; final state "
          f"{'finite' if finite else 'NOT finite'}; memory {'flat' if flat else 'NOT flat'}")
    return 0 if flat and finite else 1


if __name__ == "__main__":
    sys.exit(main())
