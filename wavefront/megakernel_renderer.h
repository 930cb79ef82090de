// The megakernel engine: each path traced start to finish, one at a time, by
// the one-path loop the reference also runs (kernels/transport/
// path_integrator.h), over the same tracer, pass schedule, threads and
// accumulators as the wavefront. It exists to measure what the wavefront's
// queues and SIMD stages buy. Compiled per instruction-set level; engines.h
// is the entry point.
#pragma once

#include <chrono>

#include "kernels/simd/isa_namespace.h"
#include "kernels/transport/camera_sample.h"
#include "kernels/transport/path_integrator.h"
#include "kernels/render/render_job.h"
#include "pass_driver.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

template <class Tracer>
RenderOutput render_megakernel_with(const Scene& scene, const Camera& camera, const RenderSettings& rs,
                                    const Tracer& tracer, const RenderControl& control) {
  const auto start = std::chrono::steady_clock::now();
  const PathIntegrator<Tracer> path(scene, rs, tracer);
  auto chunk = [&](uint32_t, std::span<const uint32_t> pixels, uint32_t first, uint32_t len, Accumulation& px,
                   RenderStats& stats) {
    for (uint32_t pixel : pixels) {
      int x = static_cast<int>(pixel % static_cast<uint32_t>(rs.width));
      int y = static_cast<int>(pixel / static_cast<uint32_t>(rs.width));
      for (uint32_t s = first; s < first + len; ++s) {
        PathSampler ps(rs, pixel, s);
        if (!px.at(pixel).add(path.radiance(jittered_camera_ray(camera, rs, x, y, ps), ps, stats)))
          ++stats.invalid_samples;
      }
      stats.samples += len;
    }
  };
  RenderOutput out = render_passes(rs, 4096, control, chunk);
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
