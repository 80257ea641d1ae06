#!/usr/bin/env bash
# Installs every system dependency of rubble from Debian's archive.
# Idempotent and non-interactive: packages already present are left alone.
set -euo pipefail

packages=(
    build-essential cmake pkg-config git
    # OpenCL: PoCL is the CPU device wherever no GPU driver exists
    pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo
    libclblast-dev
    # maths, scenes, meshes, hulls, command line, tests, benchmarks
    libglm-dev nlohmann-json3-dev libtinyobjloader-dev libqhull-dev libcli11-dev
    libgtest-dev libgmock-dev libbenchmark-dev
    # peer engines for the benchmarks (bench/peers)
    libbullet-dev libmujoco-dev
    # viewer and headless rendering
    libglfw3-dev libgl-dev libegl-dev libglx-dev libepoxy-dev libstb-dev xvfb xauth
    libegl-mesa0 libgl1-mesa-dri
    # plots of the benchmarks and comparisons
    python3 python3-matplotlib
    # videos of `rubble render` (its test runs where ffmpeg is)
    ffmpeg
    # CI's checks: clang with AddressSanitizer, UBSan and libFuzzer (the sanitize preset), and
    # Oclgrind, which runs every kernel with bounds, uninitialised-value and data-race checks
    clang libclang-rt-14-dev oclgrind
    # the Python package (docs/python.md): a virtual environment (Debian's python3 is externally
    # managed), the headers its module builds against, and the generator pip's CMake uses
    python3-venv python3-dev ninja-build
)

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done

if ((${#missing[@]} == 0)); then
    echo "setup: all ${#packages[@]} packages are installed"
    exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
echo "setup: installing ${missing[*]}"
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "setup: done"
