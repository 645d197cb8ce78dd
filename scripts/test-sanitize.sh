#!/usr/bin/env bash
# The C test programs again, built with AddressSanitizer and UndefinedBehaviorSanitizer, then
# the tools' tests (cli, render-cli, bench) against the sanitized tools.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# shellcheck disable=SC2086
[ -f build-sanitize/build.ninja ] ||
    meson setup build-sanitize -Db_sanitize=address,undefined -Db_lundef=false \
        ${CLOTHVK_SETUP_OPTIONS:-} >/dev/null
meson compile -C build-sanitize >/dev/null
meson test -C build-sanitize --print-errorlogs --suite unit --wrapper "$PWD/tests/sanitize.sh" "$@"
# The tools' tests (bad input, divergence, images, experiments) against the sanitized tools.
[ $# -gt 0 ] || meson test -C build-sanitize --print-errorlogs --wrapper "$PWD/tests/sanitize-tools.sh" \
    cli render-cli bench sigint memory-cli wedge-cli
# The libFuzzer harnesses, 30 s each (scripts/fuzz.sh; clang).
[ $# -gt 0 ] || bash scripts/fuzz.sh 30
