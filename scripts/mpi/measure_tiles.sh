#!/usr/bin/env bash
# Measures what scripts/mpi/scaling_model.py needs, on this machine: every
# tile's render time for CBbunny at 1920x1080, -s SPP (default 16) -l 4 -m 5,
# one thread, at tile sizes 16, 32, 64 and 128 (tile sets written by
# --shard 0/1, which record each tile's seconds); one process's start-up
# (scene load and BVH build: a 1x1 render); and mpirun's start-up with 2
# ranks (MPI_Init and MPI_Finalize around --list-isa). Writes out/mpi/.
#   bash scripts/mpi/measure_tiles.sh [SPP]
set -euo pipefail
cd "$(dirname "$0")/../.."
spp=${1:-16}
scene=${PT_SCENE:-../shared/scenes/cs184/CBbunny.dae}
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$(nproc)" --target pathtracer > /dev/null
bin=$PWD/build/cli/pathtracer
mkdir -p out/mpi
seconds() { local s e; s=$(date +%s.%N); "$@" > /dev/null; e=$(date +%s.%N); echo "$e - $s" | bc; }
startup=()
mpi_startup=()
for i in 1 2 3 4 5; do
  startup+=("$(seconds "$bin" "$scene" -r 1 1 -s 1 -t 1 -q -f out/mpi/startup.png)")
  mpi_startup+=("$(seconds mpirun --oversubscribe --mca pml ob1 --mca btl self,vader -np 2 "$bin" --list-isa)")
done
for tile in 16 32 64 128; do
  "$bin" "$scene" -r 1920 1080 -s "$spp" -l 4 -m 5 -a 64 0 -t 1 --tile "$tile" --shard 0/1 -q \
    -f "out/mpi/tiles_$tile.tiles"
  echo "measure_tiles: tile $tile done"
done
/usr/bin/python3 - "$spp" "${startup[*]}" "${mpi_startup[*]}" <<'PY'
import json, statistics, sys
spp, startup, mpi = int(sys.argv[1]), [float(x) for x in sys.argv[2].split()], [float(x) for x in sys.argv[3].split()]
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
avx512 = " avx512f" in open("/proc/cpuinfo").read()
json.dump({"spp": spp, "process_startup_s": statistics.median(startup), "mpirun_startup_2_ranks_s": statistics.median(mpi),
           "cpu": cpu + (" with AVX-512" if avx512 else " without AVX-512 (AVX2 + FMA)"),
           "tile_sets": {t: f"out/mpi/tiles_{t}.tiles" for t in (16, 32, 64, 128)}},
          open("out/mpi/measurements.json", "w"), indent=1)
print(open("out/mpi/measurements.json").read())
PY
