#!/usr/bin/env bash
# Speed against accuracy, in one command: builds the pathtracer, renders (or
# reuses) each scene's converged reference, runs every method of methods.txt in
# convergence mode (error against a reference at 1, 2, 4, ... spp, with wall
# time), draws one chart per scene with Debian's python3 + matplotlib and writes
# the efficiency table; full runs also write the memory table of every shared
# scene. Full runs write their data with the host record (results.py record) to
# results/studies/convergence/, the charts to docs/ and the tables into
# docs/speed_and_accuracy.md and docs/architecture.md; --quick (small images,
# few samples: a smoke test) writes only build/convergence_quick/.
#
# Usage: bash scripts/studies/convergence/run_all.sh [--quick] [--scenes "CBbunny bunny"]
#        [--methods FILE --out DIR --baseline NAME]   (a study of other methods, written to DIR only)
# Not part of CI: a full run takes about 8 minutes on 2 cores with cached
# references (each new 320x240 reference takes 5-10 minutes).
set -euo pipefail
cd "$(dirname "$0")/../../.."
here=scripts/studies/convergence
given="$*"   # for the results record's command

quick=0
scenes="CBspheres_lambertian CBbunny CBempty bunny CBgems CBcoil CBspheres_microfacet_al_ag"
all_scenes=1   # the tables in docs/ are only replaced by a run over every scene
methods_file="$here/methods.txt" baseline=default study_out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --scenes) scenes=$2; all_scenes=0; shift ;;
    --methods) methods_file=$2; shift ;;
    --baseline) baseline=$2; shift ;;
    --out) study_out=$2; all_scenes=0; shift ;;
    *) echo "usage: see the header of $0" >&2; exit 2 ;;
  esac
  shift
done

if [ "$quick" = 1 ]; then
  width=80 height=60 max_spp=64 ref_spp=2048 out=build/convergence_quick csv_dir=build/convergence_quick/csv
else
  width=320 height=240 max_spp=512 ref_spp=16384 out=results/studies/convergence csv_dir=build/convergence/csv
fi
charts=$out
[ "$out" = results/studies/convergence ] && charts=docs
if [ -n "$study_out" ]; then out=$study_out charts=$study_out csv_dir=$study_out/csv; fi
depth=5 threads=2
scene_dir=../shared/scenes/cs184
python=/usr/bin/python3   # Debian's interpreter, which has python3-matplotlib (scripts/README.md)
mkdir -p "$out" "$csv_dir"

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$(nproc)" --target pathtracer
pathtracer=build/cli/pathtracer

settings="${width}x${height}, -m $depth, -l 1, -t $threads, 1..$max_spp spp; references $ref_spp spp"
load_start=$(cut -d' ' -f1 /proc/loadavg)

method_lines() { grep -v '^\s*#' "$methods_file" | grep -v '^\s*$'; }

for scene in $scenes; do
  file="$scene_dir/$scene.dae"
  [ -f "$file" ] || { echo "run_all: $file not found" >&2; exit 1; }
  ref=$(bash "$here/make_reference.sh" "$file" "$width" "$height" "$depth" "$ref_spp" 1000003 "$threads")
  combined="$out/convergence_$scene.csv"
  echo "family,method,spp,seconds,rays,rmse,rel_mse,mean_bias,est_rmse,est_rel_rmse" > "$combined.tmp"
  while read -r family label args; do
    read -ra extra <<< "$args"
    common=(-t "$threads" -m "$depth" -l 1 -r "$width" "$height" -s "$max_spp" -q)
    csv="$csv_dir/${scene}_$label.csv"
    echo "run_all: $scene $label" >&2
    "$pathtracer" "${common[@]}" "${extra[@]}" --reference "$ref" --convergence-csv "$csv" --label "$label" \
      "$file"
    tail -n +2 "$csv" | sed "s/^/$family,/" >> "$combined.tmp"
  done < <(method_lines)
  mv "$combined.tmp" "$combined"
  "$python" "$here/plot_convergence.py" "$combined" "$ref" "$charts/convergence_$scene.png" "$baseline"
done
load_end=$(cut -d' ' -f1 /proc/loadavg)
files=(efficiency.md)
for scene in $scenes; do files+=("convergence_$scene.csv"); done

tables=("$python" "$here/efficiency_table.py" --spp-target 64 --reference-spp "$ref_spp" --baseline "$baseline")
for scene in $scenes; do
  ref=$(bash "$here/make_reference.sh" "$scene_dir/$scene.dae" "$width" "$height" "$depth" "$ref_spp" 1000003 "$threads" 2> /dev/null)
  tables+=("$scene=$out/convergence_$scene.csv=$ref")
done
"${tables[@]}" > "$out/efficiency.md"
cat "$out/efficiency.md"
if [ "$quick" = 0 ] && [ "$all_scenes" = 1 ]; then
  "$python" "$here/update_block.py" docs/speed_and_accuracy.md efficiency "$out/efficiency.md"
  "$python" "$here/memory_table.py" "$pathtracer" "$scene_dir" > "$out/memory.md"
  "$python" "$here/update_block.py" docs/architecture.md memory "$out/memory.md"
  files+=(memory.md)
fi
"$python" scripts/results.py record "$out/run.json" --kind study --command "bash $here/run_all.sh $given" \
  --title "Speed against accuracy: error against time per method and scene" --files "${files[@]}" \
  --notes "$settings; load $load_start at the start, $load_end at the end. Charts: $charts/."
