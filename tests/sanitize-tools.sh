#!/bin/sh
# Test wrapper for the tool tests against the sanitizer build: the test script is Python, which
# is not built with AddressSanitizer, and runs the sanitized tools as child processes. Their
# options go through the environment; the Vulkan driver and validation layer are preloaded so that
# LeakSanitizer can name their allocations for lsan.supp (as tests/sanitize.sh does), but libasan
# is not: it would load into Python itself, whose allocations at exit are not clothvk's. The tools
# link libasan themselves, after the preloaded libraries, which ASan allows with
# verify_asan_link_order=0. A finding makes the tool exit with status 1 and its report fails the
# test's stderr checks.
here=$(cd "$(dirname "$0")" && pwd)
preload=""
for lib in /usr/lib/*/libvulkan_lvp.so /usr/lib/*/libVkLayer_khronos_validation.so; do
    [ -e "$lib" ] && preload="$preload $lib"
done
export LD_PRELOAD="$preload"
# The quarantine as in tests/sanitize.sh.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:verify_asan_link_order=0:quarantine_size_mb=8"
export LSAN_OPTIONS="suppressions=$here/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# Tests that give the tools time limits give slower tools more (tests/tools/wedge_cases.py).
export CLOTHVK_SANITIZED=1
exec "$@"
