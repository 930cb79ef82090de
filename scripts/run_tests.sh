#!/usr/bin/env bash
# Second command of the README: build and run the whole test suite with ctest.
# Installs missing dependencies first, so it also works on a fresh machine.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build
ctest --test-dir build --output-on-failure -j "$(nproc)"
