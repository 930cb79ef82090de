// The wavefront engine over a tracer: paths in waves of SoA queues through
// separate stages (run_wave.h), waves spread over threads, passes and
// accumulation shared with the megakernel (pass_driver.h). Compiled per
// instruction-set level; engines.h is the entry point.
#pragma once

#include <cstddef>

#include "engines.h"
#include "kernels/render/render_job.h"
#include "pass_driver.h"
#include "run_wave.h"

namespace pt::wf {

/// Renders with `tracer` (intersect / occluded with a test counter). If
/// `stage_stats` is given, it receives the per-stage statistics.
template <class Tracer>
RenderOutput render_wavefront(const Scene& scene, const Camera& camera, const RenderSettings& rs, const Tracer& tracer,
                              const WavefrontOptions& options = {}, const RenderControl& control = {},
                              StageStats* stage_stats = nullptr) {
  auto start = std::chrono::steady_clock::now();
  WaveContext ctx(scene, camera, rs);
  ctx.sort_by_material = options.sort_by_material;
  tbb::enumerable_thread_specific<WaveBuffers> buffers;
  tbb::enumerable_thread_specific<StageStats> stages;
  Accumulation acc = initial_accumulation(rs, control);
  RenderOutput out;

  auto chunk = [&](std::span<const uint32_t> pixels, uint32_t first, uint32_t len, Accumulation& px,
                   RenderStats& stats) {
    WaveBuffers& b = buffers.local();
    StageStats& ss = stages.local();
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
  run_passes(rs, options.wave_paths, control, acc, out.stats, chunk);

  StageStats all;
  for (const StageStats& s : stages) all += s;
  for (const WaveBuffers& b : buffers) {
    all.queue_bytes += b.bytes();
    all.tracer_bytes += b.tracing.bytes();
  }
  out.stats.camera_rays = all.camera_rays;
  out.stats.bounce_rays = all.bounce_rays;
  out.stats.shadow_rays = all.shadow_rays;
  out.stats.intersection_tests = all.primitive_tests;
  if (stage_stats) *stage_stats = all;
  out.film = film_from(acc, rs, control);
  out.cancelled = control.cancelled();
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace pt::wf
