#!/usr/bin/env bash
# This renderer against Blender's Cycles on the shared CS184 scenes, rerunnable
# by anyone: each scene is exported as this renderer reads it
# (pathtracer --export-scene), built in Blender and rendered with Cycles under
# matched settings (cycles_render.py says what is matched, and refuses what
# cannot be); then, per scene:
#   - a converged Cycles render is compared with this renderer's converged
#     reference (scripts/studies/convergence/make_reference.sh): image mean and 8x8 blocks;
#   - ROUNDS rounds, alternating which renderer goes first, of Cycles at
#     16 / 64 / 256 spp and this renderer at 1, 2, 4, ..., 1024 spp (its
#     default flags plus any given after --), each count a render of its own
#     for both, timed on the same machine;
#   - compare_cycles.py prints the equal-error time ratios and draws the
#     error-against-time chart (OUT/<scene>.png).
# Blender (Debian's `blender`, 3.4) is installed on demand; CI never runs this.
#
# Usage: bash scripts/studies/peers/cycles.sh [--scenes "CBbunny CBspheres_lambertian"] [--size 320x240]
#        [--depth 5] [--threads 2] [--rounds 3] [--converged-spp 4096] [--ref-spp 16384]
#        [--out out/peers] [-- PATHTRACER FLAGS]
set -euo pipefail
cd "$(dirname "$0")/../../.."

scenes="CBspheres_lambertian CBbunny CBempty CBgems CBcoil bunny cow beetle teapot banana"
size=320x240 depth=5 threads=2 rounds=3 converged_spp=4096 ref_spp=16384 out=out/peers
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --scenes) scenes=$2; shift ;;
    --size) size=$2; shift ;;
    --depth) depth=$2; shift ;;
    --threads) threads=$2; shift ;;
    --rounds) rounds=$2; shift ;;
    --converged-spp) converged_spp=$2; shift ;;
    --ref-spp) ref_spp=$2; shift ;;
    --out) out=$2; shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "usage: see the header of $0" >&2; exit 2 ;;
  esac
  shift
done
width=${size%x*} height=${size#*x}
scene_dir=../shared/scenes/cs184
python=/usr/bin/python3   # Debian's interpreter, with numpy and matplotlib

if ! command -v blender > /dev/null; then
  echo "cycles.sh: installing Debian's blender (once)" >&2
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
{
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores," \
       "$(grep -q avx512f /proc/cpuinfo && echo AVX-512 || echo 'no AVX-512')"
  echo "blender: $(blender --version 2> /dev/null | head -1)"
  echo "commit: $(git rev-parse --short HEAD 2> /dev/null || echo unknown)"
  echo "settings: ${width}x${height}, -m $depth, -t $threads, $rounds rounds; ours: defaults ${extra[*]:-}"
  echo "load at start: $(cut -d' ' -f1-3 /proc/loadavg)"
} > "$out/run.txt"

blender_render() {  # json dir samples [repeats]
  blender -b --factory-startup --python scripts/studies/peers/cycles_render.py -- "$1" "$2" --samples "$3" \
    --max-depth "$depth" --threads "$threads" --repeats "${4:-1}" 2>&1 | grep -E '^cycles_render' || true
  [ -f "$2/cycles_times.json" ]
}

for scene in $scenes; do
  file="$scene_dir/$scene.dae"
  [ -f "$file" ] || { echo "cycles.sh: $file not found" >&2; exit 1; }
  dir="$out/$scene"
  mkdir -p "$dir"
  "$pathtracer" -q --export-scene "$dir/scene.json" -r "$width" "$height" "$file" 2> /dev/null
  status=0
  blender -b --factory-startup --python scripts/studies/peers/cycles_render.py -- "$dir/scene.json" "$dir/probe" \
    --samples 1 > "$dir/probe.log" 2>&1 || status=$?
  if [ "$status" = 3 ]; then
    grep 'not matched' "$dir/probe.log" | sed 's/^cycles_render: /cycles.sh: skipped: /' | tee -a "$out/run.txt"
    continue
  fi
  [ "$status" = 0 ] || { cat "$dir/probe.log" >&2; exit 1; }
  ref=$(bash scripts/studies/convergence/make_reference.sh "$file" "$width" "$height" "$depth" "$ref_spp" 1000003 "$threads")
  key="$(cat "$dir/scene.json" scripts/studies/peers/cycles_render.py | md5sum | cut -c1-8)_m${depth}_s${converged_spp}"
  if [ ! -f "$dir/cycles_converged_$key.pfm" ]; then
    echo "cycles.sh: $scene: converged Cycles render ($converged_spp spp)" >&2
    blender_render "$dir/scene.json" "$dir/converged" "$converged_spp"
    mv "$dir/converged/cycles_s$converged_spp.pfm" "$dir/cycles_converged_$key.pfm"
  fi
  cp "$dir/cycles_converged_$key.pfm" "$dir/cycles_converged.pfm"
  rm -rf "$dir"/round*
  for r in $(seq 1 "$rounds"); do
    mkdir -p "$dir/round$r"
    # Each sample count rendered from the start (timed as one render of it, with the BVH build), as
    # each of Cycles' counts is its own render.
    ours=("$pathtracer" -q -t "$threads" -m "$depth" -r "$width" "$height" -s 1024 "${extra[@]}"
          --convergence-restart --reference "$ref" --convergence-csv "$dir/round$r/ours.csv" --label ours "$file")
    if (( r % 2 )); then
      "${ours[@]}" 2> /dev/null; blender_render "$dir/scene.json" "$dir/round$r" 16,64,256
    else
      blender_render "$dir/scene.json" "$dir/round$r" 16,64,256; "${ours[@]}" 2> /dev/null
    fi
  done
  "$python" scripts/studies/peers/compare_cycles.py "$dir" "$ref" --chart "$out/$scene.png" --json "$dir/result.json" |
    tee -a "$out/summary.txt"
done
echo "load at end: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/run.txt"
