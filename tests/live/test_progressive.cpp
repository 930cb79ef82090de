// The live view's schedule: the samples of each progressive step and the
// resolution of a frame while the camera moves, as pure functions of rates.
#include <gtest/gtest.h>

#include "live/progressive.h"

namespace pt::live {
namespace {

TEST(Progressive, StepsShowOneFourSixteenSixtyFourSamples) {
  uint32_t done = 0;
  std::vector<uint32_t> shown;
  while (uint32_t step = next_step(done, 64, 0.0, 0.25)) shown.push_back(done += step);
  EXPECT_EQ(shown, (std::vector<uint32_t>{1, 4, 16, 64}));
  EXPECT_EQ(next_step(60, 64, 0.0, 0.25), 4u) << "never past the target";
  EXPECT_EQ(next_step(64, 64, 0.0, 0.25), 0u);
}

TEST(Progressive, AStepTakesAtMostTheLongestStepAndAtLeastOneSample) {
  EXPECT_EQ(next_step(64, 1024, 0.01, 0.25), 25u);  // 192 samples would take 1.92 s
  EXPECT_EQ(next_step(64, 1024, 10.0, 0.25), 1u);   // one sample is 10 s: one at a time
  EXPECT_EQ(next_step(4, 1024, 0.001, 0.25), 12u);  // under the cap: three times the samples so far
}

TEST(Progressive, ThePreviewIsTheLargestImageWithinTheFrameBudget) {
  const double budget = 1.0 / 30;
  EXPECT_EQ(preview_divisor(0, 0.0, budget), 1) << "unknown: full resolution";
  EXPECT_EQ(preview_divisor(0, 0.010, budget), 1);
  EXPECT_EQ(preview_divisor(0, 0.100, budget), 2);  // 0.025 s at half resolution
  EXPECT_EQ(preview_divisor(0, 0.500, budget), 4);  // 0.031 s at a quarter
  EXPECT_EQ(preview_divisor(0, 100.0, budget), 8);  // the smallest there is
  EXPECT_EQ(preview_divisor(2, 0.001, budget), 2) << "a fixed choice stands";
  EXPECT_EQ(preview_side(321, 2), 161);
  EXPECT_EQ(preview_side(320, 8), 40);
}

}  // namespace
}  // namespace pt::live
