#!/usr/bin/env bash
# The benchmarks in one command (Release build in build/, any generator). Each
# run's JSON is wrapped in a results record with this host and the command
# (scripts/results.py wrap; results/README.md) in out/, and tables come from
# scripts/bench_tables.py:
#   bash scripts/bench.sh trace [--quick] [bench_trace flags]   this BVH4 against Embree on every scene and ray set,
#                                                               median of 5 (--quick: two small scenes, one short
#                                                               run); prints a summary (per scene and ray set: ours,
#                                                               Embree's best with its method, the ratio) and writes
#                                                               every rate to out/bench_table.md
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
python=/usr/bin/python3  # Debian's interpreter (scripts/README.md)
tables="$python scripts/bench_tables.py"
# wrap RAW OUT KIND LEVEL TITLE COMMAND: RAW's Google Benchmark JSON in a results record (results/README.md).
wrap() { $python scripts/results.py wrap "$1" "$2" --kind "$3" --isa "$4" --title "$5" --command "$6" && rm -f "$1"; }
widest_level() { ./build/cli/pathtracer --list-isa | awk '$5 == "auto" {print $1}'; }
build() { cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null && cmake --build build -j "$(nproc)" --target "$@" > /dev/null; }
levels_this_cpu() { ./build/cli/pathtracer --list-isa | awk '$4 == "supported" {print $1}'; }
mkdir -p out
command=${1:-}
shift || true
case "$command" in
  trace)
    build bench_trace trace_rays pathtracer
    # Repetitions interleaved in random order, so that a neighbour's load on a shared machine,
    # which comes and goes, falls on this BVH4's runs and on Embree's alike.
    repeat=(--benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
            --benchmark_report_aggregates_only=true --benchmark_min_time=0.3)
    for arg in "$@"; do [ "$arg" = "--quick" ] && repeat=(--benchmark_min_time=0.02); done
    level=${PT_ISA:-$(widest_level)}
    command="PT_ISA=$level ./build/bench/bench_trace $* ${repeat[*]}"
    echo "bench.sh trace: $command (Google Benchmark's log: out/bench_trace.log)" >&2
    PT_ISA=$level ./build/bench/bench_trace "$@" "${repeat[@]}" --benchmark_out=out/bench_raw.json \
      --benchmark_out_format=json > out/bench_trace.log 2>&1 || { tail -20 out/bench_trace.log >&2; exit 1; }
    wrap out/bench_raw.json out/bench.json bench_trace "$level" \
      "bench_trace at $level: this BVH4 and Embree on every scene and ray set" "$command"
    $tables summary out/bench.json
    $tables trace out/bench.json > out/bench_table.md
    echo
    echo "every rate: out/bench_table.md; the run with its host and command: out/bench.json" \
         "(to keep it: results/bench_trace/, then $python scripts/results.py tables)" ;;
  render)
    reps=${1:-3}
    shift || true
    build bench_render pathtracer
    level=${PT_ISA:-$(widest_level)}
    command="PT_ISA=$level ./build/bench/bench_render --benchmark_repetitions=$reps --benchmark_enable_random_interleaving=true $*"
    PT_ISA=$level ./build/bench/bench_render --benchmark_repetitions="$reps" --benchmark_enable_random_interleaving=true \
      --benchmark_out=out/bench_render_raw.json --benchmark_out_format=json "$@"
    wrap out/bench_render_raw.json out/bench_render.json bench_render "$level" "bench_render: whole renders by engine" \
      "$command"
    $tables render out/bench_render.json | tee out/bench_render_table.md ;;
  levels)
    reps=${1:-3} scenes=${2:-'CBbunny|bunny|CBcoil|CBbunny_x16'}
    build bench_trace bench_render pathtracer
    mkdir -p out/levels
    mapfile -t levels < <(levels_this_cpu)
    for level in "${levels[@]}"; do
      echo "bench.sh levels: $level"
      args=(--benchmark_filter="^(trace|build)/($scenes)/" --benchmark_repetitions="$reps"
            --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true --benchmark_min_time=0.3)
      PT_ISA=$level ./build/bench/bench_trace "${args[@]}" \
        --benchmark_out="out/levels/trace_$level.raw.json" --benchmark_out_format=json > /dev/null
      wrap "out/levels/trace_$level.raw.json" "out/levels/trace_$level.json" bench_trace "$level" \
        "bench_trace at $level (bench.sh levels)" "PT_ISA=$level ./build/bench/bench_trace ${args[*]}"
    done
    for ((r = 0; r < reps; ++r)); do  # renders interleaved across levels
      for level in "${levels[@]}"; do
        filter='CBbunny.dae/(wavefront|megakernel|reference)/'
        PT_ISA=$level ./build/bench/bench_render --benchmark_filter="$filter" \
          --benchmark_out="out/levels/render_${level}_$r.raw.json" --benchmark_out_format=json > /dev/null
        wrap "out/levels/render_${level}_$r.raw.json" "out/levels/render_${level}_$r.json" bench_render "$level" \
          "bench_render at $level, round $r (bench.sh levels)" "PT_ISA=$level ./build/bench/bench_render --benchmark_filter='$filter'"
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
          --benchmark_out="out/dispatch/dispatched_${level}_$r.raw.json" --benchmark_out_format=json > /dev/null
        wrap "out/dispatch/dispatched_${level}_$r.raw.json" "out/dispatch/dispatched_${level}_$r.json" bench_render \
          "$level" "bench_render, the dispatched binary at $level, round $r" \
          "PT_ISA=$level ./build/bench/bench_render --benchmark_filter='$filter'"
        "./build-single-$level/bench/bench_render" --benchmark_filter="$filter" \
          --benchmark_out="out/dispatch/single_${level}_$r.raw.json" --benchmark_out_format=json > /dev/null
        wrap "out/dispatch/single_${level}_$r.raw.json" "out/dispatch/single_${level}_$r.json" bench_render \
          "$level" "bench_render, a build for $level alone (-march=${march[$level]}), round $r" \
          "./build-single-$level/bench/bench_render --benchmark_filter='$filter'"
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
    $tables rayfiles | tee out/rayfiles/table.md
    $python scripts/results.py collect-rayfiles out/rayfiles out/rayfiles/results.json \
      --command "bash scripts/bench.sh rayfiles $rounds '$scenes'" ;;
  *)
    sed -n '2,19p' "$0" >&2
    exit 2 ;;
esac
