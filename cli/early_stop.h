// --target-error and --time: the rule a render checks at every power-of-two
// sample count (RenderControl::stop_at_power_of_two), and the line that says
// where it stopped and why.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "kernels/render/render_job.h"

namespace pt::cli {

class EarlyStop {
 public:
  /// Seconds the render has taken when it holds `acc`.
  using Clock = std::function<double(const Accumulation& acc)>;
  /// target_error 0: no target; time_limit 0: no limit. `clock` empty: the
  /// steady clock, started now (tests pass a clock of their own).
  EarlyStop(double target_error, double time_limit, Clock clock = {});

  /// Whether to stop with the samples of `acc`: the estimated relative RMSE is
  /// at most the target, or doubling the samples done (which takes about as
  /// long as everything so far) would pass the time limit.
  bool operator()(const Accumulation& acc);

  /// The stop rule for RenderControl (holds a reference to this object).
  std::function<bool(const Accumulation&)> rule() {
    return [this](const Accumulation& acc) { return (*this)(acc); };
  }

  /// "Stopped at N samples per pixel: why" for a render that returned `out`.
  std::string stop_line(const RenderOutput& out) const;
  /// A target that the render did not meet within -s: the warning, else empty.
  std::string missed_target_warning(const RenderOutput& out, uint32_t max_samples) const;

 private:
  double target_error_, time_limit_;
  Clock clock_;
  bool met_target_ = false, out_of_time_ = false;
};

}  // namespace pt::cli
