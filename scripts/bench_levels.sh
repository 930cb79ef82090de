#!/usr/bin/env bash
# Speed at every instruction-set level this CPU runs, side by side in one run:
# bench_trace (this BVH4 against Embree restricted to the same instruction
# set) on SCENES, and bench_render (CBbunny, wavefront / megakernel /
# reference). Writes out/levels/{trace,render}_<level>.json and prints
# out/levels/table.md.
#   bash scripts/bench_levels.sh [REPS] [SCENE_REGEX]   (defaults: 3, CBbunny|bunny|CBcoil|CBbunny_x16)
set -euo pipefail
cd "$(dirname "$0")/.."
reps=${1:-3}
scenes=${2:-'CBbunny|bunny|CBcoil|CBbunny_x16'}
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build --target bench_trace bench_render pathtracer > /dev/null
mkdir -p out/levels
levels=()
while read -r level _ _ support _; do
  if [ "$support" = supported ]; then levels+=("$level"); else echo "bench_levels: $level skipped (this CPU does not run it)"; fi
done < <(./build/io/cli/pathtracer --list-isa)
for level in "${levels[@]}"; do
  echo "bench_levels: $level"
  PT_ISA=$level ./build/bench/bench_trace --benchmark_filter="^(trace|build)/($scenes)/" \
    --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true --benchmark_min_time=0.3 \
    --benchmark_out="out/levels/trace_$level.json" --benchmark_out_format=json > /dev/null
done
for ((r = 0; r < reps; ++r)); do  # renders interleaved across levels
  for level in "${levels[@]}"; do
    PT_ISA=$level ./build/bench/bench_render --benchmark_filter='CBbunny.dae/(wavefront|megakernel|reference)/' \
      --benchmark_out="out/levels/render_${level}_$r.json" --benchmark_out_format=json > /dev/null
  done
done
/usr/bin/python3 scripts/bench_levels_table.py "${levels[@]}" | tee out/levels/table.md
