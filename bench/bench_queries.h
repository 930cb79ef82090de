// What the benchmark and the BVH tests trace that the renderer does not,
// compiled once per instruction-set level (bench_queries_isa.cpp) and reached
// through the table of the active level: ranges of rays each traced on its
// own through the BVH4 (one call per range, no dispatch per ray), and the
// watertight form of the tree (watertight_blocks.h), ray by ray.
#pragma once

#include <cstdint>
#include <span>

#include "bvh/bvh4.h"
#include "bvh/scene_bvh4.h"
#include "bvh/traversal_counters.h"
#include "kernels/math/ray.h"
#include "kernels/simd/isa.h"

namespace pt::bench {

struct BenchQueryTable {
  Isa isa;
  /// hits[i] = s.intersect(rays[i]), blocked[i] = s.occluded(rays[i]).
  void (*intersect_each)(const SceneBvh4& s, std::span<const Ray> rays, std::span<Hit> hits);
  void (*occluded_each)(const SceneBvh4& s, std::span<const Ray> rays, std::span<uint8_t> blocked);
  /// The closest hit and occlusion of one ray through a tree of watertight
  /// blocks (to_watertight) and the scene's spheres, as SceneBvh4's queries
  /// answer them; `counters` may be null.
  bool (*watertight_intersect)(const Bvh4& tree, const SceneBvh4& spheres_of, const Ray& ray, Hit& hit,
                               TraversalCounters* counters);
  bool (*watertight_occluded)(const Bvh4& tree, const SceneBvh4& spheres_of, const Ray& ray,
                              TraversalCounters* counters);
};

/// The table of the level in use (active_isa()).
const BenchQueryTable& bench_queries();

/// A SceneBvh4 and the same tree in watertight form, with the queries of
/// both (the tree's, through SceneBvh4; the watertight form's, ray by ray).
class WatertightBvh4 {
 public:
  explicit WatertightBvh4(const Scene& scene, const Bvh4Options& options = {});
  const SceneBvh4& moller_trumbore() const { return bvh_; }
  bool intersect(const Ray& ray, Hit& hit, TraversalCounters* counters = nullptr) const {
    return bench_queries().watertight_intersect(tree_, bvh_, ray, hit, counters);
  }
  bool occluded(const Ray& ray, TraversalCounters* counters = nullptr) const {
    return bench_queries().watertight_occluded(tree_, bvh_, ray, counters);
  }

 private:
  SceneBvh4 bvh_;
  Bvh4 tree_;
};

}  // namespace pt::bench
