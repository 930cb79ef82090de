// SceneBvh2: ray queries over a whole Scene through the assignment's binary
// BVH (midpoint split), or by brute force over every primitive, with the
// scalar Moller-Trumbore triangle test and analytic spheres, one ray at a
// time. Counts primitive tests. The reference engine's only accelerator, and
// what `--bvh bvh2` / `--bvh none` give the other engines.
#pragma once

#include <cstdint>

#include "bvh2.h"
#include "kernels/math/ray.h"
#include "kernels/scene/scene.h"

namespace pt {

/// kMidpoint: the midpoint binary BVH; kBruteForce: every primitive.
enum class Bvh2Mode { kMidpoint, kBruteForce };

class SceneBvh2 {
 public:
  /// max_leaf_size applies to kMidpoint only.
  SceneBvh2(const Scene& scene, Bvh2Mode mode, uint32_t max_leaf_size = 4);

  /// Closest hit with ray.tmin <= t < ray.tmax; `tests` counts primitive tests.
  bool intersect(const Ray& ray, Hit& hit, uint64_t& tests) const;
  /// Whether anything lies on the ray within [tmin, tmax).
  bool occluded(const Ray& ray, uint64_t& tests) const;

  const Bvh2& bvh() const { return bvh_; }
  Bvh2Mode mode() const { return mode_; }
  /// Bytes the structure holds (BVH nodes and primitive order); 0 for brute
  /// force. used_bytes: of those, the ones in use.
  size_t bytes() const {
    return bvh_.nodes.capacity() * sizeof(Bvh2Node) + bvh_.prim_order.capacity() * sizeof(uint32_t);
  }
  size_t used_bytes() const { return bvh_.nodes.size() * sizeof(Bvh2Node) + bvh_.prim_order.size() * sizeof(uint32_t); }

 private:
  /// Tests primitive `prim` (triangles first, then spheres); on a hit closer
  /// than `tmax` fills `hit` and returns true.
  bool test_primitive(uint32_t prim, const Ray& ray, float tmax, Hit& hit) const;

  const Scene& scene_;
  Bvh2Mode mode_;
  Bvh2 bvh_;
};

}  // namespace pt
