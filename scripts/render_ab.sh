#!/usr/bin/env bash
# A/B of two pathtracer binaries on whole renders: CBbunny, CBcoil and
# CBspheres_lambertian at 480x360, -s 64 -l 4 -m 5 -a 64 0 (every pixel gets
# all 64 samples), 2 threads, the two binaries alternating (A first in odd
# rounds, B first in even ones). Prints each run's render time (the end
# report's) and, per scene, both medians and the median of the paired ratios
# B/A (below 1: B is faster).
#   bash scripts/render_ab.sh A/pathtracer B/pathtracer [ROUNDS]
set -euo pipefail
a=$1 b=$2 rounds=${3:-5}
scenes=$(cd "$(dirname "$0")/../../shared/scenes/cs184" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
lscpu | grep -m1 'Model name' | sed 's/^/cpu: /'
grep -q avx512f /proc/cpuinfo && echo "cpu: AVX-512" || echo "cpu: no AVX-512 (AVX2 + FMA)"
render() {  # binary scene -> seconds
  "$1" -t 2 -s 64 -l 4 -m 5 -a 64 0 -r 480 360 -f "$out/image.png" "$scenes/$2" < /dev/null |
    grep -oP 'Rendered in \K[0-9.]+'
}
for scene in CBbunny.dae CBcoil.dae CBspheres_lambertian.dae; do
  for r in $(seq 1 "$rounds"); do
    if (( r % 2 )); then ta=$(render "$a" "$scene"); tb=$(render "$b" "$scene")
    else tb=$(render "$b" "$scene"); ta=$(render "$a" "$scene"); fi
    echo "$scene $ta $tb"
  done
done | tee "$out/runs" | sed 's/^/run: /'
python3 - "$out/runs" <<'EOF'
import statistics, sys
rows = {}
for line in open(sys.argv[1]):
    scene, ta, tb = line.split()
    rows.setdefault(scene, []).append((float(ta), float(tb)))
print(f"{'scene':28} {'A s':>7} {'B s':>7} {'B/A':>6} {'range':>13}")
for scene, runs in rows.items():
    ratios = [tb / ta for ta, tb in runs]
    print(f"{scene:28} {statistics.median(r[0] for r in runs):7.3f} {statistics.median(r[1] for r in runs):7.3f}"
          f" {statistics.median(ratios):6.3f} {min(ratios):6.3f}-{max(ratios):.3f}")
EOF
