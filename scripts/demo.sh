#!/usr/bin/env bash
# The main job for a newcomer: set up, build, and render the demo scene as a PNG sequence.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
./build/apps/clothvk-render assets/scenes/demo.json -o demo-frames --every 2 "$@"
echo "demo: frames in demo-frames/; as a video:" \
     "./build/apps/clothvk-render assets/scenes/demo.json --every 2 --video demo.mp4"
