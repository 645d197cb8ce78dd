#!/usr/bin/env bash
# The main job for a newcomer: set up, build, and simulate the default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
./build/apps/clothvk-sim assets/scenes/hanging.json "$@"
