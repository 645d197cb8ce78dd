#!/usr/bin/env bash
# The standard hanging cloth the peers were measured on (assets/scenes/peer-hanging.json: 100 x
# 100 particles on a 1 m square, 0.1 kg, pinned at two corners, structural 1e6 N/m, 120 frames
# of 1/60 s), with its recommended settings (20 substeps of one outer iteration of 5 rbgs
# sweeps, omega 1.55, tethers) and with seed 002's (8 substeps of 1/480 s, rbgs 4 x 4, omega 1,
# no tethers), alternately, on one core of lavapipe (LP_NUM_THREADS=0): residual,
# largest and 99th-percentile stretch over the structural springs at frame 120, and GPU
# milliseconds per frame. docs/performance.md ("Accuracy against peers") quotes a run of it.
# Usage: bash scripts/peer-hanging.sh [ROUNDS]   (needs a build: bash scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-2}
sim=build/apps/clothvk-sim
scene=assets/scenes/peer-hanging.json
[ -x "$sim" ] || { echo "peer-hanging.sh: build first (bash scripts/build.sh)" >&2; exit 2; }
out=$(mktemp)
trap 'rm -f "$out"' EXIT
printf '%-44s %10s %9s %9s %12s\n' setting residual max p99 "GPU ms/frame"
for ((r = 0; r < rounds; r++)); do
    for setting in recommended seed-002; do
        args=()
        [ "$setting" = seed-002 ] && args=(--set substeps=8 --set dt=0.00208333333
            --set solver.outer_iterations=4 --set solver.inner_iterations=4
            --set solver.omega=1 --set cloths.0.tethers=0)
        LP_NUM_THREADS=0 "$sim" "$scene" --json "${args[@]}" >"$out"
        python3 - "$setting" "$out" <<'PY'
import json, sys
d = json.load(open(sys.argv[2]))
name = sys.argv[1] + (" (20 x 1x5 rbgs, omega 1.55, tethers)" if sys.argv[1] == "recommended" else " (4x4 rbgs, omega 1)")
print(f"{name:<44} {d['residual']:10.3g} {100 * d['max_stretch']:8.2f}% {100 * d['p99_stretch']:8.2f}% {d['gpu_ms_per_frame']:12.1f}")
PY
    done
done
