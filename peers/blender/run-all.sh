#!/usr/bin/env bash
# Runs the Blender drape peer (peers/blender/drape.py) over the standard set, one thread each,
# appending to a CSV (default peers/blender/results/drape-<date>.csv): grids 20 and 40 with and
# without self-collision at quality 5 (twice, alternated) and at quality 15, then grid 80 at
# quality 5 (which goes through the sphere: drape_ok=no) and 15, with and without self-collision;
# with --with-160, grid 160 at quality 30 (about 7 minutes on one core).
# Usage: bash peers/blender/run-all.sh [CSV] [--with-160]   (needs blender on PATH)
set -euo pipefail
cd "$(dirname "$0")/../.."
csv=${1:-peers/blender/results/drape-$(date -u +%Y-%m-%d).csv}
with160=${2:-}
mkdir -p "$(dirname "$csv")"
run() {
    blender -b -noaudio -t 1 --factory-startup --python peers/blender/drape.py -- "$@" --csv "$csv" \
        2>&1 | grep -E '^blender-drape (vertex|load|last|grid)'
}
for round in 1 2; do
    for g in 20 40; do run --grid "$g"; run --grid "$g" --no-self; done
done
for g in 20 40; do run --grid "$g" --quality 15; run --grid "$g" --quality 15 --no-self; done
run --grid 80
run --grid 80 --quality 15
run --grid 80 --quality 15 --no-self
if [ "$with160" = --with-160 ]; then run --grid 160 --quality 30; fi
echo "rows in $csv"
