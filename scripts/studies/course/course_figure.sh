#!/usr/bin/env bash
# The figure in docs/cs184_compatibility.md of the course renderer's quirks: renders SCENE (default
# CBbunny) at depth M (default 5) with the settings of the course's image in
# ../shared/refs/course, once in the default (physical) mode and once with
# --cs184-compat, and draws course / default / compat / ratio into
# docs/course_quirks_SCENE_mM.png.
#   bash scripts/studies/course/course_figure.sh [SCENE] [M]
set -euo pipefail
cd "$(dirname "$0")/../../.."
scene=${1:-CBbunny}
m=${2:-5}
refs=../shared/refs/course
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$(nproc)" --target pathtracer > /dev/null
mkdir -p build/course docs
args=(-q -t "$(nproc)" -c "$refs/cam_fullview_${scene}_256x192.txt" -r 256 192 -s 256 -l 4 -m "$m" -a 256 0)
./build/cli/pathtracer "${args[@]}" -f "build/course/${scene}_m${m}_default.pfm" "../shared/scenes/cs184/$scene.dae"
./build/cli/pathtracer "${args[@]}" --cs184-compat -f "build/course/${scene}_m${m}_compat.pfm" \
  "../shared/scenes/cs184/$scene.dae"
/usr/bin/python3 scripts/studies/course/compare_course.py "$refs/course_${scene}_m${m}_s256_l4.png" \
  "build/course/${scene}_m${m}_default.pfm" "build/course/${scene}_m${m}_compat.pfm" "docs/course_quirks_${scene}_m${m}.png"
echo "wrote docs/course_quirks_${scene}_m${m}.png"
