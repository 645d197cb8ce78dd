#!/usr/bin/env bash
# rbgs fused against unfused on this device, three scenes, both lavapipe threadings:
# `clothvk-bench fused SCENE --frames FRAMES --repeat 3` each, min-max of the rounds' wall ms per
# frame gathered into one CSV (docs/figures/fused/lavapipe.csv).
# Usage: bash scripts/fused-lavapipe.sh BUILD_DIR OUT.csv [FRAMES]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: fused-lavapipe.sh BUILD_DIR OUT.csv [FRAMES]}
out=${2:?usage: fused-lavapipe.sh BUILD_DIR OUT.csv [FRAMES]}
frames=${3:-20}
bench="$build/apps/clothvk-bench"
[ -x "$bench" ] || { echo "fused-lavapipe.sh: no $bench (build first)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo 'scene,threading,"dispatches per frame, unfused","dispatches per frame, fused","wall ms per frame, unfused min","wall ms per frame, unfused max","wall ms per frame, fused min","wall ms per frame, fused max",same bits' >"$work/all.csv"
run() { # label, threading, then the scene and its --set arguments
    local label=$1 threading=$2
    shift 2
    local dir="$work/$(echo "$label$threading" | tr -c 'a-z0-9' _)"
    if [ "$threading" = LP_NUM_THREADS=0 ]; then
        LP_NUM_THREADS=0 "$bench" fused "$@" --frames "$frames" --repeat 3 --no-plot -o "$dir" >/dev/null
    else
        env -u LP_NUM_THREADS "$bench" fused "$@" --frames "$frames" --repeat 3 --no-plot -o "$dir" >/dev/null
    fi
    python3 - "$label" "$threading" "$dir/fused.csv" >>"$work/all.csv" <<'PY'
import csv, sys
label, threading, path = sys.argv[1:4]
rows = list(csv.DictReader(open(path)))
def side(fuse):
    r = [x for x in rows if x["fuse"] == fuse]
    ms = [float(x["wall_ms_per_frame"]) for x in r]
    return r[0]["dispatches_per_frame"], min(ms), max(ms)
def fmt(v):
    return f"{v:.3g}" if v >= 100 else f"{v:.3g}" if v < 10 else f"{v:.1f}"
off, on = side("off"), side("on")
same = "yes" if all(x["same_bits"] == "1" for x in rows) else "no"
w = csv.writer(sys.stdout, lineterminator="\n")
w.writerow([label, threading, off[0], on[0], fmt(off[1]), fmt(off[2]), fmt(on[1]), fmt(on[2]), same])
PY
}
both() { run "$1" LP_NUM_THREADS=0 "${@:2}"; run "$1" "default threading" "${@:2}"; }
both "peer-hanging.json (10,000 particles, tethers)" assets/scenes/peer-hanging.json
both "drape.json (2,304 particles, self-contact, 2 colliders)" assets/scenes/drape.json
both "hanging.json at 32 x 32" assets/scenes/hanging.json \
    --set 'cloths.0.grid=[32,32]' --set 'cloths.0.pins=[[0,0],[31,0]]'
mv "$work/all.csv" "$out"
echo "wrote $out"
