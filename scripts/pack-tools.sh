#!/usr/bin/env bash
# Packs the built tools with every library they load (the Vulkan loader too, but no driver) into
# one folder, to run on another x86-64 Linux machine that has a Vulkan driver and nothing else of
# ours installed — a GPU machine, say, with scripts/gpu-figures.sh:
#
#   bash scripts/build.sh && bash scripts/pack-tools.sh pack
#   (copy pack/ and the source tree there)  bash scripts/gpu-figures.sh pack OUT
#
# pack/bin holds clothvk-sim, clothvk-bench, clothvk-render and test_determinism; pack/lib
# libclothvk and the libraries `ldd` lists for them but the C runtime's own. The tools find
# pack/lib by their RUNPATH ($ORIGIN/../lib); scripts/gpu-figures.sh puts it on
# LD_LIBRARY_PATH for the libraries' own dependencies. pack/layer holds the validation layer.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -eq 1 ] || { echo "usage: $0 DIR" >&2; exit 2; }
dir=$1
build=${CLOTHVK_BUILD_DIR:-build}
tools="$build/apps/clothvk-sim $build/apps/clothvk-bench $build/apps/clothvk-render
       $build/tests/sim/test_determinism"
for t in $tools; do
    [ -x "$t" ] || { echo "$0: $t is missing: run bash scripts/build.sh first" >&2; exit 1; }
done
copy_library() { # copy_library BUILD DEST: libclothvk.so and its versioned names (links kept)
    for f in "$1"/lib/libclothvk.so*; do [ -d "$f" ] || cp -P "$f" "$2/"; done
}
rm -rf "$dir"
mkdir -p "$dir/bin" "$dir/lib"
cp $tools "$dir/bin/"
copy_library "$build" "$dir/lib"
# The libraries the tools load, but the C runtime's (every Linux has its own, and a copy of
# another's would not match the loader there).
ldd $tools "$build"/lib/libclothvk.so.0 | awk '$2 == "=>" && $3 ~ /^\// { print $3 }' | sort -u |
    grep -Ev '/(libc|libm|libdl|libpthread|librt|ld-linux[^/]*)\.so' |
    while read -r lib; do cp -L "$lib" "$dir/lib/"; done
# With CLOTHVK_EXACT_BUILD_DIR, a build made with -Dfloat_exact=true: its library in pack/exact,
# for scripts/gpu-figures.sh's CLOTHVK_EXACT_LIB (the tools load it first from there).
exact=${CLOTHVK_EXACT_BUILD_DIR:-}
if [ -n "$exact" ]; then
    mkdir -p "$dir/exact"
    copy_library "$exact" "$dir/exact"
fi
# The Khronos validation layer, which test_determinism (like every test) turns on: its manifest
# names the library beside it, and scripts/gpu-figures.sh puts pack/layer on VK_LAYER_PATH.
manifest=/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
if [ -f "$manifest" ]; then
    mkdir -p "$dir/layer"
    layer=$(sed -n 's/.*"library_path": *"\([^"]*\)".*/\1/p' "$manifest")
    # (awk reads to the end: an early exit would fail ldconfig's write under pipefail)
    [ -f "$layer" ] || layer=$(ldconfig -p |
        awk -v l="$(basename "$layer")" '$1 == l && !p { p = $NF } END { print p }')
    cp -L "$layer" "$dir/layer/"
    sed 's#"library_path": *"[^"]*"#"library_path": "./'"$(basename "$layer")"'"#' "$manifest" \
        >"$dir/layer/$(basename "$manifest")"
else
    echo "pack-tools: no validation layer (vulkan-validationlayers): test_determinism will" \
        "not run" >&2
fi
echo "pack-tools: $(ls "$dir/bin" | wc -l) programs and $(ls "$dir/lib" | wc -l) libraries in $dir ($(du -sh "$dir" | cut -f1))"
