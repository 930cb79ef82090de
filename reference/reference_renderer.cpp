// render_reference: tiling, threads, per-pixel sample loop and film writes.
#include "reference_renderer.h"

#include <atomic>
#include <chrono>

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "kernels/render/pixel_accumulator.h"
#include "kernels/transport/camera_sample.h"
#include "kernels/render/sample_schedule.h"
#include "kernels/transport/path_integrator.h"

namespace pt::reference {
namespace {

constexpr int kTile = 16;

}  // namespace

RenderOutput render_reference(const Scene& scene, const Camera& camera, const RenderSettings& rs,
                              const ReferenceOptions& options, const RenderControl& control) {
  SceneBvh2 accel(scene, options.accel, options.max_leaf_size);
  return render_reference(scene, accel, camera, rs, control);
}

RenderOutput render_reference(const Scene& scene, const SceneBvh2& accel, const Camera& camera,
                              const RenderSettings& rs, const RenderControl& control) {
  auto start = std::chrono::steady_clock::now();
  const PathIntegrator<SceneBvh2> integrator(scene, rs, accel);
  RenderOutput out;
  Region region = rs.area();
  const uint32_t spp = static_cast<uint32_t>(rs.samples_per_pixel);
  out.film = control.crop_film ? Film::cropped(region, spp) : Film(rs.width, rs.height, spp);
  int tiles_x = (region.width + kTile - 1) / kTile, tiles_y = (region.height + kTile - 1) / kTile;
  int tile_count = tiles_x * tiles_y;
  std::atomic<int> tiles_done{0};
  tbb::enumerable_thread_specific<RenderStats> thread_stats;

  auto render_pixel = [&](int x, int y, RenderStats& stats) {
    const uint32_t pixel = pixel_index(rs, x, y);
    PixelAccumulator acc;
    while (acc.samples < static_cast<uint32_t>(rs.samples_per_pixel)) {
      PathSampler ps(rs, pixel, acc.samples);
      if (!acc.add(integrator.radiance(jittered_camera_ray(camera, rs, x, y, ps), ps, stats))) ++stats.invalid_samples;
      if (adaptive_check_due(rs, acc.samples) && pixel_converged(acc.moments, acc.samples, rs.adaptive_tolerance))
        break;
    }
    stats.samples += acc.samples;
    size_t i = out.film.index(x, y);
    out.film.radiance[i] = acc.mean();
    out.film.samples[i] = acc.samples;
    out.film.variance[i] = static_cast<float>(variance_of_mean(acc.moments, acc.samples));
  };

  tbb::task_arena arena(std::max(1, rs.threads));
  arena.execute([&] {
    tbb::parallel_for(0, tile_count, [&](int t) {
      if (control.cancelled()) return;
      RenderStats& stats = thread_stats.local();
      int x0 = region.x + (t % tiles_x) * kTile, y0 = region.y + (t / tiles_x) * kTile;
      int x1 = std::min(x0 + kTile, region.x + region.width), y1 = std::min(y0 + kTile, region.y + region.height);
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          if (control.cancelled()) return;  // pixels not reached stay black with 0 samples
          render_pixel(x, y, stats);
        }
      int done = tiles_done.fetch_add(1) + 1;
      if (control.progress) control.progress(double(done) / tile_count);
    });
  });
  for (const RenderStats& s : thread_stats) out.stats += s;
  out.cancelled = control.cancelled();
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace pt::reference
