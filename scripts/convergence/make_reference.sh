#!/usr/bin/env bash
# Converged reference image of one scene for the convergence charts: a render at
# a very high sample count (light sampling, wavefront engine, adaptive sampling
# off, its own seed) stored as a float PFM plus its per-pixel variance PFM and
# the render's log. Cached under build/references/, keyed by the scene file's
# name and checksum and every setting; skipped when already present.
# Prints the path of the reference PFM on stdout.
#
# Usage: make_reference.sh SCENE.dae WIDTH HEIGHT MAX_DEPTH SPP [SEED] [THREADS]
set -euo pipefail
cd "$(dirname "$0")/../.."

if [ $# -lt 5 ]; then
  echo "usage: $0 SCENE.dae WIDTH HEIGHT MAX_DEPTH SPP [SEED] [THREADS]" >&2
  exit 2
fi
scene=$1 width=$2 height=$3 depth=$4 spp=$5 seed=${6:-1000003} threads=${7:-2}
pathtracer=build/io/cli/pathtracer
[ -x "$pathtracer" ] || { echo "make_reference: build $pathtracer first" >&2; exit 1; }

name=$(basename "$scene" .dae)
checksum=$(md5sum "$scene" | cut -c1-8)
key="${name}_${width}x${height}_m${depth}_s${spp}_seed${seed}_${checksum}"
dir=build/references
out="$dir/$key.pfm" var="$dir/$key.var.pfm" log="$dir/$key.log"
mkdir -p "$dir"

if [ -f "$out" ] && [ -f "$var" ]; then
  echo "make_reference: cached $out" >&2
else
  echo "make_reference: rendering $out ($spp spp; this takes a while)" >&2
  cmd=("$pathtracer" --engine wavefront -t "$threads" -s "$spp" -a 64 0 -m "$depth" -l 1
       -r "$width" "$height" --seed "$seed" -q -f "$out" --variance "$var" "$scene")
  start=$(date +%s)
  "${cmd[@]}"
  {
    echo "command: ${cmd[*]}"
    echo "seconds: $(( $(date +%s) - start ))"
    echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
  } > "$log"
fi
echo "$out"
