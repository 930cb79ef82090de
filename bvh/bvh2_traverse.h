// Single-ray traversal of the binary BVH: the slab test and a near-first,
// stack-based walk that hands each leaf's primitives to a callback.
#pragma once

#include <cmath>

#include "kernels/simd/isa_namespace.h"
#include "bvh2.h"
#include "kernels/math/ray.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Per-ray constants of the slab test.
struct SlabRay {
  float3 org, inv_dir;
  explicit SlabRay(const Ray& r) : org(r.org), inv_dir{1.0f / r.dir.x, 1.0f / r.dir.y, 1.0f / r.dir.z} {}
};

/// Entry distance of the ray into the box within [tmin, tmax], or +inf if it
/// misses. NaN slab distances (0 * inf) impose no constraint.
inline float slab_entry(const SlabRay& r, const float3& lo, const float3& hi, float tmin, float tmax) {
  for (int a = 0; a < 3; ++a) {
    float t0 = (lo[a] - r.org[a]) * r.inv_dir[a];
    float t1 = (hi[a] - r.org[a]) * r.inv_dir[a];
    tmin = std::fmax(tmin, std::fmin(t0, t1));
    tmax = std::fmin(tmax, std::fmax(t0, t1));
  }
  return tmin <= tmax ? tmin : INFINITY;
}

/// Visits leaves in near-first order while `leaf(first, count, tmax)` may
/// shrink tmax; returns early when `leaf` returns true and any_hit is set.
template <bool any_hit, class LeafFn>
inline bool traverse_bvh2(const Bvh2& bvh, const Ray& ray, float& tmax, LeafFn&& leaf) {
  if (bvh.prim_order.empty()) return false;
  SlabRay sr(ray);
  uint32_t stack[kBvh2MaxDepth * 2];
  int top = 0;
  bool found = false;
  const Bvh2Node* nodes = bvh.nodes.data();
  if (slab_entry(sr, nodes[0].lower, nodes[0].upper, ray.tmin, tmax) == INFINITY) return false;
  uint32_t current = 0;
  for (;;) {
    const Bvh2Node& n = nodes[current];
    if (n.is_leaf()) {
      if (leaf(n.left_or_first, n.count, tmax)) {
        found = true;
        if constexpr (any_hit) return true;
      }
    } else {
      uint32_t a = n.left_or_first, b = a + 1;
      float ta = slab_entry(sr, nodes[a].lower, nodes[a].upper, ray.tmin, tmax);
      float tb = slab_entry(sr, nodes[b].lower, nodes[b].upper, ray.tmin, tmax);
      if (ta > tb) {
        std::swap(ta, tb);
        std::swap(a, b);
      }
      if (ta != INFINITY) {
        if (tb != INFINITY) stack[top++] = b;
        current = a;
        continue;
      }
    }
    if (top == 0) return found;
    current = stack[--top];
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt
