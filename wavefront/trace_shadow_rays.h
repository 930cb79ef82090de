// Stage 4: occlusion queries of the shadow queue; every ray that reaches its
// light adds its weight to its path's radiance. Hemisphere-sampling rays are
// traced closest-hit instead and add weight x the emission they find.
#pragma once

#include <algorithm>

#include "kernels/transport/surface.h"
#include "streams.h"
#include "wave_context.h"

namespace pt::wf {

/// With `coherent` (shadow rays from one pixel's first hits) runs of K rays go
/// through the tracer's SIMD packet traversal.
template <class Tracer>
void trace_shadow_rays(const Tracer& tracer, const ShadowQueue& shadows, PathState& paths, uint64_t& tests,
                       bool coherent) {
  auto add = [&](size_t i) {
    paths.add_radiance(shadows.path[i], shadows.weight_r[i], shadows.weight_g[i], shadows.weight_b[i]);
  };
  if (coherent) {
    Ray packet[kLanes];
    for (size_t i0 = 0; i0 < shadows.size; i0 += kLanes) {
      size_t n = std::min(kLanes, shadows.size - i0);
      for (size_t l = 0; l < n; ++l) packet[l] = shadows.ray(i0 + l);
      uint32_t lanes = lanes_below(n);
      uint32_t blocked = tracer.occluded_packet(packet, lanes, tests);
      for (uint32_t m = lanes & ~blocked; m; m &= m - 1) add(i0 + __builtin_ctz(m));
    }
    return;
  }
  for (size_t i = 0; i < shadows.size; ++i)
    if (!tracer.occluded(shadows.ray(i), tests)) add(i);
}

template <class Tracer>
void trace_hemisphere_rays(const Tracer& tracer, const WaveContext& ctx, const ShadowQueue& rays, PathState& paths,
                           uint64_t& tests) {
  const Scene& scene = ctx.scene;
  for (size_t i = 0; i < rays.size; ++i) {
    Ray ray = rays.ray(i);
    Hit hit;
    float3 incoming;
    if (tracer.intersect(ray, hit, tests))
      incoming = emitted_radiance(scene, surface_at(scene, ray, hit), ray, ctx.settings);
    else if (ctx.sky_visible) incoming = sky_radiance(scene, ray.dir);
    if (is_black(incoming)) continue;
    paths.add_radiance(rays.path[i], rays.weight_r[i] * incoming.x, rays.weight_g[i] * incoming.y,
                       rays.weight_b[i] * incoming.z);
  }
}

}  // namespace pt::wf
