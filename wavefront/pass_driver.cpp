// The pass loop (pass_driver.h).
#include "pass_driver.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <vector>

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "kernels/render/sample_schedule.h"

namespace pt::wf {
namespace {

/// Film of the accumulated means and sample counts: the image, or only the
/// region when control.crop_film asks.
Film film_from(const Accumulation& acc, const RenderSettings& rs, const RenderControl& control) {
  const uint32_t spp = static_cast<uint32_t>(rs.samples_per_pixel);
  Film film = control.crop_film ? Film::cropped(acc.area, spp) : Film(rs.width, rs.height, spp);
  const Region& a = acc.area;
  for (int y = a.y; y < a.y + a.height; ++y)
    for (int x = a.x; x < a.x + a.width; ++x) {
      const PixelAccumulator& p = acc.pixels[size_t(y - a.y) * a.width + (x - a.x)];
      size_t i = film.index(x, y);
      film.radiance[i] = p.mean();
      film.samples[i] = p.samples;
      film.variance[i] = static_cast<float>(variance_of_mean(p.moments, p.samples));
    }
  return film;
}

/// Each pixel's estimated RMSE laid out as film_from lays out the film.
std::vector<float> pixel_error_film(const Accumulation& acc, const RenderSettings& rs, const RenderControl& control) {
  const std::vector<float> area_error = estimate_pixel_error(acc);
  const Region& a = acc.area;
  if (control.crop_film) return area_error;
  std::vector<float> out(size_t(rs.width) * rs.height, 0.0f);
  for (int y = a.y; y < a.y + a.height; ++y)
    for (int x = a.x; x < a.x + a.width; ++x)
      out[size_t(y) * rs.width + x] = area_error[size_t(y - a.y) * a.width + (x - a.x)];
  return out;
}

/// Pixels that still take samples after `acc.samples_done` samples.
std::vector<uint32_t> active_pixels(const Accumulation& acc, const RenderSettings& rs) {
  std::vector<uint32_t> active;
  for (uint32_t p : tiled_pixel_order(rs))
    if (!acc.at(p).converged) active.push_back(p);
  return active;
}

/// Starts from control.resume_from when given (and sized for this region).
Accumulation initial_accumulation(const RenderSettings& rs, const RenderControl& control) {
  Accumulation acc;
  const Region area = rs.area();
  const size_t n = size_t(area.width) * area.height;
  if (control.resume_from && control.resume_from->pixels.size() == n) acc = *control.resume_from;
  else acc.pixels.resize(n);
  acc.area = area;
  acc.image_width = rs.width;
  return acc;
}

}  // namespace

uint32_t pass_workers(const RenderSettings& rs) { return static_cast<uint32_t>(std::max(1, rs.threads)); }

RenderOutput render_passes(const RenderSettings& rs, size_t paths_per_chunk, const RenderControl& control,
                           const PassChunk& chunk) {
  const auto start = std::chrono::steady_clock::now();
  Accumulation acc = initial_accumulation(rs, control);
  std::vector<uint32_t> active = active_pixels(acc, rs);
  const double total_samples = double(active.size()) * rs.samples_per_pixel;
  std::atomic<uint64_t> samples_finished{0};
  tbb::enumerable_thread_specific<RenderStats> thread_stats;
  tbb::task_arena arena(static_cast<int>(pass_workers(rs)));
  bool stopped_at_target = false;

  while (uint32_t len = pass_length(rs, acc.samples_done)) {
    if (active.empty() || control.cancelled()) break;
    if (control.stop_at_power_of_two) len = std::min(len, std::bit_ceil(acc.samples_done + 1) - acc.samples_done);
    // A pass interrupted before a checkpoint left some pixels finished; render the rest.
    std::vector<uint32_t> todo;
    for (uint32_t p : active)
      if (acc.at(p).samples < acc.samples_done + len) todo.push_back(p);
    const size_t per_chunk = std::max<size_t>(1, paths_per_chunk / len);
    const size_t chunks = (todo.size() + per_chunk - 1) / per_chunk;
    std::atomic<bool> complete{true};
    arena.execute([&] {
      tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
        if (control.cancelled()) {
          complete = false;
          return;
        }
        size_t begin = c * per_chunk, end = std::min(todo.size(), begin + per_chunk);
        std::span<const uint32_t> pixels(todo.data() + begin, end - begin);
        const uint32_t worker = static_cast<uint32_t>(tbb::this_task_arena::current_thread_index());
        chunk(worker, pixels, acc.samples_done, len, acc, thread_stats.local());
        uint64_t done = samples_finished.fetch_add(pixels.size() * len) + pixels.size() * len;
        if (control.progress) control.progress(std::min(1.0, done / total_samples));
      });
    });
    if (!complete) break;
    acc.samples_done += len;
    if (adaptive_check_due(rs, acc.samples_done)) {
      std::erase_if(active, [&](uint32_t p) {
        PixelAccumulator& a = acc.at(p);
        a.converged = pixel_converged(a.moments, a.samples, rs.adaptive_tolerance) ? 1 : 0;
        return a.converged != 0;
      });
    }
    if (control.on_pass) control.on_pass(acc);
    const uint32_t done = acc.samples_done;
    if (control.stop_at_power_of_two && (done & (done - 1)) == 0 && control.stop_at_power_of_two(acc)) {
      stopped_at_target = true;
      break;
    }
  }
  if (control.cancelled() && control.on_interrupt) control.on_interrupt(acc);
  RenderOutput out;
  for (const RenderStats& s : thread_stats) out.stats += s;
  out.film = film_from(acc, rs, control);
  out.cancelled = control.cancelled();
  out.samples_done = acc.samples_done;
  if (stopped_at_target) out.film.max_samples = out.samples_done;  // stopped early: the film -s samples_done makes
  if (!out.cancelled) {  // a cancelled render's film is partial, and whoever cancelled it wants it back at once
    out.error = estimate_image_error(acc);
    if (control.pixel_error) out.pixel_error = pixel_error_film(acc, rs, control);
  }
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace pt::wf
