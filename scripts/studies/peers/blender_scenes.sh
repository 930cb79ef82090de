#!/usr/bin/env bash
# Blender's own exports against Cycles: builds the test scenes in Blender
# (blender_scenes.py), exports each with Blender's COLLADA exporter, renders
# it with Cycles in two halves (two seeds), renders the exported .dae with
# this renderer, and compares (compare_blender.py: image means within 1%, 8x8
# block ratios within the spread of Cycles' two halves). Prints one line per
# scene with the command behind each figure; OUT/summary.txt keeps them.
# Blender (Debian's `blender`, 3.4) is installed on demand; CI never runs this:
# the exports are committed as tests/data/blender/*.dae.
#
# Usage: bash scripts/studies/peers/blender_scenes.sh [--scenes "point_smooth ..."] [--cycles-spp 512]
#        [--ours-spp 2048] [--depth 4] [--threads 2] [--out out/blender] [--copy-exports]
set -euo pipefail
cd "$(dirname "$0")/../.."

scenes="point_smooth sun_flat_emissive spot_blend area_shapes room_horizontal_fit"
cycles_spp=512 ours_spp=2048 depth=4 threads=2 out=out/blender copy=0
while [ $# -gt 0 ]; do
  case "$1" in
    --scenes) scenes=$2; shift ;;
    --cycles-spp) cycles_spp=$2; shift ;;
    --ours-spp) ours_spp=$2; shift ;;
    --depth) depth=$2; shift ;;
    --threads) threads=$2; shift ;;
    --out) out=$2; shift ;;
    --copy-exports) copy=1 ;;
    *) echo "usage: see the header of $0" >&2; exit 2 ;;
  esac
  shift
done
python=/usr/bin/python3   # Debian's interpreter, with numpy

if ! command -v blender > /dev/null; then
  echo "blender_scenes.sh: installing Debian's blender (once)" >&2
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends blender
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$(nproc)" --target pathtracer > /dev/null
pathtracer=build/cli/pathtracer
mkdir -p "$out"
: > "$out/summary.txt"
status=0
for scene in $scenes; do
  blender -b --factory-startup --python scripts/studies/peers/blender_scenes.py -- "$out" --scenes "$scene" \
    --samples "$cycles_spp" --seeds 1,2 --max-depth "$depth" --threads "$threads" > "$out/$scene.blender.log" 2>&1
  size=$(grep -o '([0-9]*x[0-9]*)' "$out/$scene.blender.log" | head -1 | tr -d '()')
  cmd="$pathtracer -q -t $threads -s $ours_spp -m $depth -r ${size%x*} ${size#*x} -f $out/${scene}_ours.pfm $out/$scene.dae"
  $cmd 2> "$out/$scene.warnings.txt"
  line=$($python scripts/studies/peers/compare_blender.py "$out/${scene}_ours.pfm" "$out/${scene}_cycles_seed1.pfm" \
    "$out/${scene}_cycles_seed2.pfm" --json "$out/$scene.json") || status=1
  echo "$line" | tee -a "$out/summary.txt"
  echo "  ours: $cmd; Cycles: 2 x $cycles_spp spp, max_bounces $((depth - 1))" | tee -a "$out/summary.txt"
  [ "$copy" -eq 1 ] && cp "$out/$scene.dae" tests/data/blender/
done
exit $status
