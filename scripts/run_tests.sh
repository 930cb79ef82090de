#!/usr/bin/env bash
# Second command of the README: build and run the whole test suite with ctest
# (Release), then again in an AddressSanitizer + UndefinedBehaviorSanitizer
# build (build-asan/, -O1, no benchmarks), which includes the replay of the
# fuzz regression files. Installs missing dependencies first, so it also works
# on a fresh machine. PT_SKIP_SANITIZERS=1 stops after the Release tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build
ctest --test-dir build --output-on-failure -j "$(nproc)"

if [ "${PT_SKIP_SANITIZERS:-0}" = 1 ]; then exit 0; fi
start=$(date +%s)
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DPT_SANITIZE=ON -DPT_BUILD_BENCH=OFF
cmake --build build-asan
# Left out under the sanitizers (they run in Release above): the tests that
# take over 5 s there, measured at 3-30x their Release time (statistical
# renders, furnaces, the large BVH scenes, a SIGINT timed against a render).
slow='^(WhiteFurnace|EstimatorAgreement|EmitterFormFactor|EngineAgreement|Determinism|Resume|CommandLine)\.'
slow+='|^Public/BvhSceneTest\.ClosestHitsAndOcclusionEqualBruteForce/(bunny|CBbunny|CBcoil|cow|beetle)( |$)'
slow+='|^(ThreadDeterminism\.CornellSceneWithAdaptiveSampling|RandomNumbers\.NoTwoPathsShareAllTheirNumbers'
slow+='|SkyFurnace\.PlaneUnderUniformSkyHasRadianceRhoTimesLs|AdaptiveSampling\.StopsOnBatchBoundaries.*'
slow+='|AdaptiveSampling\.NoisyPixelsAreSampledToTheMaximum)$'
ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -E "$slow"
echo "run_tests: sanitizer build and tests took $(( $(date +%s) - start )) s"
