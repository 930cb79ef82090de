#!/usr/bin/env bash
# MPI overhead on one machine: PAIRS paired alternating runs (default 7;
# scripts/ab.py renders) of `mpirun -np 2` x 1 thread against one process x 2
# threads, CBbunny 480x360 -s 64 -l 4 -m 5 (no adaptive sampling). Prints each
# run's render time (the end report's) and wall time (start to exit, mpirun's
# start-up included), the medians and the median paired ratios, and fails
# unless the two images are equal byte for byte in every pair.
#   bash scripts/studies/mpi/bench_mpi.sh [PAIRS]
set -euo pipefail
cd "$(dirname "$0")/../../.."
pairs=${1:-7}
scene=${PT_SCENE:-../shared/scenes/cs184/CBbunny.dae}
flags="-r 480 360 -s 64 -l 4 -m 5 -a 64 0"
# One machine: shared memory only (Open MPI's default transport probing adds 0.2 s to start-up).
mpirun="mpirun --oversubscribe --mca pml ob1 --mca btl self,vader"
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$(nproc)" --target pathtracer > /dev/null
bin=$PWD/build/cli/pathtracer
echo "cpu: $(lscpu | grep -m1 'Model name' | sed 's/^Model name: *//'); scene: $scene $flags"
/usr/bin/python3 scripts/ab.py renders "$pairs" "$scene" --same-image \
  "single=$bin $flags -t 2" "mpi2=$mpirun -np 2 $bin $flags -t 1"
