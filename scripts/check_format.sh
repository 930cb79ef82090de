#!/usr/bin/env bash
# The C++ files are formatted as .clang-format says (Debian 12's clang-format,
# version 14). Prints each difference and exits 1 if any file is not.
#   bash scripts/check_format.sh          every tracked .h and .cpp (what CI runs)
#   bash scripts/check_format.sh BASE     the files changed since commit BASE
#   bash scripts/check_format.sh --fix    formats every tracked file in place
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format > /dev/null || { echo "check_format: clang-format is missing (scripts/install_deps.sh installs it)" >&2; exit 2; }
fix=0
files=()
if [ "${1:-}" = --fix ]; then
  fix=1
  mapfile -t files < <(git ls-files '*.h' '*.cpp')
elif [ $# -eq 1 ]; then
  mapfile -t files < <(git diff --name-only --diff-filter=ACMR "$1" -- '*.h' '*.cpp')
else
  mapfile -t files < <(git ls-files '*.h' '*.cpp')
fi
if [ ${#files[@]} -eq 0 ]; then
  echo "check_format: no C++ file to check"
  exit 0
fi
if [ $fix = 1 ]; then
  clang-format -i "${files[@]}"
  echo "check_format: formatted ${#files[@]} files"
elif clang-format --dry-run --Werror "${files[@]}"; then
  echo "check_format: ${#files[@]} files formatted as .clang-format says"
else
  echo "check_format: run 'bash scripts/check_format.sh --fix'" >&2
  exit 1
fi
