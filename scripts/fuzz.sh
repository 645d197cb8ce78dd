#!/usr/bin/env bash
# libFuzzer harnesses (tests/fuzz/) for the scene loader with --set overrides, for the mesh
# reader and for what a bake resume reads (cache.json and snapshots), built with clang,
# AddressSanitizer and UndefinedBehaviorSanitizer in build-fuzz/, and run for SECONDS each
# (default 60) from seeds made of the scenes in assets/scenes and tests/scenes (as they are, and
# with --set overrides), the meshes in assets/ and a bake the bake harness makes; what a run
# finds new stays in build-fuzz/corpus-*, where the next run starts. Any finding (a crash, a
# sanitizer report, a leak) fails the script and leaves the input as build-fuzz/crash-* (or
# leak-*, timeout-*). For a longer run: bash scripts/fuzz.sh 3600.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
command -v clang >/dev/null && command -v clang++ >/dev/null ||
    { echo "fuzz.sh: clang is missing (apt-get install clang)" >&2; exit 2; }
if [ ! -f build-fuzz/build.ninja ]; then
    CC=clang CXX=clang++ meson setup build-fuzz -Db_sanitize=address,undefined -Db_lundef=false \
        -Dc_args=-fsanitize=fuzzer-no-link -Dcpp_args=-fsanitize=fuzzer-no-link >/dev/null
fi
meson compile -C build-fuzz lib/clothvk_internal >/dev/null
flags="-g -O1 -fsanitize=fuzzer,address,undefined -Ilib -Ilib/include -Ishaders -Ibuild-fuzz/shaders"
# -lstdc++ and the sanitizers' C++ runtime (UBSan's checks of dynamic types): the archive's one
# C++ object (lib/topology/assimp_import.cpp), linked by the C driver
libs="build-fuzz/lib/libclothvk_internal.a $(pkg-config --libs jansson assimp vulkan zlib) -lstdc++ -lm -lpthread"
libs="$libs -fsanitize-link-c++-runtime"
for name in scene mesh; do
    # shellcheck disable=SC2086
    clang $flags -o "build-fuzz/fuzz_$name" "tests/fuzz/fuzz_$name.c" $libs
done
# The bake reader is the tools' (apps/bake.c), on the library's internal archive.
# shellcheck disable=SC2086
clang $flags -Iapps -DCVK_TOOLS_VERSION=\"fuzz\" -o build-fuzz/fuzz_bake tests/fuzz/fuzz_bake.c apps/bake.c \
    apps/common.c apps/cli.c $libs

# Seeds: a scene's text as it is, and with an override; a mesh with its format byte first.
seeds=build-fuzz/seeds
rm -rf "$seeds" && mkdir -p "$seeds/scene" "$seeds/mesh" "$seeds/bake"
for f in assets/scenes/*.json tests/scenes/*.json; do
    cp "$f" "$seeds/scene/$(basename "$f")"
    printf '%s\n#set\nsubsteps=3\ncloths.0.grid=[5,4]\n' "$(cat "$f")" > "$seeds/scene/set-$(basename "$f")"
done
for f in $(find assets tests -name '*.obj' -o -name '*.ply' | head -50); do
    case "$f" in *.ply) byte='\x01' ;; *) byte='\x00' ;; esac
    { printf "$byte"; cat "$f"; } > "$seeds/mesh/$(echo "$f" | tr / _)"
done
# An OBJ file on which Assimp 5.2 leaks (see below), so that every run reads one.
printf '\x00v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no second\nf 5 6 7\n' > "$seeds/mesh/obj-assimp-leak"
# A bake's cache.json and frame 0 (the snapshot with and without its CRC-32 made right).
# The Vulkan stack keeps some allocations until exit (tests/lsan.supp); clothvk's are checked.
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
CLOTHVK_FUZZ_SEEDS="$seeds/bake" build-fuzz/fuzz_bake
# Leaks are checked in every harness. Assimp before 5.4.2 (Debian 12 has 5.2.5) leaks inside
# its OBJ importer on some malformed files: the meshes it has built stay in a local array when a
# later mesh has a face index out of range (fixed upstream by #5645). The mesh harness leaves out
# what leaks inside Assimp::BaseImporter::ReadFile, with whole stacks (fast_unwind_on_malloc=0:
# Assimp and libstdc++ keep no frame pointers) so the rule can see that frame; clothvk's own
# allocations are still checked: an importer it forgot to free leaks from its own code.
mesh_supp=build-fuzz/lsan-mesh.supp
{ cat tests/lsan.supp; echo "leak:Assimp::BaseImporter::ReadFile"; } > "$mesh_supp"
status=0
for name in scene mesh bake; do
    corpus=build-fuzz/corpus-$name
    mkdir -p "$corpus"
    asan=detect_leaks=1 lsan=$LSAN_OPTIONS
    if [ "$name" = mesh ]; then
        asan=$asan:fast_unwind_on_malloc=0 lsan="suppressions=$PWD/$mesh_supp:print_suppressions=0"
    fi
    ASAN_OPTIONS=$asan LSAN_OPTIONS=$lsan UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
        "build-fuzz/fuzz_$name" "$corpus" "$seeds/$name" -max_total_time="$seconds" \
        -max_len=65536 -timeout=10 -rss_limit_mb=2048 -artifact_prefix=build-fuzz/ \
        -print_final_stats=1 2>"build-fuzz/fuzz_$name.log" || status=1
    grep -E "^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)|cov: " \
        "build-fuzz/fuzz_$name.log" | tail -4 | sed "s/^/fuzz_$name: /"
done
[ $status -eq 0 ] || echo "fuzz.sh: a finding; see build-fuzz/fuzz_*.log and build-fuzz/crash-*" >&2
exit $status
