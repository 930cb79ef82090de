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
# Left out under the sanitizers (they run in Release above): tests that take
# tens of seconds of rendering there (about 3x longer here), and two that
# time a cancellation or a signal against the render's progress, which the
# sanitizers' slowdown changes.
slow='^(EngineAgreement\.DifferentSeedsAgreeWithinNoise|Determinism\.ThreadCountAndWaveSizeDoNotChangeTheImage'
slow+='|CommandLine\.SigintWritesAPartialImageAndTheCheckpointResumesExactly'
slow+='|Resume\.FromTheMiddleOfAPassEqualsAnUninterruptedRender)$'
ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -E "$slow"
echo "run_tests: sanitizer build and tests took $(( $(date +%s) - start )) s"
