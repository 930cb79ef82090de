// Axis-aligned bounding box over float3: the unit of every BVH builder and the
// scene's overall extent.
#pragma once

#include <limits>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/vec3.h"

namespace pt {

/// 24 bytes: lower and upper corners. An empty box has lower = +inf, upper = -inf.
struct BBox {
  float3 lower{std::numeric_limits<float>::infinity()};
  float3 upper{-std::numeric_limits<float>::infinity()};

  static BBox of_point(float3 p) { return {p, p}; }
  void expand(float3 p) {
    lower = pt::min(lower, p);
    upper = pt::max(upper, p);
  }
  void expand(const BBox& b) {
    lower = pt::min(lower, b.lower);
    upper = pt::max(upper, b.upper);
  }
  bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
  float3 extent() const { return upper - lower; }
  float3 center() const { return (lower + upper) * 0.5f; }
  /// Surface area; 0 for an empty box.
  float half_area() const {
    if (empty()) return 0.0f;
    float3 e = extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
  float area() const { return 2.0f * half_area(); }
};
static_assert(sizeof(BBox) == 24);

inline namespace PT_ISA_NS {
inline BBox merge(BBox a, const BBox& b) {
  a.expand(b);
  return a;
}

}  // namespace PT_ISA_NS
}  // namespace pt
