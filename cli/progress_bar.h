// A progress bar with ETA on standard error, drawn only when it is a terminal.
// Safe to update from several threads; redraws at most ten times a second.
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>

namespace pt::cli {

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled);
  void update(double fraction);
  /// Clears the bar's line.
  void finish();

 private:
  bool enabled_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::mutex mutex_;
};

}  // namespace pt::cli
