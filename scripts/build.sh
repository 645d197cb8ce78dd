#!/usr/bin/env bash
# Configures (once) and builds clothvk in ./build. CLOTHVK_SETUP_OPTIONS: more options for that
# meson setup (.ci/run passes -Dwerror=true).
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck disable=SC2086
[ -f build/build.ninja ] || meson setup build ${CLOTHVK_SETUP_OPTIONS:-} >/dev/null
meson compile -C build >/dev/null
