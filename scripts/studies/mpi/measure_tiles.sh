#!/usr/bin/env bash
# Measures what scripts/studies/mpi/scaling_model.py needs, on this machine:
# every tile's render time for CBbunny at 1920x1080, -s SPP (default 16) -l 4
# -m 5, one thread, at tile sizes 16, 32, 64 and 128 (tile sets written by
# --shard 0/1, which record each tile's seconds); one process's start-up (scene
# load and BVH build: a 1x1 render) and mpirun's start-up with 2 ranks
# (MPI_Init and MPI_Finalize around --list-isa), 5 alternating pairs. Writes
# out/mpi/measurements.json with the host record (scaling_model.py measure).
#   bash scripts/studies/mpi/measure_tiles.sh [SPP]
set -euo pipefail
cd "$(dirname "$0")/../../.."
spp=${1:-16}
scene=${PT_SCENE:-../shared/scenes/cs184/CBbunny.dae}
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$(nproc)" --target pathtracer > /dev/null
bin=$PWD/build/cli/pathtracer
mkdir -p out/mpi
for tile in 16 32 64 128; do
  "$bin" "$scene" -r 1920 1080 -s "$spp" -l 4 -m 5 -a 64 0 -t 1 --tile "$tile" --shard 0/1 -q \
    -f "out/mpi/tiles_$tile.tiles"
  echo "measure_tiles: tile $tile done"
done
/usr/bin/python3 scripts/studies/mpi/scaling_model.py measure "$spp" "$bin" "$scene" out/mpi/measurements.json \
  --command "bash scripts/studies/mpi/measure_tiles.sh $spp"
cat out/mpi/measurements.json
