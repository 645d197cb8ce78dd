#!/usr/bin/env bash
# Renders a bake (clothvk-sim SCENE --bake BAKE_DIR) on a Slurm cluster as ONE job array: task i
# draws the i-th chunk of N frames the bake holds with `clothvk-render SCENE -o OUT_DIR --from
# BAKE_DIR --frames A:B`. Images from a bake equal a direct render's byte for byte, so the chunks
# can run in any order on any node.
#
#   scripts/slurm-render.sh SCENE BAKE_DIR OUT_DIR [--chunk N] [-- EXTRA SBATCH ARGS...]
#
# Prints the job id on stdout (a summary line goes to stderr). Slurm writes each task's log where
# it always does (slurm-JOBID_TASK.out in the current folder) unless `-- --output=...` says
# otherwise; arguments after `--` go to sbatch after this script's own (--job-name, --array), so
# they may override the job name (not --array).
#
# Assumes a SHARED FILESYSTEM: SCENE, BAKE_DIR, OUT_DIR, any mesh file the scene names, and
# clothvk-render itself must be at the same absolute paths on the submit host and every compute
# node (the paths are made absolute here, at submission). Nothing is copied.
#
# clothvk-render is $CLOTHVK_RENDER if set, else the build tree next to this script
# (../build/apps/clothvk-render), else the one on PATH.
set -euo pipefail

me=slurm-render.sh
die() { echo "$me: $*" >&2; exit 2; }
usage() {
    echo "usage: scripts/slurm-render.sh SCENE BAKE_DIR OUT_DIR [--chunk N] [-- SBATCH ARGS...]"
    echo "  --chunk N   frames of the bake per array task (default 10)"
}

chunk=10
positional=()
extra=()
while [ $# -gt 0 ]; do
    case "$1" in
        --chunk) [ $# -ge 2 ] || die "--chunk needs a value (frames per array task)"
                 chunk=$2; shift 2 ;;
        --chunk=*) chunk=${1#--chunk=}; shift ;;
        --) shift; extra=("$@"); break ;;
        -h|--help) usage; exit 0 ;;
        -*) die "unknown option $1 (see --help)" ;;
        *) positional+=("$1"); shift ;;
    esac
done
[ ${#positional[@]} -eq 3 ] || { usage >&2; exit 2; }
[[ $chunk =~ ^[1-9][0-9]*$ ]] || die "--chunk $chunk: must be a whole number of frames, 1 or more"

scene=${positional[0]}
bake=${positional[1]}
out=${positional[2]}
[ -f "$scene" ] || die "$scene: no such scene file"
[ -f "$bake/cache.json" ] || \
    die "$bake: no bake here ($bake/cache.json is missing; make one with clothvk-sim SCENE --bake $bake)"

# frames and every from cache.json; python3 rather than jq, which clothvk does not otherwise need.
read -r frames every < <(python3 - "$bake/cache.json" <<'EOF' || echo "error error"
import json, sys
try:
    c = json.load(open(sys.argv[1]))
    assert c.get("format") == "clothvk-bake"
    print(int(c["frames"]), int(c["every"]))
except Exception:
    print("error error")
EOF
)
[[ $frames =~ ^[0-9]+$ && $every =~ ^[1-9][0-9]*$ ]] || \
    die "$bake/cache.json: not a clothvk bake (no \"format\": \"clothvk-bake\" with frames and every)"

# The bake holds frame i*every in frame_%04d.snap numbered i, for every i*every <= frames (the
# start, then one file per K frames up to the last; bake format version 3).
held=$(( frames / every + 1 ))
for (( i = 0; i < held; i++ )); do
    snap=$(printf '%s/frame_%04d.snap' "$bake" "$i")
    [ -f "$snap" ] || die "$bake: the bake is incomplete ($snap is missing; finish it with" \
                          "clothvk-sim SCENE --resume $bake)"
done

command -v sbatch >/dev/null || die "sbatch not found: this script submits to a Slurm cluster;" \
    "run it on a host with Slurm's client tools, or with another scheduler run one" \
    "'clothvk-render SCENE -o OUT --from $bake --frames A:B' per task (see docs/tools.md, Baking)"

render=${CLOTHVK_RENDER:-}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if [ -z "$render" ] && [ -x "$here/../build/apps/clothvk-render" ]; then
    render=$here/../build/apps/clothvk-render
fi
[ -n "$render" ] || render=$(command -v clothvk-render) || \
    die "clothvk-render not found (set CLOTHVK_RENDER, build the tree next to this script, or put it on PATH)"
[ -x "$render" ] || die "$render: not an executable clothvk-render (CLOTHVK_RENDER)"

# Absolute paths: the tasks start in whatever folder the node gives them.
render=$(realpath "$render")
scene=$(realpath "$scene")
bake=$(realpath "$bake")
out=$(realpath -m "$out")   # clothvk-render makes it (mkdir -p, safe when tasks race)

tasks=$(( (held + chunk - 1) / chunk ))

# The batch script run by every task. --frames A:B needs every frame from A to B in the bake, so
# with every > 1 each held frame is drawn by its own --frames F:F.
batch=$(cat <<EOF
#!/bin/bash
set -euo pipefail
render=$(printf '%q' "$render")
scene=$(printf '%q' "$scene")
bake=$(printf '%q' "$bake")
out=$(printf '%q' "$out")
chunk=$chunk every=$every held=$held
task=\${SLURM_ARRAY_TASK_ID:?this script runs as a Slurm array task}
first=\$(( task * chunk ))
last=\$(( first + chunk - 1 ))
[ "\$last" -lt "\$held" ] || last=\$(( held - 1 ))
echo "clothvk-render: task \$task draws frames \$(( first * every )) to \$(( last * every ))" \\
     "(every \$every) on \$(hostname)"
if [ "\$every" -eq 1 ]; then
    exec "\$render" "\$scene" -o "\$out" --from "\$bake" --frames "\$first:\$last" --quiet
fi
for (( i = first; i <= last; i++ )); do
    f=\$(( i * every ))
    "\$render" "\$scene" -o "\$out" --from "\$bake" --frames "\$f:\$f" --quiet
done
EOF
)

id=$(sbatch --parsable --job-name=clothvk-render "${extra[@]}" --array="0-$((tasks - 1))" \
     <<<"$batch") || die "sbatch refused the job array (its message is above)"
id=${id%%;*}
echo "$me: job $id: $tasks array tasks of up to $chunk frames, frames 0 to" \
     "$(( (held - 1) * every )) every $every, into $out" >&2
echo "$id"
