#!/usr/bin/env bash
# The dispatched binaries on CPUs this machine is not: under qemu-x86_64 with
# an SSE4.2-only CPU (Nehalem) and one with AVX2 but no AVX-512 (qemu's
# "max"), the pathtracer must pick that CPU's widest level by itself, run
# without an illegal instruction (no wider code leaks into the code compiled
# once, or into a narrower level, through a shared inline function), and
# render the image the native run makes at that level, bit for bit; the
# level detection and SIMD primitive tests must pass there too.
#   emulated_cpus.sh PATHTRACER TEST_SAMPLING TEST_ISA OUT_DIR
# Exit 77 (skipped) without qemu-x86_64 or on a non-x86-64 host.
set -euo pipefail
pathtracer=$1 test_sampling=$2 test_isa=$3 out=$4
if [ "$(uname -m)" != x86_64 ] || ! command -v qemu-x86_64 > /dev/null; then
  echo "skipped: needs qemu-x86_64 (package qemu-user) on an x86-64 host"
  exit 77
fi
mkdir -p "$out"
unset PT_ISA  # auto: the emulated CPU picks its level
render=(-r 48 36 -s 4 -l 2 -m 3 -t 2 -a 2 0.05 --seed 7)
status=0
for pair in Nehalem-v1:sse4.2 max:avx2; do
  cpu=${pair%%:*} expected=${pair##*:}
  report=$(qemu-x86_64 -cpu "$cpu" "$pathtracer" "${render[@]}" -f "$out/$cpu.pfm" 2> "$out/$cpu.err") || {
    echo "FAIL: pathtracer on $cpu exited $?: $(cat "$out/$cpu.err")"
    status=1
    continue
  }
  level=$(grep -o 'bvh4, [a-z0-9.]*,' <<< "$report" | cut -d' ' -f2 | tr -d ,)
  if [ "$level" != "$expected" ]; then
    echo "FAIL: on $cpu the pathtracer picked '$level', expected $expected"
    status=1
    continue
  fi
  "$pathtracer" "${render[@]}" --isa "$expected" -q -f "$out/native_$expected.pfm"
  if cmp -s "$out/$cpu.pfm" "$out/native_$expected.pfm"; then
    echo "ok: $cpu runs $expected; image identical to the native $expected run"
  else
    echo "FAIL: $cpu's image differs from the native $expected run"
    status=1
  fi
  # The cache sizes the emulated CPU's CPUID reports are qemu's, not the host's that sysfs
  # lists: those two tests hold on real CPUs only.
  if qemu-x86_64 -cpu "$cpu" "$test_isa" --gtest_brief=1 --gtest_filter='-CacheSize.L*IsWhatTheKernelListsOrTheDefault' \
       > "$out/$cpu.tests" 2>&1 &&
     qemu-x86_64 -cpu "$cpu" "$test_sampling" --gtest_brief=1 \
       --gtest_filter='SimdPrimitives.*:RandomNumbers.SimdLanes*:Warps.Simd*' >> "$out/$cpu.tests" 2>&1; then
    echo "ok: $cpu passes the level detection and SIMD primitive tests at $expected"
  else
    echo "FAIL: level detection or SIMD primitive tests on $cpu:"
    cat "$out/$cpu.tests"
    status=1
  fi
done
# A level the CPU lacks is refused in one line, exit 2.
err=$(qemu-x86_64 -cpu Nehalem-v1 "$pathtracer" -q --isa avx2 -f "$out/refused.png" 2>&1) && code=0 || code=$?
if [ "$code" = 2 ] && [ "$err" = "error: --isa: this CPU does not support avx2" ] && [ ! -e "$out/refused.png" ]; then
  echo "ok: --isa avx2 on Nehalem is refused: $err"
else
  echo "FAIL: --isa avx2 on Nehalem gave exit $code and: $err"
  status=1
fi
exit $status
