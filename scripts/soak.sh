#!/usr/bin/env bash
# Long-render soak test (not run in CI): renders CBbunny (or SCENE) continuously
# with checkpoints every 30 s for MINUTES minutes, samples the process's
# resident memory every 10 s, then stops it with SIGINT and checks that memory
# stayed flat (after the first minute, max - min < 5% of the max) and that the
# checkpoint resumes.
#   bash scripts/soak.sh [MINUTES=30] [SCENE]
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=${1:-30}
scene=${2:-../shared/scenes/cs184/CBbunny.dae}
[ -f "$scene" ] || scene=scenes/cornell_spheres.dae
bin=build/io/cli/pathtracer
[ -x "$bin" ] || { echo "build first (scripts/setup.sh)"; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$bin" --engine wavefront -t 2 -s 16777216 -a 1 0 -l 4 -m 5 -r 480 360 -q \
  -f "$out/soak.png" --checkpoint "$out/soak.ckpt" --checkpoint-every 30 "$scene" &
pid=$!
samples=()
end=$((SECONDS + minutes * 60))
while [ $SECONDS -lt $end ] && kill -0 $pid 2>/dev/null; do
  sleep 10
  rss=$(awk '/VmRSS/ {print $2}' /proc/$pid/status 2>/dev/null || echo 0)
  samples+=("$SECONDS $rss")
  echo "t=${SECONDS}s rss=${rss} kB checkpoint=$(stat -c %s "$out/soak.ckpt" 2>/dev/null || echo none)"
done
kill -INT $pid
wait $pid || code=$?
echo "exit code ${code:-0} (130 = interrupted as expected)"
printf '%s\n' "${samples[@]}" | awk '$1 > 60 {if (min == "" || $2 < min) min = $2; if ($2 > max) max = $2}
  END {printf "RSS after the first minute: min %d kB, max %d kB, spread %.2f%%\n", min, max, 100 * (max - min) / max;
       exit (max - min) > 0.05 * max}'
[ -f "$out/soak.partial.png" ] && echo "partial image written"
[ -f "$out/soak.ckpt" ] && echo "checkpoint kept: $(stat -c %s "$out/soak.ckpt") bytes"
