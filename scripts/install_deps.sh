#!/usr/bin/env bash
# Installs every build, test and benchmark dependency from Debian 12 packages.
# With --aarch64 (what run_tests.sh asks for on x86-64), also the aarch64
# cross compiler, Debian's arm64 multiarch packages of the linked libraries,
# and qemu-user (which also runs x86-64 binaries on emulated CPUs).
# The browser test's packages (Chromium, its WebDriver, Selenium) are
# installed last and may fail alone: where Chromium cannot be installed, that
# test skips with a message and everything else is installed.
# Run as root or with sudo available. Safe to re-run.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libxsimd-dev libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev
  libstb-dev libpugixml-dev libcli11-dev libtinyexr-dev nlohmann-json3-dev
  libopenmpi-dev openmpi-bin    # mpirun renders across ranks (optional: without it the build has no MPI)
  libembree-dev                 # optional: only the benchmark compares against it
  clang libclang-rt-14-dev      # libFuzzer and the sanitizer build
  clang-format                  # the code style check (scripts/check_format.sh)
  python3-matplotlib            # convergence charts
  libmicrohttpd-dev             # the live view's HTTP server (pathtracer --serve)
  python3-pil                   # the live view's browser test reads PNGs
  python3-imageio libfreeimage3 # EXR images in the scripts' toolkit (scripts/ptlib/images.py)
)
browser=(chromium chromium-driver python3-selenium)  # the live view's browser test (headless Chromium)
sudo_cmd=""
[ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
if [ "${1:-}" = --aarch64 ]; then
  packages+=(g++-aarch64-linux-gnu qemu-user libtbb-dev:arm64 libpugixml-dev:arm64 libgtest-dev:arm64
             libgmock-dev:arm64 libtinyexr-dev:arm64)
  if ! dpkg --print-foreign-architectures | grep -qx arm64; then
    $sudo_cmd dpkg --add-architecture arm64
  fi
fi
missing() {  # the packages among "$@" not installed
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || echo "$p"
  done
}
mapfile -t needed < <(missing "${packages[@]}")
mapfile -t needed_browser < <(missing "${browser[@]}")
if [ ${#needed[@]} -eq 0 ] && [ ${#needed_browser[@]} -eq 0 ]; then
  echo "install_deps: all $(( ${#packages[@]} + ${#browser[@]} )) packages present"
  exit 0
fi
$sudo_cmd apt-get update -qq
if [ ${#needed[@]} -gt 0 ]; then
  echo "install_deps: installing ${needed[*]}"
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${needed[@]}"
fi
if [ ${#needed_browser[@]} -gt 0 ]; then
  echo "install_deps: installing ${needed_browser[*]}"
  if ! DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${needed_browser[@]}"; then
    echo "install_deps: ${needed_browser[*]} could not be installed here; the live view's browser test will skip"
  fi
fi
