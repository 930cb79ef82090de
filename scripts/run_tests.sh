#!/usr/bin/env bash
# Second command of the README: build and run the whole test suite.
#  1. Release build (every instruction-set level in one binary, with Open MPI:
#     the mpirun tests run); ctest once per level, each level forced through
#     PT_ISA; a level this CPU cannot run is reported as skipped.
#  2. AddressSanitizer + UndefinedBehaviorSanitizer build (build-asan/, -O1,
#     -march=native: the CPU's widest level, and the native build's path;
#     without MPI: the build everyone without Open MPI gets), with the replay
#     of the fuzz regression files.
#  3. On x86-64: an aarch64 cross build (build-aarch64/), whose kernel, BVH,
#     engine-agreement, furnace and loader tests run under qemu-aarch64.
# Installs missing dependencies first, so it also works on a fresh machine.
# PT_SKIP_SANITIZERS=1 and PT_SKIP_AARCH64=1 leave steps 2 and 3 out.
set -euo pipefail
cd "$(dirname "$0")/.."
host=$(uname -m)
if [ "$host" = x86_64 ] && [ "${PT_SKIP_AARCH64:-0}" != 1 ]; then
  bash scripts/install_deps.sh --aarch64
else
  bash scripts/install_deps.sh
fi
summary=()
failed=0

# "N tests, P passed, F failed, S skipped" of a ctest log.
ctest_counts() {
  local total failed_n skipped
  total=$(grep -oP 'tests failed out of \K[0-9]+' "$1" | tail -1)
  failed_n=$(grep -oP '[0-9]+(?= tests failed out of)' "$1" | tail -1)
  skipped=$(grep -cE '\*\*\*Skipped|Not Run \(Disabled\)' "$1" || true)
  echo "${total:-0} tests, $(( ${total:-0} - ${failed_n:-0} - skipped )) passed, ${failed_n:-0} failed, $skipped skipped"
}

# ---------------------------------------------------------------- 1. Release
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build
while read -r level lanes _ support _; do
  if [ "$support" != supported ]; then
    echo "run_tests: level $level SKIPPED: this CPU does not run it"
    summary+=("release $level ($lanes lanes): SKIPPED, this CPU does not run it")
    continue
  fi
  echo "run_tests: Release tests at level $level ($lanes lanes)"
  log=build/ctest_$level.log
  # stdin from /dev/null: nothing a test runs may read the level list this loop reads
  if PT_ISA=$level ctest --test-dir build --output-on-failure -j "$(nproc)" < /dev/null 2>&1 | tee "$log"; then :; else
    failed=1
  fi
  summary+=("release $level ($lanes lanes): $(ctest_counts "$log")")
done < <(./build/io/cli/pathtracer --list-isa)

# ------------------------------------------------------------- 2. Sanitizers
if [ "${PT_SKIP_SANITIZERS:-0}" != 1 ]; then
  start=$(date +%s)
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DPT_SANITIZE=ON -DPT_NATIVE=ON -DPT_BUILD_BENCH=OFF -DPT_MPI=OFF
  cmake --build build-asan
  # Left out under the sanitizers (they run in Release above): the tests that
  # take over 5 s there, measured at 3-30x their Release time (statistical
  # renders, furnaces, the large BVH scenes, a SIGINT timed against a render).
  slow='^(WhiteFurnace|EstimatorAgreement|EmitterFormFactor|EngineAgreement|Determinism|Resume|CommandLine|CourseImages)\.'
  slow+='|^Public/BvhSceneTest\.ClosestHitsAndOcclusionEqualBruteForce/(bunny|CBbunny|CBcoil|cow|beetle)( |$)'
  slow+='|^(ThreadDeterminism\.CornellSceneWithAdaptiveSampling|RandomNumbers\.NoTwoPathsShareAllTheirNumbers'
  slow+='|SkyFurnace\.PlaneUnderUniformSkyHasRadianceRhoTimesLs|AdaptiveSampling\.StopsOnlyAtChecks.*'
  slow+='|AdaptiveSampling\.NoisyPixelsAreSampledToTheMaximum|Sobol\.HashScramblingHasTheErrorOfTrueOwenScrambling'
  slow+='|Sobol\.ErrorAtAStepInRadianceFallsFasterThanIndependentSampling)$'
  level=$(./build-asan/io/cli/pathtracer --list-isa | awk '{print $1}')
  log=build-asan/ctest.log
  if ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1 \
     LSAN_OPTIONS=suppressions="$PWD/scripts/build/lsan_suppressions.txt":print_suppressions=0 \
     UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
     ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -E "$slow" 2>&1 | tee "$log"; then :; else failed=1; fi
  summary+=("asan+ubsan native $level: $(ctest_counts "$log") (the slow statistical tests left out)")
  echo "run_tests: sanitizer build and tests took $(( $(date +%s) - start )) s"
fi

# ----------------------------------------------------------------- 3. aarch64
if [ "$host" = x86_64 ] && [ "${PT_SKIP_AARCH64:-0}" != 1 ]; then
  start=$(date +%s)
  cmake -S . -B build-aarch64 -G Ninja -DCMAKE_BUILD_TYPE=Release -DPT_BUILD_BENCH=OFF -DPT_MPI=OFF \
        -DCMAKE_TOOLCHAIN_FILE=scripts/build/aarch64-linux-gnu.cmake
  programs=(test_isa test_sampling test_geometry test_loader test_bvh4_build test_bvh4_traversal test_bvh4_robustness
            test_bvh4_batch test_engines test_light_transport test_engine_contract)
  mkdir -p build-aarch64/qemu
  cmake --build build-aarch64 --target "${programs[@]}"
  echo "run_tests: aarch64 (neon) tests under qemu-aarch64: ${programs[*]}"
  printf '%s\n' "${programs[@]}" | xargs -P "$(nproc)" -I{} sh -c \
    'timeout 1200 qemu-aarch64 build-aarch64/tests/{} --gtest_brief=1 > build-aarch64/qemu/{}.log 2>&1; echo $? > build-aarch64/qemu/{}.status'
  passed=0 failed_n=0 skipped=0
  for p in "${programs[@]}"; do
    log=build-aarch64/qemu/$p.log
    n=$(grep -oP '\[  PASSED  \] \K[0-9]+' "$log" || echo 0)
    # --gtest_brief prints one '[  FAILED  ] Suite.Test (N ms)' line per failure and no failure total
    f=$(grep -cP '^\[  FAILED  \] \S+ \([0-9]+ ms\)$' "$log" || true)
    s=$(grep -oP '\[  SKIPPED \] \K[0-9]+(?= tests?,)' "$log" || echo 0)
    passed=$((passed + n)) failed_n=$((failed_n + f)) skipped=$((skipped + s))
    if [ "$(cat build-aarch64/qemu/$p.status)" != 0 ]; then
      failed=1
      echo "run_tests: aarch64 $p FAILED:"
      cat "$log"
    fi
  done
  summary+=("aarch64 neon (qemu, ${#programs[@]} test programs): $((passed + failed_n + skipped)) tests, $passed passed, $failed_n failed, $skipped skipped")
  echo "run_tests: aarch64 build and tests took $(( $(date +%s) - start )) s"
fi

echo "run_tests: summary"
printf '  %s\n' "${summary[@]}"
exit $failed
