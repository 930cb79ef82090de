// How the live view spends its time: the samples of each progressive step
// (the counts shown are 1, 4, 16, 64, ...: each step three times the samples
// so far, fewer steps than doubling for the same early frames; capped so that
// a still view still updates a few times a second) and the resolution divisor of a
// frame while the camera moves (the largest image that keeps the frame rate).
// Pure functions of measured rates, so the policy is testable without clocks.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pt::live {

/// Samples per pixel of the step after `done` of `target`: 3 x `done` (at
/// least 1), at most what takes `max_step_seconds` at `seconds_per_sample` (at
/// least 1; a rate of 0 means unknown: no cap), never past the target.
inline uint32_t next_step(uint32_t done, uint32_t target, double seconds_per_sample, double max_step_seconds) {
  if (done >= target) return 0;
  double step = std::max<double>(3.0 * done, 1.0);
  if (seconds_per_sample > 0.0) step = std::min(step, std::max(1.0, std::floor(max_step_seconds / seconds_per_sample)));
  return static_cast<uint32_t>(std::min<double>(step, target - done));
}

/// The resolution divisor (1, 2, 4 or 8) of a frame while the camera moves:
/// `fixed` when not 0, else the smallest whose one-sample frame takes at most
/// `budget_seconds`, from `full_frame_seconds` (one sample per pixel at the
/// view's size; 0 = unknown: 1).
inline int preview_divisor(int fixed, double full_frame_seconds, double budget_seconds) {
  if (fixed != 0) return fixed;
  int d = 1;
  while (d < 8 && full_frame_seconds / (double(d) * d) > budget_seconds) d *= 2;
  return d;
}

/// ceil(size / divisor): the preview's side for a view side.
inline int preview_side(int size, int divisor) { return (size + divisor - 1) / divisor; }

}  // namespace pt::live
