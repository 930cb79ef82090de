// EarlyStop (early_stop.h).
#include "early_stop.h"

#include <cstdio>
#include <utility>

namespace pt::cli {

EarlyStop::EarlyStop(double target_error, double time_limit, Clock clock)
    : target_error_(target_error), time_limit_(time_limit), clock_(std::move(clock)) {
  if (!clock_)
    clock_ = [start = std::chrono::steady_clock::now()](const Accumulation&) {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
}

bool EarlyStop::operator()(const Accumulation& acc) {
  // A checkpoint saved part-way through a pass of another render can hold
  // pixels past this count; the image is not yet the one of this count.
  for (const PixelAccumulator& p : acc.pixels)
    if (p.samples > acc.samples_done) return false;
  if (target_error_ > 0.0) {
    const ImageErrorEstimate e = estimate_image_error(acc);
    met_target_ = e.available && e.relative_rmse <= target_error_;
  }
  if (time_limit_ > 0.0) { out_of_time_ = 2.0 * clock_(acc) > time_limit_; }
  return met_target_ || out_of_time_;
}

std::string EarlyStop::stop_line(const RenderOutput& out) const {
  char line[200];
  const char* why = met_target_    ? "the estimated relative RMSE met --target-error"
                    : out_of_time_ ? "twice the samples would pass --time"
                                   : "the -s limit";
  std::snprintf(line, sizeof line, "Stopped at %u samples per pixel: %s", out.samples_done, why);
  return line;
}

std::string EarlyStop::missed_target_warning(const RenderOutput& out, uint32_t max_samples) const {
  if (target_error_ <= 0.0 || met_target_ || out.samples_done < max_samples) return {};
  char line[240];
  if (out.error.available)
    std::snprintf(line, sizeof line,
                  "warning: --target-error %g not reached within -s %u (estimated relative RMSE %.4g); wrote the "
                  "image at %u samples per pixel",
                  target_error_, max_samples, out.error.relative_rmse, out.samples_done);
  else
    std::snprintf(line, sizeof line,
                  "warning: --target-error %g not reached within -s %u (no estimate below 4 samples per pixel); "
                  "wrote the image at %u samples per pixel",
                  target_error_, max_samples, out.samples_done);
  return line;
}

}  // namespace pt::cli
