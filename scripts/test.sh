#!/usr/bin/env bash
# Set up, build, and run the test suite on lavapipe with the Vulkan validation layer on.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
meson test -C build --print-errorlogs "$@"

# The Python package against the library just built. Debian's interpreter has the packages
# setup.sh installed; a python3 earlier on PATH (pyenv, a venv) may not.
python=python3
"$python" -c "import cffi, numpy, pytest" 2>/dev/null || python=/usr/bin/python3
PYTHONPATH=python CLOTHVK_BUILD_DIR="$PWD/build" "$python" -m pytest python/tests -q
