// The pass loop shared by the wavefront and megakernel engines: pixels in
// tile order, passes of samples (kernels/render/sample_schedule.h), chunks of pixels
// spread over oneTBB threads, per-pixel accumulators in sample order, the
// adaptive test between passes, progress and cancellation.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <span>
#include <vector>

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "kernels/render/accumulation.h"
#include "kernels/render/render_job.h"
#include "kernels/render/sample_schedule.h"

namespace pt::wf {

/// Film of the accumulated means and sample counts: the image, or only the
/// region when control.crop_film asks.
inline Film film_from(const Accumulation& acc, const RenderSettings& rs, const RenderControl& control) {
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

/// Pixels that still take samples after `acc.samples_done` samples.
inline std::vector<uint32_t> active_pixels(const Accumulation& acc, const RenderSettings& rs) {
  std::vector<uint32_t> active;
  for (uint32_t p : tiled_pixel_order(rs))
    if (!acc.at(p).converged) active.push_back(p);
  return active;
}

/// Starts from control.resume_from when given (and sized for this region).
inline Accumulation initial_accumulation(const RenderSettings& rs, const RenderControl& control) {
  Accumulation acc;
  const Region area = rs.area();
  const size_t n = size_t(area.width) * area.height;
  if (control.resume_from && control.resume_from->pixels.size() == n) acc = *control.resume_from;
  else acc.pixels.resize(n);
  acc.area = area;
  acc.image_width = rs.width;
  return acc;
}

/// Runs passes until done or cancelled. `chunk(pixels, first_sample, samples,
/// acc, stats)` renders samples [first, first + samples) of each pixel in
/// `pixels` and adds them, in order, to acc.at(pixel); it is
/// called concurrently for disjoint pixel sets; a chunk is never interrupted,
/// so after a cancel every pixel holds whole chunks. control.on_pass runs
/// after each completed pass; control.on_interrupt once after a cancel, with
/// the state reached.
template <class Chunk>
void run_passes(const RenderSettings& rs, size_t paths_per_chunk, const RenderControl& control, Accumulation& acc,
                RenderStats& total, Chunk&& chunk) {
  std::vector<uint32_t> active = active_pixels(acc, rs);
  const double total_samples = double(active.size()) * rs.samples_per_pixel;
  std::atomic<uint64_t> samples_finished{0};
  tbb::enumerable_thread_specific<RenderStats> thread_stats;
  tbb::task_arena arena(std::max(1, rs.threads));

  while (uint32_t len = pass_length(rs, acc.samples_done)) {
    if (active.empty() || control.cancelled()) break;
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
        chunk(pixels, acc.samples_done, len, acc, thread_stats.local());
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
  }
  if (control.cancelled() && control.on_interrupt) control.on_interrupt(acc);
  for (const RenderStats& s : thread_stats) total += s;
}

}  // namespace pt::wf
