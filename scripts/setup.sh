#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages clothvk needs, only those missing. Run as root, or as a
# user with sudo.
set -euo pipefail

packages=(
    gcc pkg-config python3 meson ninja-build   # build
    glslang-tools                              # GLSL -> SPIR-V at build time
    libvulkan-dev                              # the Vulkan loader and headers
    mesa-vulkan-drivers                        # lavapipe: Vulkan on the CPU
    vulkan-validationlayers                    # every test runs with validation on
    libjansson-dev                             # scene files (JSON)
    libstb-dev                                 # PNG output (stb_image_write)
    zlib1g-dev                                 # fast deflate for the PNG output; snapshot CRC-32
    libassimp-dev g++                          # mesh files for cloths (OBJ, glTF 2, PLY, STL),
                                               # read by the library's one C++ file
    gnuplot-nox                                # clothvk-bench's plots (optional at run time:
                                               # the CSV is always written)
    python3-cffi python3-numpy                 # the Python package (python/)
    python3-pytest                             # its tests
    python3-mesonpy python3-venv               # scripts/test-pip.sh: pip install . in a venv,
                                               # nothing downloaded
    ffmpeg                                     # clothvk-render --video (a separate process;
                                               # optional at run time)
    slurm-wlm munge                            # tests/tools/test_slurm.py starts a one-node Slurm
                                               # cluster (scripts/slurm-render.sh)
    clang                                      # scripts/fuzz.sh: libFuzzer harnesses
    libbullet-dev                              # peers/bullet: the Bullet soft-body harness
                                               # (built only when both are found)
)

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "setup: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
