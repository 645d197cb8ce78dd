#!/usr/bin/env bash
# pip install of the repository (pyproject.toml: meson-python builds the library into the
# package) in a fresh virtual environment, with nothing downloaded: Debian's cffi, numpy and
# meson-python through --system-site-packages. Then a script from another folder, with no
# CLOTHVK_* variable, steps a scene and reads positions (python/tests/installed.py). Arguments go
# to pip: --config-settings=compile-args=-j1 builds on one core.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
"$work/venv/bin/pip" install --quiet --no-index --no-build-isolation "$@" "$root"
cp python/tests/installed.py "$work/"
cd "$work"
env -u CLOTHVK_LIBRARY -u CLOTHVK_BUILD_DIR -u PYTHONPATH \
    "$work/venv/bin/python" installed.py "$root/assets/scenes/hanging.json"
