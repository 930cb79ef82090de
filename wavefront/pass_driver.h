// The pass loop shared by the wavefront and megakernel engines: pixels in
// tile order, passes of samples (kernels/render/sample_schedule.h), chunks of
// pixels spread over oneTBB threads, per-pixel accumulators in sample order,
// the adaptive test between passes, progress and cancellation. Compiled once:
// the engines' code of each instruction-set level renders the chunks, and the
// threads stay here, so that no level's code holds oneTBB's own inline code.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

#include "kernels/render/accumulation.h"
#include "kernels/render/render_job.h"

namespace pt::wf {

/// Renders samples [first_sample, first_sample + samples) of each pixel of
/// `pixels` and adds them, in order, to acc.at(pixel). Chunks run
/// concurrently for disjoint pixel sets; `worker` (0 <= worker <
/// pass_workers()) names the calling thread's slot, which no other chunk
/// holds at the same time.
using PassChunk = std::function<void(uint32_t worker, std::span<const uint32_t> pixels, uint32_t first_sample,
                                     uint32_t samples, Accumulation& acc, RenderStats& stats)>;

/// The worker slots render_passes runs chunks on: rs.threads, at least 1.
uint32_t pass_workers(const RenderSettings& rs);

/// Renders in passes until every active pixel has rs.samples_per_pixel
/// samples, adaptive sampling stops it, or control cancels: chunks of about
/// `paths_per_chunk` paths (pixels times samples), never interrupted, so that
/// after a cancel every pixel holds whole chunks. Starts from
/// control.resume_from when it fits the region; control.on_pass runs after
/// each completed pass, control.on_interrupt on a cancel. Returns the film of
/// the accumulated means and the chunks' statistics (seconds: the whole call).
RenderOutput render_passes(const RenderSettings& rs, size_t paths_per_chunk, const RenderControl& control,
                           const PassChunk& chunk);

}  // namespace pt::wf
