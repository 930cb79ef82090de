// render_reference: tiling, threads, per-pixel sample loop and film writes.
#include "reference_renderer.h"

#include <atomic>
#include <chrono>

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "kernels/adaptive.h"
#include "kernels/camera_sample.h"
#include "reference_integrator.h"

namespace pt::reference {
namespace {

constexpr int kTile = 16;

Region render_region(const RenderSettings& rs) {
  return rs.region ? *rs.region : Region{0, 0, rs.width, rs.height};
}

}  // namespace

float3 reference_sample(const Scene& scene, const ReferenceAccel& accel, const Camera& camera,
                        const RenderSettings& rs, int x, int y, uint32_t sample, RenderStats& stats) {
  uint32_t key = path_key(rs.seed, pixel_index(rs, x, y), sample);
  return ReferenceIntegrator<>(scene, accel, rs).radiance(jittered_camera_ray(camera, rs, x, y, key), key, stats);
}

RenderOutput render_reference(const Scene& scene, const Camera& camera, const RenderSettings& rs,
                              const ReferenceOptions& options, const RenderControl& control) {
  auto start = std::chrono::steady_clock::now();
  ReferenceAccel accel(scene, options.accel, options.max_leaf_size);
  ReferenceIntegrator<> integrator(scene, accel, rs);
  RenderOutput out;
  out.film = Film(rs.width, rs.height, static_cast<uint32_t>(rs.samples_per_pixel));
  Region region = render_region(rs);
  int tiles_x = (region.width + kTile - 1) / kTile, tiles_y = (region.height + kTile - 1) / kTile;
  int tile_count = tiles_x * tiles_y;
  std::atomic<int> tiles_done{0};
  tbb::enumerable_thread_specific<RenderStats> thread_stats;

  auto render_pixel = [&](int x, int y, RenderStats& stats) {
    uint32_t pixel = pixel_index(rs, x, y);
    PixelMoments moments;
    double sum[3] = {0, 0, 0};
    uint32_t n = 0;
    while (n < static_cast<uint32_t>(rs.samples_per_pixel)) {
      uint32_t key = path_key(rs.seed, pixel, n);
      float3 L = integrator.radiance(jittered_camera_ray(camera, rs, x, y, key), key, stats);
      if (!is_finite(L)) {
        ++stats.invalid_samples;
        L = float3{};
      }
      for (int c = 0; c < 3; ++c) sum[c] += L[c];
      moments.add(illuminance(L));
      ++n;
      if (rs.adaptive() && n % static_cast<uint32_t>(rs.adaptive_batch) == 0 &&
          pixel_converged(moments, n, rs.adaptive_tolerance))
        break;
    }
    stats.samples += n;
    size_t i = out.film.index(x, y);
    out.film.radiance[i] = float3(static_cast<float>(sum[0] / n), static_cast<float>(sum[1] / n),
                                  static_cast<float>(sum[2] / n));
    out.film.samples[i] = n;
  };

  tbb::task_arena arena(std::max(1, rs.threads));
  arena.execute([&] {
    tbb::parallel_for(0, tile_count, [&](int t) {
      if (control.cancelled()) return;
      RenderStats& stats = thread_stats.local();
      int x0 = region.x + (t % tiles_x) * kTile, y0 = region.y + (t / tiles_x) * kTile;
      int x1 = std::min(x0 + kTile, region.x + region.width), y1 = std::min(y0 + kTile, region.y + region.height);
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) render_pixel(x, y, stats);
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
