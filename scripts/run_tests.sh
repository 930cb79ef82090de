#!/usr/bin/env bash
# Second command of the README: build and run the whole test suite.
#  0. The code style: every C++ file formatted as .clang-format says.
#  1. Release build in build/ with CMake's default generator, Unix Makefiles
#     (the standard recipe; a build/ made earlier keeps its generator): every
#     instruction-set level in one binary, with Open MPI, so the mpirun tests
#     run; ctest once per level, each level forced through PT_ISA; a level this
#     CPU cannot run is reported as skipped. The tests labelled `browser` (the
#     live view in headless Chromium) or `once` (long tests of code that is
#     the same at every level) run once after the levels, at the widest.
#  2. AddressSanitizer + UndefinedBehaviorSanitizer build with Clang and Ninja
#     (build-asan/, -O1, -march=native: the CPU's widest level and the native
#     build's path; without MPI: the build everyone without Open MPI gets):
#     every test but those labelled `slow` (over 5 s there; they ran in step 1)
#     or `browser`. Step 1 builds with GCC, so every run builds with both
#     compilers.
#  3. On x86-64: an aarch64 cross build with Ninja (build-aarch64/), whose
#     kernel, BVH, engine-agreement, furnace and loader tests run under
#     qemu-aarch64.
# So every run builds and tests with both generators.
# Tests are chosen by their ctest labels (tests/CMakeLists.txt):
#   --labels REGEX   run only the tests whose labels match, in every step
# Installs missing dependencies first, so it also works on a fresh machine.
# PT_SKIP_SANITIZERS=1 and PT_SKIP_AARCH64=1 leave steps 2 and 3 out.
set -euo pipefail
cd "$(dirname "$0")/.."
labels=()
if [ "${1:-}" = --labels ]; then
  labels=(-L "$2")
  shift 2
fi
[ $# -eq 0 ] || { echo "usage: $0 [--labels REGEX]" >&2; exit 2; }
host=$(uname -m)
if [ "$host" = x86_64 ] && [ "${PT_SKIP_AARCH64:-0}" != 1 ]; then
  bash scripts/install_deps.sh --aarch64
else
  bash scripts/install_deps.sh
fi
summary=()
failed=0

# ------------------------------------------------------------------ 0. Style
if bash scripts/check_format.sh; then
  summary+=("clang-format: every .h and .cpp formatted as .clang-format says")
else
  failed=1
  summary+=("clang-format: FAILED (bash scripts/check_format.sh --fix formats the files)")
fi

# "N tests, P passed, F failed, S skipped" of a ctest log.
ctest_counts() {
  local total failed_n skipped
  total=$(grep -oP 'tests failed out of \K[0-9]+' "$1" | tail -1)
  failed_n=$(grep -oP '[0-9]+(?= tests failed out of)' "$1" | tail -1)
  skipped=$(grep -cE '\*\*\*Skipped|Not Run \(Disabled\)' "$1" || true)
  echo "${total:-0} tests, $(( ${total:-0} - ${failed_n:-0} - skipped )) passed, ${failed_n:-0} failed, $skipped skipped"
}

# ctest in DIR with the label selection; stdin from /dev/null: nothing a test
# runs may read what the calling loop reads.
run_ctest() {  # dir log [ctest args]
  local dir=$1 log=$2
  shift 2
  if ctest --test-dir "$dir" --output-on-failure -j "$(nproc)" "${labels[@]}" "$@" < /dev/null 2>&1 | tee "$log"; then
    :
  else
    failed=1
  fi
}

# --------------------------------------------------------------- 1. Release
generator=()
[ -f build/CMakeCache.txt ] || generator=(-G "Unix Makefiles")
start=$(date +%s)
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)"
echo "run_tests: Release build took $(( $(date +%s) - start )) s ($(grep -oP 'CMAKE_GENERATOR:INTERNAL=\K.*' build/CMakeCache.txt))"
while read -r level lanes _ support _; do
  if [ "$support" != supported ]; then
    echo "run_tests: level $level SKIPPED: this CPU does not run it"
    summary+=("release $level ($lanes lanes): SKIPPED, this CPU does not run it")
    continue
  fi
  echo "run_tests: Release tests at level $level ($lanes lanes)"
  PT_ISA=$level run_ctest build "build/ctest_$level.log" -LE 'browser|once'
  summary+=("release $level ($lanes lanes): $(ctest_counts "build/ctest_$level.log")")
done < <(./build/cli/pathtracer --list-isa)
echo "run_tests: browser tests (the widest level)"
run_ctest build build/ctest_browser.log -L browser -V  # -V: its figures (first frame) and any skip reason in the log
summary+=("browser (headless Chromium): $(ctest_counts build/ctest_browser.log)")
echo "run_tests: tests labelled once (the widest level)"
run_ctest build build/ctest_once.log -L once
summary+=("once (the widest level): $(ctest_counts build/ctest_once.log)")

