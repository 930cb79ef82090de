// The assignment's adaptive sampling test on a pixel's illuminance samples:
// stop when the 95% confidence interval 1.96 sigma / sqrt(n) is at most
// tolerance * mean. Checked only after whole batches.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"

namespace pt {

/// Running sums of one pixel's sample illuminances.
struct PixelMoments {
  double s1 = 0.0, s2 = 0.0;
  void add(double x) {
    s1 += x;
    s2 += x * x;
  }
};

inline namespace PT_ISA_NS {
/// Unbiased sample variance of the n samples, divided by n: the variance of
/// their mean. 0 for n < 2.
inline double variance_of_mean(const PixelMoments& m, uint32_t n) {
  if (n < 2) return 0.0;
  return std::max(0.0, (m.s2 - m.s1 * m.s1 / n) / (n - 1)) / n;
}

/// True when n > 1 samples with these moments meet the tolerance. A pixel of
/// constant value (including black) has sigma = 0 and converges at once.
inline bool pixel_converged(const PixelMoments& m, uint32_t n, double tolerance) {
  if (n < 2) return false;
  double mean = m.s1 / n;
  double var = std::max(0.0, (m.s2 - m.s1 * m.s1 / n) / (n - 1));
  double interval = 1.96 * std::sqrt(var) / std::sqrt(double(n));
  return interval <= tolerance * mean;
}

}  // namespace PT_ISA_NS
}  // namespace pt
