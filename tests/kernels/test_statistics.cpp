// The test suite's own statistics (tests/support/statistics.h) checked against closed
// forms, since every statistical test's stated confidence rests on them: the
// chi-square tail for 1 degree of freedom is erfc(sqrt(x / 2)) and for 2k
// degrees of freedom e^(-x/2) sum_{i<k} (x/2)^i / i!. Nothing here samples:
// every check is exact (to 1e-8 relative or better), with no false failures.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "support/statistics.h"

namespace pt::test {
namespace {

double even_dof_tail(double x, int dof) {
  double term = std::exp(-0.5 * x), sum = 0.0;
  for (int i = 0; i < dof / 2; ++i) {
    sum += term;
    term *= 0.5 * x / (i + 1);
  }
  return sum;
}

TEST(ChiSquareTail, MatchesClosedForms) {
  for (double x : {0.01, 0.5, 1.0, 3.841458820694124, 10.0, 30.0})
    EXPECT_NEAR(chi_square_tail(x, 1), std::erfc(std::sqrt(0.5 * x)), 1e-12 + 1e-9 * std::erfc(std::sqrt(0.5 * x)))
        << x;
  for (int dof : {2, 10, 64, 512, 1022})
    for (double f : {0.5, 0.9, 1.0, 1.1, 1.3, 2.0}) {
      double x = f * dof, expected = even_dof_tail(x, dof);
      EXPECT_NEAR(chi_square_tail(x, dof), expected, 1e-12 + 1e-8 * expected) << "dof " << dof << " x " << x;
    }
  EXPECT_NEAR(chi_square_tail(3.841458820694124, 1), 0.05, 1e-12);
  EXPECT_EQ(chi_square_tail(0.0, 7), 1.0);
}

TEST(ChiSquareTest, PerfectFitAndImpossibleCounts) {
  std::vector<double> expected(100, 50.0), observed = expected;
  ChiSquareResult r = chi_square_test(observed, expected);
  EXPECT_EQ(r.statistic, 0.0);
  EXPECT_EQ(r.dof, 99);
  EXPECT_EQ(r.p_value, 1.0);
  expected.push_back(0.0);
  observed.push_back(1.0);
  EXPECT_EQ(chi_square_test(observed, expected).p_value, 0.0) << "a sample where none can fall";
}

TEST(ChiSquareTest, SmallBinsArePooled) {
  // Two bins of expected 2 pool into one of expected 4 (still < 5, but pooled once).
  const std::vector<double> expected = {100, 100, 2, 2}, observed = {100, 100, 4, 0};
  ChiSquareResult r = chi_square_test(observed, expected);
  EXPECT_EQ(r.dof, 2);
  EXPECT_NEAR(r.statistic, 0.0, 1e-12);
}

TEST(MeanAndError, KnownValues) {
  const std::vector<double> v = {1, 2, 3, 4};
  MeanError m = mean_and_error(v);
  EXPECT_DOUBLE_EQ(m.mean, 2.5);
  EXPECT_DOUBLE_EQ(m.standard_error, std::sqrt(5.0 / 3.0 / 4.0));
  EXPECT_DOUBLE_EQ(z_score(m, 2.5 + 2 * m.standard_error), -2.0);
}

}  // namespace
}  // namespace pt::test