# ------------------------------------------------------------- 2. Sanitizers
if [ "${PT_SKIP_SANITIZERS:-0}" != 1 ]; then
  start=$(date +%s)
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DPT_SANITIZE=ON -DPT_NATIVE=ON -DPT_BUILD_BENCH=OFF -DPT_MPI=OFF \
        -DCMAKE_CXX_COMPILER=clang++
  cmake --build build-asan
  level=$(./build-asan/cli/pathtracer --list-isa | awk '{print $1}')
  ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1 \
  LSAN_OPTIONS=suppressions="$PWD/tests/support/lsan_suppressions.txt":print_suppressions=0 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    run_ctest build-asan build-asan/ctest.log -LE 'slow|browser'
  summary+=("asan+ubsan (clang) native $level: $(ctest_counts build-asan/ctest.log) (the tests labelled slow or browser left out)")
  echo "run_tests: sanitizer build and tests took $(( $(date +%s) - start )) s"
fi

# ----------------------------------------------------------------- 3. aarch64
if [ "$host" = x86_64 ] && [ "${PT_SKIP_AARCH64:-0}" != 1 ]; then
  start=$(date +%s)
  cmake -S . -B build-aarch64 -G Ninja -DCMAKE_BUILD_TYPE=Release -DPT_BUILD_BENCH=OFF -DPT_MPI=OFF \
        -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake
  # The longest under qemu first (see the shards below).
  programs=(test_engines test_light_transport test_sampling test_isa test_geometry test_loader test_bvh4_build
            test_bvh4_traversal test_bvh4_robustness test_bvh4_batch test_bvh4_queue test_engine_contract)
  rm -rf build-aarch64/qemu
  mkdir -p build-aarch64/qemu
  cmake --build build-aarch64 --target "${programs[@]}"
  # The programs run in GoogleTest shards (GTEST_TOTAL_SHARDS), the longest
  # programs in more of them and first, so that the cores stay busy to the end
  # (test_engines takes about 3 minutes under qemu).
  declare -A shards=([test_light_transport]=2 [test_sampling]=2 [test_engines]=4 [test_engine_contract]=2
                     [test_bvh4_queue]=2)
  jobs=()
  for p in "${programs[@]}"; do
    n=${shards[$p]:-1}
    for ((i = 0; i < n; ++i)); do jobs+=("$p $i $n"); done
  done
  # The tests labelled slow (their names from build/'s ctest) are left out as in step 2,
  # but for test_engines': the NEON engines' agreement with the reference and their
  # determinism. The rest of those programs runs the same NEON paths in less time.
  slow=$(ctest --test-dir build -N -L slow | grep -oP 'Test +#[0-9]+: \K\S+' | paste -sd: -)
  echo "run_tests: aarch64 (neon) tests under qemu-aarch64 (slow ones but test_engines' left out): ${programs[*]}"
  printf '%s\n' "${jobs[@]}" | PT_SLOW_TESTS=$slow xargs -P "$(nproc)" -L 1 sh -c \
    'dir=$(dirname "$(find build-aarch64/tests -name "$0" -type f -executable | head -1)");
     filter=-$PT_SLOW_TESTS; [ "$0" = test_engines ] && filter="*";
     GTEST_TOTAL_SHARDS=$2 GTEST_SHARD_INDEX=$1 timeout 1200 qemu-aarch64 "$dir/$0" --gtest_brief=1 \
       "--gtest_filter=$filter" > "build-aarch64/qemu/$0.$1.log" 2>&1; echo $? > "build-aarch64/qemu/$0.$1.status"'
  passed=0 failed_n=0 skipped=0
  for p in "${programs[@]}"; do
    for log in build-aarch64/qemu/$p.*.log; do
      n=$(grep -oP '\[  PASSED  \] \K[0-9]+' "$log" || echo 0)
      # --gtest_brief prints one '[  FAILED  ] Suite.Test (N ms)' line per failure and no failure total
      f=$(grep -cP '^\[  FAILED  \] \S+ \([0-9]+ ms\)$' "$log" || true)
      s=$(grep -oP '\[  SKIPPED \] \K[0-9]+(?= tests?\.)' "$log" || echo 0)
      passed=$((passed + n)) failed_n=$((failed_n + f)) skipped=$((skipped + s))
      if [ "$(cat "${log%.log}.status")" != 0 ]; then
        failed=1
        echo "run_tests: aarch64 $p FAILED ($log):"
        cat "$log"
      fi
    done
  done
  summary+=("aarch64 neon (qemu, ${#programs[@]} test programs): $((passed + failed_n + skipped)) tests, $passed passed, $failed_n failed, $skipped skipped")
  echo "run_tests: aarch64 build and tests took $(( $(date +%s) - start )) s"
fi

echo "run_tests: summary"
printf '  %s\n' "${summary[@]}"
exit $failed
