// The reference renderer's ray queries: a binary BVH built with the
// assignment's midpoint split, or brute force over every primitive, with
// Moller-Trumbore triangles and analytic spheres; or the 4-wide SIMD BVH
// (SceneBvh4). Counts primitive tests.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "bvh/bvh2.h"
#include "bvh/scene_bvh4.h"
#include "kernels/ray.h"
#include "kernels/scene.h"

namespace pt::reference {

/// kBvh: the midpoint binary BVH; kBruteForce: every primitive; kBvh4: SceneBvh4.
enum class AccelMode { kBvh, kBruteForce, kBvh4 };

class ReferenceAccel {
 public:
  /// max_leaf_size applies to kBvh only.
  ReferenceAccel(const Scene& scene, AccelMode mode, uint32_t max_leaf_size = 4);

  /// Closest hit with ray.tmin <= t < ray.tmax; `tests` counts primitive tests.
  bool intersect(const Ray& ray, Hit& hit, uint64_t& tests) const;
  /// Whether anything lies on the ray within [tmin, tmax).
  bool occluded(const Ray& ray, uint64_t& tests) const;

  const Bvh2& bvh() const { return bvh_; }
  AccelMode mode() const { return mode_; }
  /// Bytes the structure holds (BVH nodes and primitive order, or the BVH4);
  /// 0 for brute force. used_bytes: of those, the ones in use.
  size_t bytes() const {
    return bvh_.nodes.capacity() * sizeof(Bvh2Node) + bvh_.prim_order.capacity() * sizeof(uint32_t) +
           (bvh4_ ? bvh4_->bytes() : 0);
  }
  size_t used_bytes() const {
    return bvh_.nodes.size() * sizeof(Bvh2Node) + bvh_.prim_order.size() * sizeof(uint32_t) +
           (bvh4_ ? bvh4_->used_bytes() : 0);
  }

 private:
  /// Tests primitive `prim` (triangles first, then spheres); on a hit closer
  /// than `tmax` fills `hit` and returns true.
  bool test_primitive(uint32_t prim, const Ray& ray, float tmax, Hit& hit) const;

  const Scene& scene_;
  AccelMode mode_;
  Bvh2 bvh_;
  std::unique_ptr<SceneBvh4> bvh4_;
};

}  // namespace pt::reference
