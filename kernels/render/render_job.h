// The contract between the command line (or a test) and any render engine:
// what to render, how to report progress and stop early, and what comes back.
#pragma once

#include <atomic>
#include <functional>

#include "kernels/render/accumulation.h"
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

  /// The film holds only the render region (Film::cropped), not the image.
  bool crop_film = false;

  bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
};

struct RenderOutput {
  Film film;
  RenderStats stats;
  bool cancelled = false;  ///< the film holds only what finished before the stop
};

}  // namespace pt
