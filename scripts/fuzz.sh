#!/usr/bin/env bash
# Fuzzes the COLLADA loader (tests/fuzz/fuzz_collada_loader.cpp) with libFuzzer
# for MINUTES minutes: builds build-fuzz/ with clang, ASan and UBSan, grows
# build-fuzz/fuzz-corpus/ from the seeds in tests/fuzz/corpus/ and
# tests/fuzz/regressions/, and keeps going after a finding (fork mode); each
# crash, timeout or out-of-memory input lands in build-fuzz/fuzz-artifacts/.
# Fix it, then copy it into tests/fuzz/regressions/ (ctest fuzz_regressions
# replays them). Usage: scripts/fuzz.sh [MINUTES=10] [extra libFuzzer flags]
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=${1:-10}
shift $(( $# > 0 ? 1 : 0 ))

cmake -S . -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Release \
  -DPT_FUZZ=ON -DPT_BUILD_TESTS=ON -DPT_BUILD_BENCH=OFF >/dev/null
cmake --build build-fuzz --target fuzz_collada_loader

mkdir -p build-fuzz/fuzz-corpus build-fuzz/fuzz-artifacts
log=build-fuzz/fuzz-$(date +%Y%m%d-%H%M%S).log
echo "fuzz.sh: ${minutes} min, log in ${log}"
# -timeout: a hang is any input taking over 10 s; -rss_limit_mb/-malloc_limit_mb:
# an input that makes the loader allocate 2 GiB is a finding, not a slow test.
status=0
ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=0 \
./build-fuzz/tests/fuzz/fuzz_collada_loader build-fuzz/fuzz-corpus tests/fuzz/corpus tests/fuzz/regressions \
  -dict=tests/fuzz/collada.dict -max_len=16384 -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
  -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
  -artifact_prefix=build-fuzz/fuzz-artifacts/ -max_total_time=$((minutes * 60)) -print_final_stats=1 "$@" \
  >"$log" 2>&1 || status=$?
grep -E "^#[0-9]+: cov|DONE|Done|stat::" "$log" | tail -n 3 || true
echo "fuzz.sh: findings in build-fuzz/fuzz-artifacts/: $(ls build-fuzz/fuzz-artifacts | wc -l) (exit status ${status})"
