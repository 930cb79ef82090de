// The error a pass-based render estimates for its own image, with no reference,
// from the means every pixel kept at its last three power-of-two sample counts
// (PixelAccumulator::at_powers). With P samples, D(P) is the mean squared
// change from the image at P/2 samples to the image at P. If the changes from
// one power of two to the next are uncorrelated and shrink by a steady ratio
// r = D(P) / D(P/2), the image's mean squared error against the converged
// image is the sum of the changes still to come: MSE(P) = D(P) r / (1 - r).
// That holds for independent samples (r = 1/2, MSE = D) and for the nested
// strata of Owen-scrambled Sobol points, whose first P/2 points are themselves
// a stratified set (r near 2^-1.5 for edges, lower for smooth regions). The
// whole image sums D over every pixel and channel and takes r as the median of
// its 8x8 blocks' ratios (robust to the few pixels a rare bright path swings);
// a pixel's estimate is its own D(P) with the image's r.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/render/accumulation.h"

namespace pt {

/// The pooled ratio r is kept inside [kMinStepRatio, kMaxStepRatio]: a ratio
/// from few or noisy differences can come out near 0 (which would claim no
/// error) or at or above 1 (an infinite sum). 1/8 is the N^-3 decay of the
/// best-behaved integrands under Owen scrambling; 0.9 caps the factor
/// r / (1 - r) at 9, nine times the independent-sample figure.
inline constexpr double kMinStepRatio = 0.125;
inline constexpr double kMaxStepRatio = 0.9;

/// The whole image's estimate.
struct ImageErrorEstimate {
  bool available = false;    ///< every pixel holds at least 4 samples
  double rmse = 0.0;         ///< over the linear RGB values of every pixel
  double relative_rmse = 0;  ///< rmse / the image's mean value (0 for a black image)
  double step_ratio = 0.0;   ///< the ratio r used, after clamping
  uint32_t at_samples = 0;   ///< the power-of-two count P the estimate is for (the smallest over the pixels)
};

/// The mean over a pixel's three channels of |I(P/2) - I(P)|^2 (half) and of
/// |I(P/4) - I(P/2)|^2 (quarter); both 0 below 4 samples.
struct StepChanges {
  double half = 0.0, quarter = 0.0;
};
StepChanges step_changes(const PixelAccumulator& p);

/// r / (1 - r) with r = `ratio` clamped as above.
double remaining_error_factor(double ratio);

/// The whole image's estimate from the accumulated pixels of the render region.
/// `scale` multiplies the estimate (1 but in tests that check calibration fails
/// on a scaled estimator).
ImageErrorEstimate estimate_image_error(const Accumulation& acc, double scale = 1.0);

/// Each pixel's estimated RMSE over its channels, row-major over acc.area:
/// its own D(P) with the image's ratio.
std::vector<float> estimate_pixel_error(const Accumulation& acc);

}  // namespace pt
