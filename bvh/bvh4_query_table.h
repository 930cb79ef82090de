// The BVH4 queries of one instruction-set level as a table of entry points:
// SceneBvh4 calls through the table of the level it was built for. Each
// level's table is defined by bvh4_queries_isa.cpp, compiled once per level.
#pragma once

#include <cstdint>
#include <span>

#include "kernels/simd/isa.h"
#include "kernels/math/ray.h"
#include "kernels/math/ray_arrays.h"
#include "queue_scratch.h"
#include "traversal_counters.h"

namespace pt {

class SceneBvh4;

/// Queries as SceneBvh4 documents them; `counters` may be null.
struct Bvh4QueryTable {
  Isa isa;
  uint32_t packet_lanes;
  bool (*intersect)(const SceneBvh4&, const Ray&, Hit&, TraversalCounters* counters);
  bool (*occluded)(const SceneBvh4&, const Ray&, TraversalCounters* counters);
  void (*intersect_each)(const SceneBvh4&, std::span<const Ray>, std::span<Hit>);
  void (*occluded_each)(const SceneBvh4&, std::span<const Ray>, std::span<uint8_t>);
  void (*intersect_packets)(const SceneBvh4&, std::span<const Ray>, std::span<Hit>);
  void (*intersect_packet)(const SceneBvh4&, const Ray*, Hit*, uint32_t lanes);
  uint32_t (*occluded_packet)(const SceneBvh4&, const Ray*, uint32_t lanes);
  void (*intersect_queue)(const SceneBvh4&, const RayArrays&, const HitArrays&, QueueScratch&, TraversalCounters*);
  void (*occluded_queue)(const SceneBvh4&, const RayArrays&, uint8_t*, QueueScratch&, TraversalCounters*);
};

/// The table of a level compiled into this binary (IsaError otherwise).
const Bvh4QueryTable& bvh4_query_table(Isa isa);

}  // namespace pt
