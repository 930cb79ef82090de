#!/usr/bin/env bash
# Converged reference image of one scene for the convergence charts: two
# independent halves of SPP / 2 samples each (MIS direct light, Owen-scrambled
# Sobol, wavefront engine, adaptive sampling off, seeds SEED and SEED + 1),
# averaged into a float PFM, with the per-pixel variance PFM and the noise of
# the average estimated from the halves' difference (combine_reference.py).
# Cached under build/references/, keyed by the scene file's name and checksum
# and every setting; skipped when present. Prints the reference's path.
#
# Usage: make_reference.sh SCENE.dae WIDTH HEIGHT MAX_DEPTH SPP [SEED] [THREADS]
set -euo pipefail
cd "$(dirname "$0")/../../.."

if [ $# -lt 5 ]; then
  echo "usage: $0 SCENE.dae WIDTH HEIGHT MAX_DEPTH SPP [SEED] [THREADS]" >&2
  exit 2
fi
scene=$1 width=$2 height=$3 depth=$4 spp=$5 seed=${6:-1000003} threads=${7:-2}
pathtracer=${PATHTRACER:-build/cli/pathtracer}   # PATHTRACER=... renders with another binary
[ -x "$pathtracer" ] || { echo "make_reference: build $pathtracer first" >&2; exit 1; }

name=$(basename "$scene" .dae)
checksum=$(md5sum "$scene" | cut -c1-8)
key="${name}_${width}x${height}_m${depth}_s${spp}_sobol_mis_seed${seed}_${checksum}"
dir=build/references
out="$dir/$key.pfm"
mkdir -p "$dir"

if [ -f "$out" ] && [ -f "$dir/$key.var.pfm" ] && [ -f "$dir/$key.noise" ]; then
  echo "make_reference: cached $out" >&2
  echo "$out"
  exit 0
fi
echo "make_reference: rendering $out (2 x $((spp / 2)) spp; this takes a while)" >&2
start=$(date +%s)
for half in 1 2; do
  part="$dir/$key.half$half.pfm"
  [ -f "$part" ] && [ -f "${part%.pfm}.var.pfm" ] && continue
  cmd=("$pathtracer" --engine wavefront --sampler sobol --direct mis --rr-mode fixed -t "$threads" -s "$((spp / 2))" -a 64 0 -m "$depth" -l 1
       -r "$width" "$height" --seed "$((seed + half - 1))" -q -f "$part" --variance "${part%.pfm}.var.pfm" "$scene")
  "${cmd[@]}"
  echo "command: ${cmd[*]}" >> "$dir/$key.log"
done
/usr/bin/python3 scripts/studies/convergence/combine_reference.py "$dir/$key.half1.pfm" "$dir/$key.half2.pfm" "$out"
{
  echo "seconds: $(( $(date +%s) - start ))"
  echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
} >> "$dir/$key.log"
echo "$out"
