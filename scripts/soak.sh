#!/usr/bin/env bash
# Long-render soak test (not run in CI): renders CBbunny (or SCENE) continuously
# with checkpoints every 30 s for MINUTES minutes, samples the process's
# resident memory every 10 s, then stops it with SIGINT. Fails unless memory
# stayed flat (after the first minute, max - min < 5% of the max), the render
# exited 130 with its partial image and checkpoint written, and a second run of
# the same command resumes from that checkpoint.
#   bash scripts/soak.sh [MINUTES=30] [SCENE]
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=${1:-30}
scene=${2:-../shared/scenes/cs184/CBbunny.dae}
[ -f "$scene" ] || scene=scenes/cornell_spheres.dae
bin=build/cli/pathtracer
[ -x "$bin" ] || { echo "build first (scripts/setup.sh)"; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
render=("$bin" --engine wavefront -t 2 -s 16777216 -a 1 0 -l 4 -m 5 -r 480 360
        -f "$out/soak.png" --checkpoint "$out/soak.ckpt" --checkpoint-every 30 "$scene")
"${render[@]}" -q &
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
code=0
wait $pid || code=$?
echo "exit code $code (130 = interrupted as expected)"
[ "$code" = 130 ] || { echo "soak: expected exit code 130"; exit 1; }
[ -f "$out/soak.partial.png" ] || { echo "soak: no partial image"; exit 1; }
[ -f "$out/soak.ckpt" ] || { echo "soak: no checkpoint"; exit 1; }
echo "partial image written; checkpoint kept: $(stat -c %s "$out/soak.ckpt") bytes"
printf '%s\n' "${samples[@]}" | awk '$1 > 60 {if (min == "" || $2 < min) min = $2; if ($2 > max) max = $2}
  END {printf "RSS after the first minute: min %d kB, max %d kB, spread %.2f%%\n", min, max, 100 * (max - min) / max;
       exit (max - min) > 0.05 * max}'
# The same command resumes from the checkpoint (stopped again after 5 s).
"${render[@]}" > "$out/resume.log" 2>&1 &
pid=$!
sleep 5
kill -INT $pid
wait $pid || true
grep -m1 "Resuming from" "$out/resume.log" || { echo "soak: the checkpoint did not resume"; cat "$out/resume.log"; exit 1; }
