#!/usr/bin/env bash
# What run-time dispatch costs: the dispatched build (build/, every level in
# one binary, PT_ISA forcing the level) against single-level builds compiled
# for that level alone (-DPT_NATIVE=ON -DPT_MARCH=...: x86-64-v2, x86-64-v3,
# and native for the widest level this CPU runs), at every level this CPU
# runs. Whole CBbunny renders (bench_render: 480x360, -s 64 -l 4 -m 5, 2
# threads, wavefront and megakernel), REPS interleaved pairs (default 5);
# prints medians and dispatched / single-level time ratios.
#   bash scripts/bench_dispatch.sh [REPS]
set -euo pipefail
cd "$(dirname "$0")/.."
reps=${1:-5}
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build --target bench_render > /dev/null
best=$(./build/io/cli/pathtracer --list-isa | awk '$5 == "auto" {print $1}')
declare -A march=([sse4.2]=x86-64-v2 [avx2]=x86-64-v3 [avx512]=x86-64-v4 [neon]=native)
march[$best]=native
levels=()
while read -r level _ _ support _; do
  [ "$support" = supported ] || continue
  levels+=("$level")
  dir=build-single-$level
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPT_NATIVE=ON -DPT_MARCH="${march[$level]}" \
        -DPT_BUILD_TESTS=OFF > /dev/null
  cmake --build "$dir" --target bench_render > /dev/null
done < <(./build/io/cli/pathtracer --list-isa)
mkdir -p out/dispatch
filter='CBbunny.dae/(wavefront|megakernel)/'
for ((r = 0; r < reps; ++r)); do
  for level in "${levels[@]}"; do
    PT_ISA=$level ./build/bench/bench_render --benchmark_filter="$filter" \
      --benchmark_out="out/dispatch/dispatched_${level}_$r.json" --benchmark_out_format=json > /dev/null
    ./build-single-$level/bench/bench_render --benchmark_filter="$filter" \
      --benchmark_out="out/dispatch/single_${level}_$r.json" --benchmark_out_format=json > /dev/null
  done
done
/usr/bin/python3 - "${levels[@]}" <<'PY'
import glob, json, statistics, sys
print("| level | engine | dispatched s | single-level s | dispatched / single |")
print("|---|---|---|---|---|")
for level in sys.argv[1:]:
    times = {}
    for kind in ("dispatched", "single"):
        for path in glob.glob(f"out/dispatch/{kind}_{level}_*.json"):
            for b in json.load(open(path))["benchmarks"]:
                engine = b["run_name"].split("/")[2]
                times.setdefault((kind, engine), []).append(b["seconds"])
    for engine in ("wavefront", "megakernel"):
        d = statistics.median(times[("dispatched", engine)])
        s = statistics.median(times[("single", engine)])
        print(f"| {level} | {engine} | {d:.3f} | {s:.3f} | {d / s:.3f} |")
PY
