#!/usr/bin/env bash
# The figures a GPU gives that lavapipe cannot, in one run of a few minutes, with the tools that
# scripts/pack-tools.sh packed (run from the source tree's root, for the scenes):
#
#   bash scripts/gpu-figures.sh PACK OUT [SECONDS]
#
# Each step writes its output under OUT and a line to OUT/log; a step that fails or runs past
# its time is logged and the next one runs. SECONDS (default: none) is a deadline for the whole
# run: a step gets at most what is left of it, and is skipped when under 10 s are left. At the
# end OUT.tar.gz holds the whole folder. In order of what is missing most:
#   1. the 25-layer pile of 250,000 particles (assets/scenes/contact-pile-large.json): ms,
#      dispatches and passes per frame over 120 frames, intersecting pairs at its last frame;
#   2. the contact scenes (the 40 x 40 drape, the six-cloth pile, the twist): the same --json,
#      and scripts/contact_figures.py's rows with the drape at 20, 40, 80 and 160;
#   3. clothvk-bench fused (unfused, fused with the iterate in shared memory where it fits, fused
#      in global memory) on peer-hanging.json, drape.json and one 32 x 32 napkin, and batch of
#      32 x 32 napkins up to 4,096 copies, unfused and fused (a workgroup a copy);
#   4. test_determinism's contact part (the same bits for every dispatch shape, fused and not);
#   5. intersecting pairs after every frame: the large pile (contact-ensemble, one variant), then
#      every showcase's ensemble (a process a showcase, eight at a time).
# CLOTHVK_EXACT_LIB=DIR, a folder holding libclothvk.so.0 from a build with -Dfloat_exact=true
# (meson_options.txt), adds after step 4 test_determinism contact and clothvk-bench fused on
# drape.json with that library: whether fused and unfused round alike once no driver may fuse a
# multiply and an add (docs/limits.md, Solvers). To make one:
#   meson setup build-exact -Dfloat_exact=true && ninja -C build-exact &&
#   CLOTHVK_EXACT_BUILD_DIR=build-exact bash scripts/pack-tools.sh pack    (then pack/exact)
# CLOTHVK_QUICK=1 runs every step for two frames (a check of the script, on any device).
set -uo pipefail
cd "$(dirname "$0")/.."
[ $# -eq 2 ] || [ $# -eq 3 ] || { echo "usage: $0 PACK OUT [SECONDS]" >&2; exit 2; }
pack=$(cd "$1" && pwd)
out=$2
deadline=${3:-0}
mkdir -p "$out"
out=$(cd "$out" && pwd)
export LD_LIBRARY_PATH="$pack/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
[ -d "$pack/layer" ] && export VK_LAYER_PATH="$pack/layer${VK_LAYER_PATH:+:$VK_LAYER_PATH}"
sim=$pack/bin/clothvk-sim
bench=$pack/bin/clothvk-bench
quick=${CLOTHVK_QUICK:-0}
frames() { if [ "$quick" = 1 ]; then echo 2; else echo "$1"; fi; }
log=$out/log
: >"$log"

limit_for() { # limit_for SECONDS: SECONDS, or what is left before the deadline if that is less
    local limit=$1
    if [ "$deadline" -gt 0 ]; then
        local left=$((deadline - SECONDS))
        [ "$left" -lt "$limit" ] && limit=$left
    fi
    echo "$limit"
}

step() { # step NAME SECONDS COMMAND...: runs it with its output in OUT/NAME.out
    local name=$1 limit
    limit=$(limit_for "$2")
    shift 2
    if [ "$limit" -lt 10 ]; then
        echo "$name: skipped, the deadline is near" | tee -a "$log"
        return
    fi
    local t0=$SECONDS
    timeout "$limit" "$@" >"$out/$name.out" 2>"$out/$name.err"
    local rc=$?
    echo "$name: exit $rc after $((SECONDS - t0)) s (limit $limit s)" | tee -a "$log"
}

"$sim" --version | tee -a "$log"
step device 60 "$sim" assets/scenes/contact-drape.json --frames 1 --json
grep -m1 '"device"' "$out/device.out" | tee -a "$log"

step pile-large 150 "$sim" assets/scenes/contact-pile-large.json --frames "$(frames 120)" --json
for scene in contact-drape contact-pile contact-twist; do
    step "$scene" 60 "$sim" "assets/scenes/$scene.json" --frames "$(frames 240)" --json
done
# contact_figures.py runs BUILD/apps/clothvk-sim: a build folder of links to the pack.
mkdir -p "$out/build"
ln -sfn "$pack/bin" "$out/build/apps"
if [ "$quick" = 1 ]; then
    echo "contact-figures: not run for a quick check" | tee -a "$log"
else
    step contact-figures 150 python3 scripts/contact_figures.py "$out/build" \
        "$out/contact-figures.csv" --sizes 20,40,80,160
fi
step fused-peer 60 "$bench" fused assets/scenes/peer-hanging.json --frames "$(frames 30)" \
    --no-plot -o "$out/fused-peer"
step fused-drape 60 "$bench" fused assets/scenes/drape.json --frames "$(frames 30)" \
    --no-plot -o "$out/fused-drape"
step fused-napkin 60 "$bench" fused assets/scenes/hanging.json --set 'cloths.0.grid=[32,32]' \
    --set 'cloths.0.pins=[[0,0],[31,0]]' --frames "$(frames 30)" --no-plot -o "$out/fused-napkin"
counts=1,16,256,1024,4096
[ "$quick" = 1 ] && counts=1,2
step batch 120 "$bench" batch --set 'cloths.0.grid=[32,32]' --counts "$counts" \
    --frames "$(frames 10)" --no-plot -o "$out/batch"
step batch-fused 120 "$bench" batch --set 'cloths.0.grid=[32,32]' --set 'solver.fuse="on"' \
    --counts "$counts" --frames "$(frames 10)" --no-plot -o "$out/batch-fused"
if [ "$quick" = 1 ]; then
    echo "determinism: not run for a quick check" | tee -a "$log"
else
    step determinism 150 "$pack/bin/test_determinism" contact
fi
exact=${CLOTHVK_EXACT_LIB:-}
if [ -n "$exact" ] && [ "$quick" != 1 ]; then
    exact=$(cd "$exact" && pwd)
    step determinism-exact 150 env LD_LIBRARY_PATH="$exact:$LD_LIBRARY_PATH" \
        "$pack/bin/test_determinism" contact
    step fused-drape-exact 60 env LD_LIBRARY_PATH="$exact:$LD_LIBRARY_PATH" \
        "$bench" fused assets/scenes/drape.json --frames 30 --no-plot -o "$out/fused-drape-exact"
fi
step pile-large-ensemble 150 "$bench" contact-ensemble \
    --scenes assets/scenes/contact-pile-large.json --variants 1 --frames "$(frames 120)" \
    --no-plot -o "$out/pile-large-ensemble"
# Every showcase's ensemble, eight processes at a time; each writes its own folder, so what
# finished before the deadline is kept. Each process gets what is left of the limit when it
# starts (a queue's last ones start late).
limit=$(limit_for 300)
if [ "$limit" -lt 10 ]; then
    echo "showcase-ensembles: skipped, the deadline is near" | tee -a "$log"
else
    t0=$SECONDS
    end=$(($(date +%s) + limit))
    mkdir -p "$out/ensembles"
    # The thirteen showcases with contact (apps/bench/contact_ensemble.c's list).
    for n in box-stack sphere-hit throw funnel drape table chair ribbons demo poncho \
        contact-drape contact-pile contact-twist; do
        echo "$n"
    done | xargs -P 8 -I{} sh -c 'left=$(($3 - $(date +%s)))
        if [ "$left" -lt 10 ]; then echo "ensemble {}: skipped, the deadline is near"; exit 0; fi
        timeout "$left" "$0" contact-ensemble --scenes assets/scenes/{}.json ${1:+--frames 2} \
            --no-plot -o "$2/{}" >"$2/{}.out" 2>&1
        echo "ensemble {}: exit $? (limit $left s)"' \
        "$bench" "$( [ "$quick" = 1 ] && echo q)" "$out/ensembles" "$end" | tee -a "$log"
    echo "showcase-ensembles: $((SECONDS - t0)) s (limit $limit s)" | tee -a "$log"
fi
rm -rf "$out/build"
echo "gpu-figures: done after $SECONDS s; outputs in $out, and all of them in $out.tar.gz" |
    tee -a "$log"
tar czf "$out.tar.gz" -C "$out" .
