#!/usr/bin/env bash
# Dispatches per frame of every rbgs scene of assets/scenes, unfused and fused (solver.fuse off, on),
# and whether both runs end on the same bits: `clothvk-bench fused` on each scene, one round of
# FRAMES frames (default 20), its rows gathered into one CSV (docs/figures/fused/dispatches.csv).
# The wall times are lavapipe's, where a fused pass runs on one thread (performance.md).
# Usage: bash scripts/fused-dispatches.sh BUILD_DIR OUT.csv [FRAMES]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: fused-dispatches.sh BUILD_DIR OUT.csv [FRAMES]}
out=${2:?usage: fused-dispatches.sh BUILD_DIR OUT.csv [FRAMES]}
frames=${3:-20}
bench="$build/apps/clothvk-bench"
[ -x "$bench" ] || { echo "fused-dispatches.sh: no $bench (build first)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scenes=$(cd assets/scenes && ls *.json | sed 's/\.json$//')
echo "scene,particles,substeps a frame,frames,dispatches per frame unfused,dispatches per frame fused,wall ms per frame unfused,wall ms per frame fused,same bits" >"$work/all.csv"
for scene in $scenes; do
    file="assets/scenes/$scene.json"
    info=$(LP_NUM_THREADS=0 "$build/apps/clothvk-sim" "$file" --frames 0 --json |
           python3 -c 'import json, sys; d = json.load(sys.stdin); s = d["solver"]
print(d["particles"], d["substeps"], s["method"] + "/" + s.get("linear", "-"))')
    # only rbgs fuses (its scenes: the others take another solver)
    [ "${info##* }" = pd/rbgs ] || continue
    LP_NUM_THREADS=0 "$bench" fused "$file" --frames "$frames" --repeat 1 --warmup 0 --no-plot \
        -o "$work/$scene" >/dev/null
    python3 - "$scene" "$info" "$work/$scene/fused.csv" >>"$work/all.csv" <<'PY'
import csv, sys
scene, info, path = sys.argv[1], sys.argv[2].split(), sys.argv[3]
rows = {r["fuse"]: r for r in csv.DictReader(open(path))}
# fused in global memory: the library's choice on a CPU device (cvk_sim_desc.fused_shared_memory)
off, on = rows["off"], rows["global"]
print(f'{scene}.json,{info[0]},{info[1]},{off["frames"]},{off["dispatches_per_frame"]},'
      f'{on["dispatches_per_frame"]},{float(off["wall_ms_per_frame"]):.1f},'
      f'{float(on["wall_ms_per_frame"]):.1f},{"yes" if on["same_bits"] == "1" else "no"}')
PY
done
mv "$work/all.csv" "$out"
echo "wrote $out"
