// Film checks: per-channel pixel statistics and exact comparisons.
#include "support/film_checks.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace pt::test {

MeanError film_channel_mean(const Film& film, int channel) {
  std::vector<double> v;
  v.reserve(film.radiance.size());
  for (const float3& p : film.radiance) v.push_back(p[channel]);
  return mean_and_error(v);
}

void expect_film_estimates(const Film& film, const float3& expected, const std::string& what, double detectable_bias) {
  for (int c = 0; c < 3; ++c) {
    if (expected[c] == 0.0f) {
      for (const float3& p : film.radiance) ASSERT_EQ(p[c], 0.0f) << what << ", channel " << c << " must be black";
      continue;
    }
    MeanError m = film_channel_mean(film, c);
    if (m.standard_error == 0.0) {  // a zero-variance estimator: exact up to rounding
      EXPECT_NEAR(m.mean, expected[c], 1e-6 * expected[c]) << what << ", channel " << c << " (no noise)";
      continue;
    }
    EXPECT_LT(std::fabs(z_score(m, expected[c])), kZ5)
        << what << ", channel " << c << ": mean " << m.mean << " +- " << m.standard_error << " vs exact " << expected[c]
        << " (z = " << z_score(m, expected[c]) << ")";
    EXPECT_LE(m.standard_error, detectable_bias / (kZ5 + kZ95) * expected[c])
        << what << ", channel " << c << ": standard error " << m.standard_error / expected[c]
        << " of the expected value, too large to see a bias of " << detectable_bias;
  }
}

void expect_film_equals(const Film& film, const float3& expected, const std::string& what, double relative) {
  int reported = 0;
  for (size_t i = 0; i < film.radiance.size() && reported < 5; ++i)
    for (int c = 0; c < 3; ++c)
      if (!(std::fabs(film.radiance[i][c] - expected[c]) <= relative * std::fabs(expected[c]))) {
        ADD_FAILURE() << what << ", pixel " << i << " channel " << c << ": " << film.radiance[i][c] << " vs exact "
                      << expected[c];
        ++reported;
      }
}

}  // namespace pt::test
