#!/bin/sh
# Test wrapper for the sanitizer build: keeps the Vulkan driver and validation layer loaded
# until exit (instead of being dlclose'd) so LeakSanitizer can name their allocations and the
# suppressions in lsan.supp can match them; a leak from clothvk still fails the test.
here=$(cd "$(dirname "$0")" && pwd)
preload="$(gcc -print-file-name=libasan.so)"
for lib in /usr/lib/*/libvulkan_lvp.so /usr/lib/*/libVkLayer_khronos_validation.so; do
    [ -e "$lib" ] && preload="$preload $lib"
done
export LD_PRELOAD="$preload"
# A quarantine of 8 MB, not ASan's 256: lavapipe's queue thread allocates and frees large blocks at
# every submit, and with the larger quarantine each new one maps fresh pages (page faults made
# up most of the run: test_pd_tolerance 45 -> 26 s, 3.3 -> 0.9 GB). A use after free is still
# caught while less than 8 MB has been freed since (docs/testing.md).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:quarantine_size_mb=8"
export LSAN_OPTIONS="suppressions=$here/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# Lavapipe on one thread for the determinism tests too (meson gives the others LP_NUM_THREADS=0
# already): this run looks for memory errors in clothvk's own code, which runs the same on any
# number of lavapipe threads.
export LP_NUM_THREADS=0
# test_determinism: a few dispatch shapes, not all (docs/testing.md)
export CLOTHVK_SANITIZED=1
exec "$@"
