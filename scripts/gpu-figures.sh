#!/usr/bin/env bash
# The figures a GPU gives that lavapipe cannot, in one run of a few minutes, with the tools that
# scripts/pack-tools.sh packed (run from the source tree's root, for the scenes):
#
#   bash scripts/gpu-figures.sh PACK OUT
#
# Each step writes its output under OUT and a line to OUT/log; a step that fails or runs past
# its time is logged and the next one runs. At the end OUT.tar.gz holds the whole folder. In order of what is missing most:
#   1. the 25-layer pile of 250,000 particles (assets/scenes/contact-pile-large.json): ms, dispatches
#      and passes per frame over 120 frames, intersecting pairs at its last frame; then the
#      pairs after every frame (contact-ensemble, one variant);
#   2. the contact scenes (the 40 x 40 drape, the six-cloth pile, the twist): the same --json;
#   3. test_determinism's contact part (the same bits for every dispatch shape, fused and not);
#   4. clothvk-bench fused on peer-hanging.json and drape.json, and batch of 32 x 32 napkins
#      up to 4,096 copies.
# CLOTHVK_QUICK=1 runs every step for two frames (a check of the script, on any device).
set -uo pipefail
cd "$(dirname "$0")/.."
[ $# -eq 2 ] || { echo "usage: $0 PACK OUT" >&2; exit 2; }
pack=$(cd "$1" && pwd)
out=$2
mkdir -p "$out"
out=$(cd "$out" && pwd)
export LD_LIBRARY_PATH="$pack/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
sim=$pack/bin/clothvk-sim
bench=$pack/bin/clothvk-bench
quick=${CLOTHVK_QUICK:-0}
frames() { if [ "$quick" = 1 ]; then echo 2; else echo "$1"; fi; }
log=$out/log
: >"$log"

step() { # step NAME SECONDS COMMAND...: runs it with its output in OUT/NAME.out
    local name=$1 limit=$2
    shift 2
    local t0=$SECONDS
    timeout "$limit" "$@" >"$out/$name.out" 2>"$out/$name.err"
    local rc=$?
    echo "$name: exit $rc after $((SECONDS - t0)) s" | tee -a "$log"
}

"$sim" --version | tee -a "$log"
step device 60 "$sim" assets/scenes/contact-drape.json --frames 1 --json
grep -m1 '"device"' "$out/device.out" | tee -a "$log"

step pile-large 240 "$sim" assets/scenes/contact-pile-large.json --frames "$(frames 120)" --json
step pile-large-ensemble 300 "$bench" contact-ensemble --scenes assets/scenes/contact-pile-large.json \
    --variants 1 --frames "$(frames 120)" --no-plot -o "$out/pile-large-ensemble"
for scene in contact-drape contact-pile contact-twist; do
    step "$scene" 120 "$sim" "assets/scenes/$scene.json" --frames "$(frames 240)" --json
done
if [ "$quick" = 1 ]; then
    echo "determinism: not run for a quick check" | tee -a "$log"
else
    step determinism 300 "$pack/bin/test_determinism" contact
fi
step fused-peer 120 "$bench" fused assets/scenes/peer-hanging.json --frames "$(frames 30)" \
    --no-plot -o "$out/fused-peer"
step fused-drape 120 "$bench" fused assets/scenes/drape.json --frames "$(frames 30)" \
    --no-plot -o "$out/fused-drape"
counts=1,16,256,1024,4096
[ "$quick" = 1 ] && counts=1,2
step batch 300 "$bench" batch --set 'cloths.0.grid=[32,32]' --counts "$counts" \
    --frames "$(frames 10)" --no-plot -o "$out/batch"
echo "gpu-figures: done; outputs in $out, and all of them in $out.tar.gz" | tee -a "$log"
tar czf "$out.tar.gz" -C "$out" .
