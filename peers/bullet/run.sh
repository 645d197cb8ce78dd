#!/usr/bin/env bash
# clothvk against Bullet 3.24's soft body on the standard hanging cloth
# (assets/scenes/peer-hanging.json), alternately, ROUNDS times, both on one CPU thread: clothvk
# at its recommended settings on lavapipe with LP_NUM_THREADS=0, Bullet with 256 position
# iterations (peers/bullet/hanging.cpp). Prints one line a run and, at the end, Bullet's median
# ms per frame over clothvk's; appends every run to peers/bullet/results/hanging-DATE.csv.
# Usage: bash peers/bullet/run.sh [ROUNDS]   (needs a build: bash scripts/build.sh; Bullet from
# libbullet-dev, which scripts/setup.sh installs)
set -euo pipefail
cd "$(dirname "$0")/../.."
rounds=${1:-3}
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: ROUNDS must be a positive integer, got '$rounds'" >&2; exit 2; }
sim=build/apps/clothvk-sim
bullet=build/peers/bullet/bullet-hanging
scene=assets/scenes/peer-hanging.json
[ -x "$sim" ] || { echo "run.sh: build first (bash scripts/build.sh)" >&2; exit 2; }
if [ ! -x "$bullet" ]; then
    # meson builds it when it finds bullet and a C++ compiler; otherwise build it here.
    pkg-config --exists bullet || { echo "run.sh: Bullet not found (apt-get install libbullet-dev)" >&2; exit 2; }
    bullet=$(mktemp -d)/bullet-hanging
    # shellcheck disable=SC2046 # pkg-config's flags are separate words
    c++ -O2 -std=c++17 -o "$bullet" peers/bullet/hanging.cpp $(pkg-config --cflags --libs bullet)
fi
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -n1)
csv=peers/bullet/results/hanging-$(date -u +%F).csv
[ -s "$csv" ] || echo "utc,cpu,engine,round,settings,ms_per_frame,wall_ms_per_frame,residual,max_stretch,p99_stretch" >"$csv"
out=$(mktemp)
trap 'rm -f "$out"' EXIT
echo "cpu: $cpu"
printf '%-8s %5s %14s %14s %10s %8s %8s\n' engine round "ms per frame" "wall ms/frame" residual max p99
for ((r = 1; r <= rounds; r++)); do
    now=$(date -u +%FT%TZ)
    LP_NUM_THREADS=0 "$sim" "$scene" --json >"$out"
    python3 - "$out" "$now" "$cpu" "$r" "$csv" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
now, cpu, r, csv = sys.argv[2:6]
row = ["clothvk", r, "recommended (20 substeps x 1 x 5 rbgs omega 1.55 tethers; lavapipe LP_NUM_THREADS=0; ms = GPU timestamps)",
       d["gpu_ms_per_frame"], d["wall_ms_per_frame"], d["residual"], d["max_stretch"], d["p99_stretch"]]
print(f"{'clothvk':<8} {r:>5} {d['gpu_ms_per_frame']:14.2f} {d['wall_ms_per_frame']:14.2f} {d['residual']:10.3g} {100*d['max_stretch']:7.2f}% {100*d['p99_stretch']:7.2f}%")
with open(csv, "a") as f:
    f.write(",".join([now, '"' + cpu + '"'] + [f'"{x}"' if isinstance(x, str) and "," in x else str(x) for x in row]) + "\n")
PY
    now=$(date -u +%FT%TZ)
    "$bullet" >"$out"
    python3 - "$out" "$now" "$cpu" "$r" "$csv" <<'PY'
import sys
line = open(sys.argv[1]).read().split()
now, cpu, r, csv = sys.argv[2:6]
d = dict(kv.split("=", 1) for kv in line[1:])
if d["finite"] != "yes":
    sys.exit("run.sh: Bullet's cloth has a non-finite position at the last frame")
ms = float(d["ms_per_frame_mean"])
print(f"{'bullet':<8} {r:>5} {ms:14.2f} {ms:14.2f} {float(d['residual']):10.3g} {100*float(d['max_stretch']):7.2f}% {100*float(d['p99_stretch']):7.2f}%")
settings = f"btSoftBody kLST 1 piterations {d['iterations']} substeps {d['substeps']}; one thread; ms = wall clock"
with open(csv, "a") as f:
    f.write(",".join([now, '"' + cpu + '"', "bullet", r, settings, str(ms), str(ms), d["residual"], d["max_stretch"], d["p99_stretch"]]) + "\n")
PY
done
python3 - "$csv" "$rounds" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))[-2 * int(sys.argv[2]):]
med = lambda eng, key: statistics.median(float(r[key]) for r in rows if r["engine"] == eng)
b = med("bullet", "ms_per_frame")
print(f"Bullet / clothvk, median ms per frame over {sys.argv[2]} rounds: "
      f"{b / med('clothvk', 'ms_per_frame'):.2f} x (clothvk GPU time), "
      f"{b / med('clothvk', 'wall_ms_per_frame'):.2f} x (clothvk wall time)")
print(f"appended to {sys.argv[1]}")
PY
