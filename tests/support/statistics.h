// The statistics the sampling, light-transport, engine and stability tests
// stand on: Pearson's chi-square goodness-of-fit test (p-value from the
// regularised incomplete gamma function), the mean and standard error of
// independent estimates, the z thresholds every test quotes for its
// false-failure probability, and films compared within their noise (they
// read the film's per-pixel variance of the mean, so pixels are the
// independent units and no test needs repeated renders).
#pragma once

#include <cstddef>
#include <span>
#include <string>

#include "kernels/render/film.h"

namespace pt::test {

/// Two-sided z thresholds and their false-failure probabilities under a
/// normal sampling distribution: P(|Z| > 4.5) = 6.8e-6, P(|Z| > 5) = 5.7e-7.
inline constexpr double kZ45 = 4.5;
inline constexpr double kZ5 = 5.0;
/// One-sided 95% quantile of the normal: a test whose threshold lies kZ95
/// standard errors short of an effect detects that effect with probability 0.95.
inline constexpr double kZ95 = 1.6448536;

/// P(X >= x) for X chi-square distributed with `dof` > 0 degrees of freedom.
double chi_square_tail(double x, double dof);

struct ChiSquareResult {
  double statistic = 0.0;
  int dof = 0;
  double p_value = 1.0;
  std::string summary;  ///< statistic, dof, p and the bin that deviates most, for failure messages
};

/// Pearson's test of `observed` counts against `expected` counts (both sum to
/// the sample size). Bins with expected < 5 are pooled into one (as pbrt's
/// chi2test does); counts in a bin whose expected count is 0 give p = 0.
ChiSquareResult chi_square_test(std::span<const double> observed, std::span<const double> expected);

struct MeanError {
  double mean = 0.0;
  double standard_error = 0.0;  ///< sample standard deviation / sqrt(n)
  size_t n = 0;
};

/// Mean and standard error of n >= 2 independent, identically distributed values.
MeanError mean_and_error(std::span<const double> values);

/// (mean - expected) / standard_error; +-inf when the error is 0 and the means differ.
double z_score(const MeanError& m, double expected);

/// Mean over pixels of the pixels' mean illuminance, and its standard error
/// sqrt(sum of the pixels' variances of the mean) / pixels.
struct ImageMean {
  double mean = 0.0;
  double standard_error = 0.0;
};
ImageMean image_mean(const Film& film);

/// Average over pixels of the variance of one sample's illuminance
/// (variance of the mean x samples): what one more sample costs in noise.
double per_sample_variance(const Film& film);

/// z = (mean(a) - mean(b)) / sqrt(se(a)^2 + se(b)^2), approximately standard
/// normal when both films estimate the same image (many pixels and samples).
double mean_difference_z(const Film& a, const Film& b);

/// Two-sided z bound with false-alarm probability 1e-5 under the normal approximation.
inline constexpr double kZ1e5 = 4.42;

/// Stouffer's combined score over pixels with noise: sum of the per-pixel
/// z = (Y_a - Y_b) / sqrt(var_a + var_b), divided by sqrt(count). Standard
/// normal when a and b estimate the same image; unlike the image mean it is
/// not drowned by a few very noisy pixels (the edges of a visible light).
double stouffer_z(const Film& a, const Film& b);

/// The smallest relative bias of a against b (a's radiance scaled by 1 +
/// bias in its noisy pixels) that moves stouffer_z beyond 5 with probability
/// 0.95: (5 + kZ95) sqrt(count) / sum of Y_a / sqrt(var_a + var_b) over the
/// pixels with noise. Pixels whose standard error is below 1e-4 of their value
/// are left out of the sum (they still count): rounding noise on an exact
/// value (a light or the sky seen directly) would claim a bias of 1e-8.
double stouffer_detectable_bias(const Film& a, const Film& b);

/// Asserts that a and b estimate the same image (renders with different
/// seeds, or of equivalent scenes): per pixel z = (Y_a - Y_b) / sqrt(var_a +
/// var_b) on illuminance, with var each pixel's variance of the mean. Under
/// agreement |z| > 3.29 has probability 0.001 (for near-normal means): at
/// most N * 0.001 + 5 sqrt(N * 0.001) such pixels (false alarm < 1e-6 for
/// independent pixels), none beyond 6.5 (Bonferroni at 1e-10 / N: a single
/// badly wrong pixel), |stouffer_z| < 5 (two-sided 6e-7: a bias too small to
/// show in single pixels), and noiseless pixels (variance 0 in both) equal
/// within 1e-6 relative. Nonfatal; prints the statistics and the smallest
/// bias the Stouffer bound detects (stouffer_detectable_bias).
void expect_same_image_within_noise(const Film& a, const Film& b, const std::string& what);

/// A copy of `film` with every radiance multiplied by `factor` (power checks).
Film scaled_film(const Film& film, float factor);

}  // namespace pt::test
