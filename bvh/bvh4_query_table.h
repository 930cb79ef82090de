// The BVH4 queries of one instruction-set level as a table of entry points:
// SceneBvh4 calls through the table of the level it was built for. Each
// level's table is defined by bvh4_queries_isa.cpp, compiled once per level.
#pragma once

#include <cstdint>

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
  bool (*intersect)(const SceneBvh4&, const Ray&, Hit&, TraversalCounters* counters);
  bool (*occluded)(const SceneBvh4&, const Ray&, TraversalCounters* counters);
  void (*intersect_queue)(const SceneBvh4&, const RayArrays&, const HitArrays&, QueueScratch&, TraversalCounters*);
  void (*occluded_queue)(const SceneBvh4&, const RayArrays&, uint8_t*, QueueScratch&, TraversalCounters*);
  /// The closest-hit walk of one traceable ray through the tree alone (no
  /// spheres) into `hit`: visit(context, ref) hears of every node and leaf
  /// it takes, in order (walk_bvh4, bvh4_inspect.h).
  void (*walk_tree)(const SceneBvh4&, const Ray&, Hit& hit, TraversalCounters& counters,
                    void (*visit)(void* context, uint32_t ref), void* context);
};

/// The table of a level compiled into this binary (IsaError otherwise).
const Bvh4QueryTable& bvh4_query_table(Isa isa);

}  // namespace pt
