#!/usr/bin/env bash
# The render benchmark in one command: builds bench_render (Release; the
# engines run at the level PT_ISA names, default the widest this CPU runs),
# renders CBbunny, CBspheres_lambertian, CBcoil, CBgems and
# CBspheres_microfacet_al_ag at 480x360, -s 64 -l 4 -m 5, 2 threads, with the
# wavefront (with and without packets, sorted by material or not),
# megakernel and reference engines interleaved, REPS times each (default 3),
# writes out/bench_render.json and prints medians and the engine ratios.
#   bash scripts/bench_render.sh [REPS] [extra Google Benchmark flags]
set -euo pipefail
cd "$(dirname "$0")/.."
reps=${1:-3}
shift || true
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build --target bench_render
mkdir -p out
./build/bench/bench_render --benchmark_repetitions="$reps" --benchmark_enable_random_interleaving=true \
  --benchmark_out=out/bench_render.json --benchmark_out_format=json "$@"
/usr/bin/python3 scripts/bench_render_table.py out/bench_render.json | tee out/bench_render_table.md
