#!/usr/bin/env bash
# MPI overhead on one machine: PAIRS paired runs (default 7, the order inside
# each pair alternating) of `mpirun -np 2` x 1 thread against one process x 2
# threads, CBbunny 480x360 -s 64 -l 4 -m 5 (no adaptive sampling). Prints each
# pair's wall time (process start to exit, mpirun's start-up included) and
# render time (the end report's), checks the two images are equal byte for
# byte, and prints the medians and the median of the per-pair ratios.
#   bash scripts/mpi/bench_mpi.sh [PAIRS]
set -euo pipefail
cd "$(dirname "$0")/../.."
pairs=${1:-7}
scene=${PT_SCENE:-../shared/scenes/cs184/CBbunny.dae}
flags=(-r 480 360 -s 64 -l 4 -m 5 -a 64 0)
# One machine: shared memory only (Open MPI's default transport probing adds 0.2 s to start-up).
mpirun=(mpirun --oversubscribe --mca pml ob1 --mca btl self,vader)
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$(nproc)" --target pathtracer > /dev/null
bin=$PWD/build/cli/pathtracer
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
run() {  # label command... -> "label wall render"
  local label=$1 start end report
  shift
  start=$(date +%s.%N)
  report=$("$@")
  end=$(date +%s.%N)
  echo "$label $(echo "$end - $start" | bc) $(grep -oP 'Rendered in \K[0-9.]+' <<< "$report")"
}
lscpu | grep -m1 'Model name' | sed 's/^/cpu: /'
grep -q avx512f /proc/cpuinfo && echo "cpu: AVX-512" || echo "cpu: no AVX-512 (AVX2 + FMA)"
echo "scene: $scene ${flags[*]}"
for i in $(seq "$pairs"); do
  one=(run single "$bin" "$scene" "${flags[@]}" -t 2 -f "$out/one.png")
  two=(run mpi2 "${mpirun[@]}" -np 2 "$bin" "$scene" "${flags[@]}" -t 1 -f "$out/two.png")
  if [ $((i % 2)) = 1 ]; then "${one[@]}"; "${two[@]}"; else "${two[@]}"; "${one[@]}"; fi
  cmp -s "$out/one.png" "$out/two.png" || { echo "bench_mpi: the images differ" >&2; exit 1; }
done | tee "$out/runs.txt"
/usr/bin/python3 - "$out/runs.txt" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
single = [r for r in rows if r[0] == "single"]
mpi = [r for r in rows if r[0] == "mpi2"]
def med(rs, k): return statistics.median(float(r[k]) for r in rs)
for k, what in ((1, "wall (start to exit)"), (2, "render (end report)")):
    ratios = [float(m[k]) / float(s[k]) for s, m in zip(single, mpi)]
    print(f"{what}: 1 process x 2 threads {med(single, k):.3f} s, mpirun -np 2 x 1 thread {med(mpi, k):.3f} s, "
          f"median ratio mpi/single {statistics.median(ratios):.3f} (range {min(ratios):.3f}-{max(ratios):.3f})")
print("images equal byte for byte in every pair")
PY
