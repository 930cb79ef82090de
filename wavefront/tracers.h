// Ray tracers the engines can run on, behind one small interface:
// intersect(ray, hit, tests) and occluded(ray, tests).
#pragma once

#include "tests/reference/reference_accel.h"

namespace pt::wf {

/// The reference's midpoint binary BVH.
struct Bvh2Tracer {
  const reference::ReferenceAccel& accel;
  bool intersect(const Ray& r, Hit& h, uint64_t& tests) const { return accel.intersect(r, h, tests); }
  bool occluded(const Ray& r, uint64_t& tests) const { return accel.occluded(r, tests); }
};

}  // namespace pt::wf
