#!/usr/bin/env bash
# Installs every build, test and benchmark dependency from Debian 12 packages.
# With --aarch64 (what run_tests.sh asks for on x86-64), also the aarch64
# cross compiler, Debian's arm64 multiarch packages of the linked libraries,
# and qemu-user (which also runs x86-64 binaries on emulated CPUs).
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
)
sudo_cmd=""
[ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
if [ "${1:-}" = --aarch64 ]; then
  packages+=(g++-aarch64-linux-gnu qemu-user libtbb-dev:arm64 libpugixml-dev:arm64 libgtest-dev:arm64
             libgmock-dev:arm64 libtinyexr-dev:arm64)
  if ! dpkg --print-foreign-architectures | grep -qx arm64; then
    $sudo_cmd dpkg --add-architecture arm64
  fi
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install_deps: installing ${missing[*]}"
$sudo_cmd apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
