// The megakernel engine: each path traced start to finish, one at a time, by
// the reference's path loop, over the same ray tracer, pass schedule, threads
// and accumulators as the wavefront. It exists to measure what the wavefront's
// queues and SIMD stages buy.
#pragma once

#include <chrono>

#include "kernels/camera_sample.h"
#include "kernels/render_job.h"
#include "pass_driver.h"
#include "tests/reference/reference_integrator.h"

namespace pt::wf {

template <class Tracer>
RenderOutput render_megakernel(const Scene& scene, const Camera& camera, const RenderSettings& rs,
                               const Tracer& tracer, const RenderControl& control = {}) {
  auto start = std::chrono::steady_clock::now();
  const reference::ReferenceIntegrator<Tracer> integrator(scene, tracer, rs);
  Accumulation acc = initial_accumulation(rs, control);
  RenderOutput out;
  auto chunk = [&](std::span<const uint32_t> pixels, uint32_t first, uint32_t len, std::vector<PixelAccumulator>& px,
                   RenderStats& stats) {
    for (uint32_t pixel : pixels) {
      int x = static_cast<int>(pixel % static_cast<uint32_t>(rs.width));
      int y = static_cast<int>(pixel / static_cast<uint32_t>(rs.width));
      for (uint32_t s = first; s < first + len; ++s) {
        PathSampler ps(rs, pixel, s);
        if (!px[pixel].add(integrator.radiance(jittered_camera_ray(camera, rs, x, y, ps), ps, stats)))
          ++stats.invalid_samples;
      }
      stats.samples += len;
    }
  };
  run_passes(rs, 4096, control, acc, out.stats, chunk);
  out.film = film_from(acc, rs);
  out.cancelled = control.cancelled();
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace pt::wf
