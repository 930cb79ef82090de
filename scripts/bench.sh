#!/usr/bin/env bash
# The ray tracing benchmark in one command: builds bench_trace (Release; the
# kernels run at the level PT_ISA names, default the widest this CPU runs, and
# Embree at the same instruction set), runs every scene side by side with
# Embree (median of 5 repetitions), writes out/bench.json (Google Benchmark JSON) and prints
# out/bench_table.md. Arguments go to bench_trace, e.g. --quick for a smoke
# run (two small scenes, one short repetition) or --benchmark_filter=CBbunny.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build --target bench_trace trace_rays
mkdir -p out
repeat=(--benchmark_repetitions=5 --benchmark_report_aggregates_only=true --benchmark_min_time=0.3)
for arg in "$@"; do [ "$arg" = "--quick" ] && repeat=(--benchmark_min_time=0.02); done
./build/bench/bench_trace "$@" "${repeat[@]}" --benchmark_out=out/bench.json --benchmark_out_format=json
/usr/bin/python3 scripts/bench_table.py out/bench.json | tee out/bench_table.md
