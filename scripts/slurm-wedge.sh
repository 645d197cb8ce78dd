#!/usr/bin/env bash
# Runs a wedge — many variants of one scene (clothvk-sim --wedge / --wedges) — on a Slurm cluster
# as ONE job array, task K running `clothvk-sim SCENE ... -o DIR --wedge-index K`, and a gather
# job that waits for every task (afterany) and writes DIR/wedges.csv (a row per variant) and
# DIR/contact-sheet.png (each variant's last frame, labelled with its values).
#
#   scripts/slurm-wedge.sh SCENE -o DIR [CLOTHVK-SIM OPTIONS...] [-- EXTRA SBATCH ARGS...]
#
# CLOTHVK-SIM OPTIONS are clothvk-sim's: --wedge key.path=v1,v2,..., --wedges FILE, --set k=v,
# --frames N, --wedge-limit N, --wedge-time-limit S, --wedge-bake. Every variant draws its last
# frame (--wedge-preview is added). The wedge is checked first (clothvk-sim --wedge-count): a bad
# key path, value or list is one line from clothvk-sim and exit 2, before anything is submitted
# or written.
#
# Prints the gather job's id on stdout (when it ends, the table and the sheet are there); a
# summary line with both ids goes to stderr. Each task's log is DIR/slurm-ARRAY_TASK.out, the
# gather's DIR/slurm-JOB-gather.out, unless `-- --output=...` says otherwise: arguments after
# `--` go to both sbatch calls after this script's own (--job-name, --array, --time, --output,
# --chdir, --dependency), so they may override them (not --array or --dependency).
#
# With --wedge-time-limit S a variant stops itself after S seconds (its row says timed-out, with
# the frames it ran), and the array gets sbatch --time of S plus a minute, rounded up to whole
# minutes, so that a task hung inside a frame is ended by Slurm (its row then says timed-out
# with Slurm's state). The gather job reads each task's state (scontrol) into DIR/states.tsv:
# a variant that crashed or was killed is a row that says how, never a missing one.
#
# Assumes a SHARED FILESYSTEM: the current folder (every task starts there: --chdir), SCENE,
# DIR, any file the options or the scene name, and clothvk-sim itself must be at the same paths
# on the submit host and every compute node. Nothing is copied.
#
# clothvk-sim is $CLOTHVK_SIM if set, else the build tree next to this script
# (../build/apps/clothvk-sim), else the one on PATH.
set -euo pipefail

me=slurm-wedge.sh
die() { echo "$me: $*" >&2; exit 2; }
usage() {
    echo "usage: scripts/slurm-wedge.sh SCENE -o DIR [CLOTHVK-SIM OPTIONS...] [-- SBATCH ARGS...]"
    echo "  CLOTHVK-SIM OPTIONS: --wedge key.path=v1,v2,... --wedges FILE --set k=v --frames N"
    echo "                       --wedge-limit N --wedge-time-limit S --wedge-bake"
}

scene=""
out=""
time_limit=""
sim_args=()
extra=()
while [ $# -gt 0 ]; do
    case "$1" in
        -o|--output) [ $# -ge 2 ] || die "$1 needs a value (the wedge's folder)"
                     out=$2; shift 2 ;;
        --output=*) out=${1#--output=}; shift ;;
        --wedge-time-limit) [ $# -ge 2 ] || die "--wedge-time-limit needs a value (seconds)"
                            time_limit=$2; sim_args+=("$1" "$2"); shift 2 ;;
        --wedge-time-limit=*) time_limit=${1#--wedge-time-limit=}; sim_args+=("$1"); shift ;;
        --jobs|--jobs=*|--wedge-index|--wedge-index=*|--wedge-count|--wedge-gather*)
            die "$1: the script runs each variant as an array task and gathers them itself" ;;
        --) shift; extra=("$@"); break ;;
        -h|--help) usage; exit 0 ;;
        -*) sim_args+=("$1")
            # clothvk-sim's options with a value take the next argument, whatever it looks like.
            case "$1" in
                --wedge|--wedges|--set|--frames|--wedge-limit|--workgroup-size|--max-workgroups)
                    [ $# -ge 2 ] && { sim_args+=("$2"); shift; } ;;
            esac
            shift ;;
        *) [ -z "$scene" ] || die "one scene file expected, got $scene and $1"
           scene=$1; shift ;;
    esac
