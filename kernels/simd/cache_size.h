// The size of this CPU's caches, for the choices that depend on what they
// hold: whether a tree's walks prefetch (bvh/bvh4_interleaved.h), whether a
// queue goes as octant sets (bvh/queue_coherence.h), how far ahead a stream
// loads its queue (bvh/bvh4_stream.h).
#pragma once

#include <cstddef>

namespace pt {

/// The L2 cache of one core, in bytes, as the C library reports it (glibc
/// reads it from CPUID on x86-64), or kDefaultL2CacheBytes where it reports
/// none (on aarch64, glibc often does not). Read once.
std::size_t l2_cache_bytes();

inline constexpr std::size_t kDefaultL2CacheBytes = std::size_t(1) << 20;

/// `reported` (a C library's answer, 0 or negative for none) as an L2 size:
/// the fallback where none is reported.
constexpr std::size_t l2_cache_bytes_from(long reported) {
  return reported > 0 ? std::size_t(reported) : kDefaultL2CacheBytes;
}

/// The L1 data cache of one core, in bytes, likewise (kDefaultL1CacheBytes
/// where none is reported).
std::size_t l1_data_cache_bytes();

inline constexpr std::size_t kDefaultL1CacheBytes = std::size_t(32) << 10;

constexpr std::size_t l1_cache_bytes_from(long reported) {
  return reported > 0 ? std::size_t(reported) : kDefaultL1CacheBytes;
}

}  // namespace pt
