// What the BVH4's queue tracer (bvh4_stream.h) keeps between queues on one
// thread, reused so that a render allocates it once per thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace pt {

/// The lists a queue is split into and each ray's current tmax.
struct QueueScratch {
  std::vector<uint32_t> ids;                         ///< the lists of rays, one after the other (bvh4_stream.h)
  std::vector<float> tmax;                           ///< any hit: the ray's tmax, -inf once blocked
  std::vector<std::pair<uint32_t, uint32_t>> alone;  ///< (ray, node) walks left to single rays

  size_t bytes() const {
    return ids.capacity() * sizeof(uint32_t) + tmax.capacity() * sizeof(float) + alone.capacity() * sizeof(alone[0]);
  }
};

}  // namespace pt
