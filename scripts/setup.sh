#!/usr/bin/env bash
# First command of the README: install dependencies, build (Release, the SIMD
# kernels of every instruction-set level in one binary) and render the built-in
# default scene to out/cornell_spheres.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
# The standard CMake recipe, with CMake's default generator (Unix Makefiles);
# -G Ninja works too. A build/ made earlier keeps its generator.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)"
mkdir -p out
./build/cli/pathtracer -t "$(nproc)" -s 64 -l 4 -m 5 -r 480 360 -f out/cornell_spheres.png