done
[ -n "$scene" ] || { usage >&2; exit 2; }
[ -n "$out" ] || die "no output folder given (-o DIR)"

sim=${CLOTHVK_SIM:-}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if [ -z "$sim" ] && [ -x "$here/../build/apps/clothvk-sim" ]; then
    sim=$here/../build/apps/clothvk-sim
fi
[ -n "$sim" ] || sim=$(command -v clothvk-sim) || \
    die "clothvk-sim not found (set CLOTHVK_SIM, build the tree next to this script, or put it on PATH)"
[ -x "$sim" ] || die "$sim: not an executable clothvk-sim (CLOTHVK_SIM)"
sim=$(realpath "$sim")
sim_args+=(--wedge-preview)

# The whole wedge is checked here, on the submit host: clothvk-sim prints the one line.
count=$("$sim" "$scene" "${sim_args[@]}" -o "$out" --wedge-count) || exit $?
[[ $count =~ ^[1-9][0-9]*$ ]] || die "clothvk-sim --wedge-count printed '$count', not a count"

command -v sbatch >/dev/null || die "sbatch not found: this script submits to a Slurm cluster;" \
    "run it on a host with Slurm's client tools, or run the wedge on one machine with" \
    "clothvk-sim SCENE ... -o $out --jobs N (see docs/tools.md, Wedges)"

mkdir -p "$out"
out=$(realpath "$out")
time_args=()
if [ -n "$time_limit" ]; then
    time_args=(--time=$(( (time_limit + 60 + 59) / 60 )))
fi

quoted=$(printf ' %q' "$sim" "$scene" "${sim_args[@]}" -o "$out")
array=$(cat <<EOF
#!/bin/bash
task=\${SLURM_ARRAY_TASK_ID:?this script runs as a Slurm array task}
echo "clothvk-sim: wedge variant \$task on \$(hostname)"
exec$quoted --wedge-index "\$task"
EOF
)
id=$(sbatch --parsable --job-name=clothvk-wedge --array="0-$((count - 1))" "${time_args[@]}" \
     --chdir="$PWD" --output="$out/slurm-%A_%a.out" "${extra[@]}" <<<"$array") || \
    die "sbatch refused the job array (its message is above)"
id=${id%%;*}

# The gather: each task's Slurm state (for the variants that did not end by themselves), then
# the table and the sheet.
gather=$(cat <<EOF
#!/bin/bash
set -uo pipefail
out=$(printf '%q' "$out")
scontrol -o show job $id | awk '{
    task = ""; state = ""; reason = ""; code = ""
    for (i = 1; i <= NF; i++) {
        split(\$i, kv, "=")
        if (kv[1] == "ArrayTaskId") task = kv[2]
        if (kv[1] == "JobState") state = kv[2]
        if (kv[1] == "Reason") reason = kv[2]
        if (kv[1] == "ExitCode") code = kv[2]
    }
    if (task ~ /^[0-9]+\$/)
        printf "%s\t%s\tSlurm job ${id}_%s: %s, reason %s, exit code %s\n", task, state, task, state, reason, code
}' | sort -n > "\$out/states.tsv.tmp" && mv "\$out/states.tsv.tmp" "\$out/states.tsv"
exec $(printf '%q' "$sim") --wedge-gather "\$out"
EOF
)
gid=$(sbatch --parsable --job-name=clothvk-wedge-gather --dependency="afterany:$id" \
      --chdir="$PWD" --output="$out/slurm-%j-gather.out" "${extra[@]}" <<<"$gather") || {
    scancel "$id" 2>/dev/null || true
    die "sbatch refused the gather job (its message is above); job array $id cancelled"
}
gid=${gid%%;*}
echo "$me: job array $id: $count variants into $out; gather job $gid writes $out/wedges.csv" \
     "and $out/contact-sheet.png when every task has ended" >&2
echo "$gid"
