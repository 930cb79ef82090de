#!/usr/bin/env bash
# Installs every build, test and benchmark dependency from Debian 12 packages.
# Run as root or with sudo available. Safe to re-run.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libxsimd-dev libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev
  libstb-dev libpugixml-dev libcli11-dev
  libembree-dev                 # optional: only the benchmark compares against it
  clang libclang-rt-14-dev      # libFuzzer and the sanitizer build
  python3-matplotlib            # convergence charts
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
sudo_cmd=""
[ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
echo "install_deps: installing ${missing[*]}"
$sudo_cmd apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
