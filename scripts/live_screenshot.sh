#!/usr/bin/env bash
# The README's picture of the live view: the browser test (tests/browser/
# test_live_view.py, every one of its checks) run on CBbunny at 480x360,
# 64 samples, 5 bounces, keeping its screenshot as docs/live_view.png.
#   bash scripts/live_screenshot.sh [BUILD=build]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
/usr/bin/python3 tests/browser/test_live_view.py --pathtracer "$build/cli/pathtracer" \
  --scene ../shared/scenes/cs184/CBbunny.dae --flags "-r 480 360 -s 64 -m 5" --screenshot docs/live_view.png
