// Ray tracers the engines run on, behind one small interface:
// intersect(ray, hit, tests) and occluded(ray, tests), where `tests` counts
// primitive tests when the tracer counts them.
#pragma once

#include "bvh/scene_bvh4.h"
#include "tests/reference/reference_accel.h"

namespace pt::wf {

/// The 4-wide BVH. kCount: also count primitive tests (off in the fast path).
template <bool kCount = false>
struct Bvh4Tracer {
  const SceneBvh4& accel;
  bool intersect(const Ray& r, Hit& h, uint64_t& tests) const {
    if constexpr (kCount) {
      TraversalCounters c;
      bool found = accel.intersect(r, h, c);
      tests += c.primitives;
      return found;
    } else {
      return accel.intersect(r, h);
    }
  }
  bool occluded(const Ray& r, uint64_t& tests) const {
    if constexpr (kCount) {
      TraversalCounters c;
      bool blocked = accel.occluded(r, c);
      tests += c.primitives;
      return blocked;
    } else {
      return accel.occluded(r);
    }
  }
};

/// The reference's accelerators (midpoint binary BVH, or brute force).
struct Bvh2Tracer {
  const reference::ReferenceAccel& accel;
  bool intersect(const Ray& r, Hit& h, uint64_t& tests) const { return accel.intersect(r, h, tests); }
  bool occluded(const Ray& r, uint64_t& tests) const { return accel.occluded(r, tests); }
};

}  // namespace pt::wf
