// Large batches of incoherent rays (bounce and shadow rays) through a
// SceneBvh4, traced one by one in parallel in the calling oneTBB arena; when
// the tree is larger than the caches they are first put in the order of
// coherent_order (ray_order.h), so that neighbouring rays find each other's
// nodes and leaves in cache. Measured inside whole renders this does not pay
// (waves of 4096 paths are too small to share nodes: CBbunny 2.83 -> 3.20 s,
// its 16x subdivision 5.04 -> 5.20 s), so it lives with the benchmark.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "bvh/scene_bvh4.h"
#include "kernels/math/bbox.h"

namespace pt::bench {

class IncoherentBatches {
 public:
  /// Reorders batches when the BVH holds at least `reorder_min_bytes`
  /// (measured on this project's machine, 1 MiB of L2 per core: reordering
  /// loses below 2 MiB and wins above 20 MiB).
  explicit IncoherentBatches(const SceneBvh4& bvh, const Scene& scene, size_t reorder_min_bytes = size_t(4) << 20);

  /// hits[i] = closest hit of rays[i]; same answers as SceneBvh4::intersect.
  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
  /// blocked[i] = 0 or 1, as SceneBvh4::occluded.
  void occluded(std::span<const Ray> rays, std::span<uint8_t> blocked) const;

 private:
  const SceneBvh4& bvh_;
  BBox bounds_;  ///< of all vertices and spheres: the grid of ray_order_key
  bool reorder_;
};

}  // namespace pt::bench
