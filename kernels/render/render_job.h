// The contract between the command line (or a test) and any render engine:
// what to render, how to report progress and stop early, and what comes back.
#pragma once

#include <atomic>
#include <functional>

#include "kernels/render/accumulation.h"
#include "kernels/render/error_estimate.h"
#include "kernels/scene/camera.h"
#include "kernels/render/film.h"
#include "kernels/render/render_settings.h"
#include "kernels/render/render_stats.h"
#include "kernels/scene/scene.h"

namespace pt {

struct RenderControl {
  /// Called now and then from worker threads with the finished fraction.
  std::function<void(double)> progress;
  /// When set and true, engines stop at the next tile / pass boundary.
  const std::atomic<bool>* cancel = nullptr;

  /// Pass-based engines: start from this state (a checkpoint) instead of zero.
  const Accumulation* resume_from = nullptr;
  /// Pass-based engines: called after every completed pass (not after a pass
  /// a cancel cut short), e.g. to save a checkpoint now and then.
  std::function<void(const Accumulation&)> on_pass;
  /// Pass-based engines: called once when a cancel ended the render, with the
  /// state reached (whole chunks only: a pass may be partly done), e.g. to
  /// save the checkpoint a resume starts from.
  std::function<void(const Accumulation&)> on_interrupt;

  /// Pass-based engines: when set, passes end at every power-of-two sample
  /// count, and after each such pass (once on_pass has run) the render stops
  /// if this returns true. The image is then the one a render of that many
  /// samples makes (samples are added in order, however the passes fall).
  std::function<bool(const Accumulation&)> stop_at_power_of_two;
  /// Pass-based engines: also fill RenderOutput::pixel_error.
  bool pixel_error = false;

  /// The film holds only the render region (Film::cropped), not the image.
  bool crop_film = false;

  bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
};

struct RenderOutput {
  Film film;
  RenderStats stats;
  bool cancelled = false;  ///< the film holds only what finished before the stop
  /// Pass-based engines: the image's own error estimate (error_estimate.h).
  ImageErrorEstimate error;
  /// Pass-based engines, when RenderControl::pixel_error asks: each pixel's
  /// estimated RMSE, laid out as the film's pixels.
  std::vector<float> pixel_error;
  /// Pass-based engines: samples per pixel completed (fewer than asked when
  /// stop_at_power_of_two stopped the render).
  uint32_t samples_done = 0;

  RenderOutput();
  // Defined once (render_job.cpp), as Film's are: the engines of every
  // instruction-set level make and drop outputs, and their members are no level's own.
  RenderOutput(const RenderOutput&);
  RenderOutput(RenderOutput&&) noexcept;
  RenderOutput& operator=(const RenderOutput&);
  RenderOutput& operator=(RenderOutput&&) noexcept;
  ~RenderOutput();
};

}  // namespace pt
