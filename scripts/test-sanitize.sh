#!/usr/bin/env bash
# The C test programs again, built with AddressSanitizer and UndefinedBehaviorSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
[ -f build-sanitize/build.ninja ] ||
    meson setup build-sanitize -Db_sanitize=address,undefined -Db_lundef=false >/dev/null
meson compile -C build-sanitize >/dev/null
meson test -C build-sanitize --print-errorlogs --suite unit --wrapper "$PWD/tests/sanitize.sh" "$@"
