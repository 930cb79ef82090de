// What the BVH4's queue tracer (bvh4_stream.h) keeps between queues on one
// thread, reused so that a render allocates it once per thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <xsimd/memory/xsimd_aligned_allocator.hpp>

namespace pt {

/// A vector whose data starts on a 64-byte cache line, so that a list's
/// chunks (whose fields start at multiples of 16 words) load as whole lines:
/// malloc's 16-byte alignment had put every 64-byte load of a list across two
/// lines.
template <class T>
using LineAlignedArray = std::vector<T, xsimd::aligned_allocator<T, 64>>;

/// The lists a queue is split into and each ray's current tmax.
struct QueueScratch {
  LineAlignedArray<uint32_t> ids;                    ///< the lists of rays, one after the other (bvh4_stream.h)
  LineAlignedArray<float> tmax;                      ///< any hit: the ray's tmax, -inf once blocked
  std::vector<std::pair<uint32_t, uint32_t>> alone;  ///< (ray, node) walks left to single rays

  size_t bytes() const {
    return ids.capacity() * sizeof(uint32_t) + tmax.capacity() * sizeof(float) + alone.capacity() * sizeof(alone[0]);
  }
};

}  // namespace pt
