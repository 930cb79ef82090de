// The wavefront engine over a tracer: paths in waves of SoA queues through
// separate stages (run_wave.h), waves spread over threads, passes and
// accumulation shared with the megakernel (pass_driver.h). Compiled per
// instruction-set level; engines.h is the entry point.
#pragma once

#include <chrono>
#include <cstddef>
#include <vector>

#include "kernels/simd/isa_namespace.h"
#include "engines.h"
#include "kernels/render/render_job.h"
#include "pass_driver.h"
#include "run_wave.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// What one worker slot of the pass driver keeps from chunk to chunk.
struct WaveWorker {
  WaveBuffers buffers;
  StageStats stages;
};

/// Renders with `tracer` (intersect / occluded with a test counter). If
/// `stage_stats` is given, it receives the per-stage statistics.
template <class Tracer>
RenderOutput render_wavefront_with(const Scene& scene, const Camera& camera, const RenderSettings& rs,
                                   const Tracer& tracer, const WavefrontOptions& options, const RenderControl& control,
                                   StageStats* stage_stats) {
  const auto start = std::chrono::steady_clock::now();
  WaveContext ctx(scene, camera, rs);
  ctx.sort_by_material = options.sort_by_material;
  std::vector<WaveWorker> workers(pass_workers(rs));
  auto chunk = [&](uint32_t worker, std::span<const uint32_t> pixels, uint32_t first, uint32_t len, Accumulation& px,
                   RenderStats& stats) {
    WaveBuffers& b = workers[worker].buffers;
    StageStats& ss = workers[worker].stages;
    run_wave(ctx, tracer, pixels, first, len, options, b, ss);
    StageTimer t(ss, Stage::kAccumulate);
    for (size_t p = 0, i = 0; i < b.paths.size; ++p) {  // path i <-> pixel i / len, in path order
      PixelAccumulator& pixel = px.at(pixels[p]);
      for (const size_t end = i + len; i < end; ++i) {
        float3 L{b.paths.radiance_r[i], b.paths.radiance_g[i], b.paths.radiance_b[i]};
        if (!pixel.add(L)) ++stats.invalid_samples;
      }
    }
    stats.samples += b.paths.size;
  };
  RenderOutput out = render_passes(rs, options.wave_paths, control, chunk);

  StageStats all;
  for (const WaveWorker& w : workers) {
    all += w.stages;
    all.queue_bytes += w.buffers.bytes();
    all.tracer_bytes += w.buffers.tracing.bytes();
  }
  out.stats.camera_rays = all.camera_rays;
  out.stats.bounce_rays = all.bounce_rays;
  out.stats.shadow_rays = all.shadow_rays;
  out.stats.intersection_tests = all.primitive_tests;
  if (stage_stats) *stage_stats = all;
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
