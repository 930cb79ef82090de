#!/usr/bin/env bash
# The benchmarks in one command (Release build in build/, any generator; JSON
# in out/ and a table from scripts/bench_tables.py):
#   bash scripts/bench.sh trace [--quick] [bench_trace flags]   this BVH4 against Embree on every scene and ray set,
#                                                               median of 5 (--quick: two small scenes, one short run)
#   bash scripts/bench.sh render [REPS] [flags]                 whole renders by engine, REPS interleaved runs (3)
#   bash scripts/bench.sh levels [REPS] [SCENE_REGEX]           both at every SIMD level this CPU runs
#   bash scripts/bench.sh dispatch [REPS]                       dispatched binary against single-level builds
#   bash scripts/bench.sh rayfiles [ROUNDS] [SCENE_REGEX]       trace_rays on exported ray files (camera, diffuse and
#                                                               shadow rays in render order), the queue tracer against
#                                                               every Embree method, 1 thread, at each level from AVX2
#                                                               up (NEON on Arm), ROUNDS (2)
# The kernels run at the level PT_ISA names (default: the widest this CPU runs),
# Embree restricted to the same instruction set.
set -euo pipefail
cd "$(dirname "$0")/.."
tables="/usr/bin/python3 scripts/bench_tables.py"
build() { cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null && cmake --build build -j "$(nproc)" --target "$@" > /dev/null; }
levels_this_cpu() { ./build/cli/pathtracer --list-isa | awk '$4 == "supported" {print $1}'; }
mkdir -p out
command=${1:-}
shift || true
case "$command" in
  trace)
    build bench_trace trace_rays
    # Repetitions interleaved in random order, so that a neighbour's load on a shared machine,
    # which comes and goes, falls on this BVH4's runs and on Embree's alike.
    repeat=(--benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
            --benchmark_report_aggregates_only=true --benchmark_min_time=0.3)
    for arg in "$@"; do [ "$arg" = "--quick" ] && repeat=(--benchmark_min_time=0.02); done
    ./build/bench/bench_trace "$@" "${repeat[@]}" --benchmark_out=out/bench.json --benchmark_out_format=json
    $tables trace out/bench.json | tee out/bench_table.md ;;
  render)
    reps=${1:-3}
    shift || true
    build bench_render
    ./build/bench/bench_render --benchmark_repetitions="$reps" --benchmark_enable_random_interleaving=true \
      --benchmark_out=out/bench_render.json --benchmark_out_format=json "$@"
    $tables render out/bench_render.json | tee out/bench_render_table.md ;;
  levels)
    reps=${1:-3} scenes=${2:-'CBbunny|bunny|CBcoil|CBbunny_x16'}
    build bench_trace bench_render pathtracer
    mkdir -p out/levels
    mapfile -t levels < <(levels_this_cpu)
    for level in "${levels[@]}"; do
      echo "bench.sh levels: $level"
      PT_ISA=$level ./build/bench/bench_trace --benchmark_filter="^(trace|build)/($scenes)/" \
        --benchmark_repetitions="$reps" --benchmark_enable_random_interleaving=true \
        --benchmark_report_aggregates_only=true --benchmark_min_time=0.3 \
        --benchmark_out="out/levels/trace_$level.json" --benchmark_out_format=json > /dev/null
    done
    for ((r = 0; r < reps; ++r)); do  # renders interleaved across levels
      for level in "${levels[@]}"; do
        PT_ISA=$level ./build/bench/bench_render --benchmark_filter='CBbunny.dae/(wavefront|megakernel|reference)/' \
          --benchmark_out="out/levels/render_${level}_$r.json" --benchmark_out_format=json > /dev/null
      done
    done
    $tables levels "${levels[@]}" | tee out/levels/table.md ;;
  dispatch)
    reps=${1:-5}
    build bench_render pathtracer
    best=$(./build/cli/pathtracer --list-isa | awk '$5 == "auto" {print $1}')
    declare -A march=([sse4.2]=x86-64-v2 [avx2]=x86-64-v3 [avx512]=x86-64-v4 [neon]=native)
    march[$best]=native
    mapfile -t levels < <(levels_this_cpu)
    for level in "${levels[@]}"; do
      cmake -S . -B "build-single-$level" -DCMAKE_BUILD_TYPE=Release -DPT_NATIVE=ON -DPT_MARCH="${march[$level]}" \
            -DPT_BUILD_TESTS=OFF > /dev/null
      cmake --build "build-single-$level" -j "$(nproc)" --target bench_render > /dev/null
    done
    mkdir -p out/dispatch
    filter='CBbunny.dae/(wavefront|megakernel)/'
    for ((r = 0; r < reps; ++r)); do
      for level in "${levels[@]}"; do
        PT_ISA=$level ./build/bench/bench_render --benchmark_filter="$filter" \
          --benchmark_out="out/dispatch/dispatched_${level}_$r.json" --benchmark_out_format=json > /dev/null
        "./build-single-$level/bench/bench_render" --benchmark_filter="$filter" \
          --benchmark_out="out/dispatch/single_${level}_$r.json" --benchmark_out_format=json > /dev/null
      done
    done
    $tables dispatch "${levels[@]}" | tee out/dispatch/table.md ;;
  rayfiles)
    rounds=${1:-2} scenes=${2:-'CBbunny|CBcoil|CBgems|bunny|teapot|CBbunny_x16|CBbunny_x64'}
    build bench_trace trace_rays pathtracer
    mkdir -p out/rayfiles
    # bench_trace writes every scene's files and then .complete; an interrupted export is redone.
    if [ ! -f out/rayfiles/rays/.complete ]; then
      ./build/bench/bench_trace --export-rays out/rayfiles/rays > /dev/null
      touch out/rayfiles/rays/.complete
    fi
    mapfile -t levels < <(levels_this_cpu | grep -v -x sse4.2 || true)
    mapfile -t files < <(ls out/rayfiles/rays/ | sed -n 's/\.tris$//p' | grep -E -x "$scenes" || true)
    ((${#levels[@]})) || { echo "bench.sh rayfiles: no SIMD level to run" >&2; exit 1; }
    ((${#files[@]})) || { echo "bench.sh rayfiles: no exported scene matches '$scenes'" >&2; exit 1; }
    rm -f out/rayfiles/*.jsonl  # the table is of this run only
    for ((r = 0; r < rounds; ++r)); do  # rounds interleave the levels, so that load that comes and goes hits both
      for level in "${levels[@]}"; do
        for scene in "${files[@]}"; do
          for set in primary diffuse shadow; do
            occluded=(); [ "$set" = shadow ] && occluded=(--occluded)
            PT_ISA=$level ./build/bench/trace_rays "out/rayfiles/rays/$scene.tris" "out/rayfiles/rays/${scene}_$set.rays" \
              "${occluded[@]}" --embree --threads 1 > "out/rayfiles/${level}_${scene}_${set}_$r.jsonl"
          done
        done
      done
    done
    $tables rayfiles | tee out/rayfiles/table.md ;;
  *)
    sed -n '2,14p' "$0" >&2
    exit 2 ;;
esac
