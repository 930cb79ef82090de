// Stage 4: occlusion queries of the shadow queue; every ray that reaches its
// light adds its weight to its path's radiance. Hemisphere-sampling rays are
// traced closest-hit instead and add weight x the emission they find. Tracing
// and adding are separate steps, so that the tracer's time can be told apart.
#pragma once

#include <algorithm>

#include "kernels/simd/isa_namespace.h"
#include "intersect_closest.h"
#include "kernels/transport/surface.h"
#include "streams.h"
#include "trace_mode.h"
#include "wave_buffers.h"
#include "wave_context.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// tb.blocked[i] = whether shadow ray i is blocked.
template <class Tracer>
void find_blocked(const Tracer& tracer, const ShadowQueue& shadows, TracingBuffers& tb, uint64_t& tests,
                  TraceMode mode) {
  tb.blocked.resize(std::max(tb.blocked.size(), shadows.size));
  uint8_t* blocked = tb.blocked.data();
  if (mode == TraceMode::kQueue) {
    tracer.occluded_queue(shadows.arrays(), blocked, tb.scratch, tests);
    return;
  }
  for (size_t i = 0; i < shadows.size; ++i) blocked[i] = tracer.occluded(shadows.ray(i), tests);
}

/// Every shadow ray that reaches its light (not tb.blocked) adds its weight
/// to its path's radiance.
/// Branch-free (a blocked ray adds +0, which leaves every sum's bits as
/// they are: sums start at +0 and only grow), with the arrays read once
/// (stores into radiance would otherwise reload every pointer).
inline void add_unblocked(const ShadowQueue& shadows, const TracingBuffers& tb, PathState& paths) {
  const uint8_t* __restrict blocked = tb.blocked.data();
  const uint32_t* __restrict path = shadows.path.data();
  const float* __restrict wr = shadows.weight_r.data();
  const float* __restrict wg = shadows.weight_g.data();
  const float* __restrict wb = shadows.weight_b.data();
  float* __restrict lr = paths.radiance_r.data();
  float* __restrict lg = paths.radiance_g.data();
  float* __restrict lb = paths.radiance_b.data();
  for (size_t i = 0, n = shadows.size; i < n; ++i) {
    const bool through = blocked[i] == 0;
    const uint32_t p = path[i];
    lr[p] += through ? wr[i] : 0.0f;
    lg[p] += through ? wg[i] : 0.0f;
    lb[p] += through ? wb[i] : 0.0f;
  }
}

/// Each hemisphere-sampling ray adds weight x the emission its hit (in
/// `hits`) finds.
inline void add_found_emission(const WaveContext& ctx, const ShadowQueue& rays, const HitQueue& hits,
                               PathState& paths) {
  const Scene& scene = ctx.scene;
  for (size_t i = 0; i < rays.size; ++i) {
    const Ray ray = rays.ray(i);
    const Hit hit{hits.t[i], hits.u[i], hits.v[i], hits.prim[i]};
    float3 incoming;
    if (hit.valid()) incoming = emitted_radiance(scene, surface_at(scene, ray, hit), ray, ctx.settings);
    else if (ctx.sky_visible) incoming = sky_radiance(scene, ray.dir);
    if (is_black(incoming)) continue;
    paths.add_radiance(rays.path[i], rays.weight_r[i] * incoming.x, rays.weight_g[i] * incoming.y,
                       rays.weight_b[i] * incoming.z);
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
