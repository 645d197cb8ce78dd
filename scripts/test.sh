#!/usr/bin/env bash
# Set up, build, and run the test suite on lavapipe with the Vulkan validation layer on.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
meson test -C build --print-errorlogs "$@"
