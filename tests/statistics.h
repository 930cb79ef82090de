// The statistics the sampling and light-transport tests stand on: Pearson's
// chi-square goodness-of-fit test (p-value from the regularised incomplete
// gamma function) and the mean and standard error of independent estimates,
// with the z thresholds every test quotes for its false-failure probability.
#pragma once

#include <cstddef>
#include <span>
#include <string>

namespace pt::test {

/// Two-sided z thresholds and their false-failure probabilities under a
/// normal sampling distribution: P(|Z| > 4.5) = 6.8e-6, P(|Z| > 5) = 5.7e-7.
inline constexpr double kZ45 = 4.5;
inline constexpr double kZ5 = 5.0;

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

}  // namespace pt::test
