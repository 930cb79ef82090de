// What a render reports at the end (the course renderer's report plus ray
// counts by type and the samples discarded as non-finite).
#pragma once

#include <cstdint>

namespace pt {

struct RenderStats {
  uint64_t camera_rays = 0;
  uint64_t bounce_rays = 0;
  uint64_t shadow_rays = 0;
  uint64_t intersection_tests = 0;  ///< primitive tests (triangles + spheres)
  uint64_t samples = 0;             ///< camera samples taken
  uint64_t invalid_samples = 0;     ///< NaN / inf path results dropped
  double seconds = 0.0;

  uint64_t rays() const { return camera_rays + bounce_rays + shadow_rays; }
  /// Adds another render's counts and its time (renders one after another, or
  /// tiles whose busy time is summed); += leaves seconds alone (threads of one render).
  void add_render(const RenderStats& o) {
    *this += o;
    seconds += o.seconds;
  }
  RenderStats& operator+=(const RenderStats& o) {
    camera_rays += o.camera_rays;
    bounce_rays += o.bounce_rays;
    shadow_rays += o.shadow_rays;
    intersection_tests += o.intersection_tests;
    samples += o.samples;
    invalid_samples += o.invalid_samples;
    return *this;
  }
};

}  // namespace pt
