// The reference path tracer for one camera sample, written one ray at a time
// in the assignment's structure: zero-bounce emission, direct lighting by light
// importance sampling or uniform hemisphere sampling, and indirect bounces with
// Russian roulette up to the maximum depth. The arbiter for the other engines.
#pragma once

#include <cstdint>

#include "kernels/render_settings.h"
#include "kernels/render_stats.h"
#include "kernels/scene.h"
#include "kernels/surface.h"
#include "reference_accel.h"

namespace pt::reference {

class ReferenceIntegrator {
 public:
  ReferenceIntegrator(const Scene& scene, const ReferenceAccel& accel, const RenderSettings& settings)
      : scene_(scene), accel_(accel), rs_(settings) {}

  /// Radiance along a camera ray for the path keyed by `path_key`.
  float3 radiance(const Ray& camera_ray, uint32_t path_key, RenderStats& stats) const;

  /// Direct light reflected at `sp` towards -wo_dir, for the path at `vertex`.
  float3 direct_light(const SurfacePoint& sp, uint32_t path_key, uint32_t vertex, RenderStats& stats) const;

 private:
  float3 light_sampling(const SurfacePoint& sp, uint32_t key, uint32_t vertex, RenderStats& stats) const;
  float3 hemisphere_sampling(const SurfacePoint& sp, uint32_t key, uint32_t vertex, RenderStats& stats) const;
  /// Incident radiance from one light sample if its shadow ray is clear,
  /// weighted by cos / pdf; black otherwise.
  float3 shadowed(const SurfacePoint& sp, const LightSample& ls, RenderStats& stats) const;
  float3 sky(const float3& dir) const;

  const Scene& scene_;
  const ReferenceAccel& accel_;
  const RenderSettings& rs_;
};

}  // namespace pt::reference
