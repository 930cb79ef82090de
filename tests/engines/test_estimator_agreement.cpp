// Hemisphere sampling and light importance sampling estimate the same image:
// on the built-in area-lit scene (scenes/cornell_spheres.dae) the per-pixel
// difference D = hemisphere - light sampling has expectation 0 in every pixel,
// and pixels are independent, so the mean of D over a set of pixels divided by
// its standard error is a z statistic.
//
// 48 x 36 pixels, 192 samples, -l 4 (4 hemisphere rays per vertex), maximum
// depth 1 and 3: per channel, over the whole image and over each of 16 blocks
// of 12 x 9 pixels, |z| < 5 (false failure 5.7e-7 per comparison; 2 x 3 x 17 =
// 102 comparisons per engine, < 6e-5 in all), and the whole image's SE < 1% of
// its mean (it is about 0.8%), so that the two estimators' image means differing
// by 6.6% (5.3% at the measured SE) fail with probability 0.95 (z threshold 5
// plus 1.645). The test has power: the course renderer's
// area-light quirk (colour / area * cos when a ray hits the light) must be
// detected (|z| > 5), even at 16 samples. About 4 s per engine.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/engines_under_test.h"
#include "io/camera_setup.h"
#include "support/statistics.h"
#include "support/test_support.h"

namespace pt {
namespace {

constexpr int kWidth = 48, kHeight = 36, kBlocksX = 4, kBlocksY = 4;

struct Difference {
  test::MeanError whole;
  std::vector<test::MeanError> blocks;
  double image_mean = 0.0;
};

/// Per-pixel hemisphere - light-sampling difference in channel `c`, summarised.
Difference difference(const Film& hemisphere, const Film& light, int c) {
  Difference d;
  std::vector<double> all;
  std::vector<std::vector<double>> blocks(kBlocksX * kBlocksY);
  double sum = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      size_t i = light.index(x, y);
      double v = double(hemisphere.radiance[i][c]) - light.radiance[i][c];
      all.push_back(v);
      blocks[(y * kBlocksY / kHeight) * kBlocksX + x * kBlocksX / kWidth].push_back(v);
      sum += light.radiance[i][c];
    }
  d.whole = test::mean_and_error(all);
  for (const auto& b : blocks) d.blocks.push_back(test::mean_and_error(b));
  d.image_mean = sum / all.size();
  return d;
}

struct RenderPair {
  Film hemisphere, light;
};

RenderPair render_both(const test::EngineUnderTest& e, const Scene& s, int spp, int max_depth, bool quirk) {
  const Camera camera = resolve_camera(s, kWidth, kHeight);
  RenderSettings rs{.width = kWidth,
                    .height = kHeight,
                    .samples_per_pixel = spp,
                    .light_samples = 4,
                    .max_depth = max_depth,
                    .adaptive_tolerance = 0.0f,
                    .threads = 2,
                    .cs184_light_quirk = quirk};
  RenderPair r;
  r.light = e.render(s, camera, rs).film;
  rs.direct = DirectLighting::kHemisphere;
  r.hemisphere = e.render(s, camera, rs).film;
  return r;
}

TEST(EstimatorAgreement, HemisphereAndLightSamplingAgreeOnTheCornellScene) {
  const Scene s = load_collada_file(test::project_scene("cornell_spheres.dae")).scene;
  for (const test::EngineUnderTest& e : test::engines_under_test())
    for (int m : {1, 3}) {
      RenderPair r = render_both(e, s, 192, m, false);
      for (int c = 0; c < 3; ++c) {
        Difference d = difference(r.hemisphere, r.light, c);
        std::string what = e.name + ", m=" + std::to_string(m) + ", channel " + std::to_string(c);
        EXPECT_LT(std::fabs(test::z_score(d.whole, 0.0)), test::kZ5)
            << what << ": mean difference " << d.whole.mean << " +- " << d.whole.standard_error;
        EXPECT_LT(d.whole.standard_error, 0.01 * d.image_mean) << what << ": too noisy to mean anything";
        for (size_t b = 0; b < d.blocks.size(); ++b)
          EXPECT_LT(std::fabs(test::z_score(d.blocks[b], 0.0)), test::kZ5)
              << what << ", block " << b << ": mean difference " << d.blocks[b].mean << " +- "
              << d.blocks[b].standard_error;
      }
    }
}

// The same comparison must reject an inconsistent pair of estimators.
TEST(EstimatorAgreement, DetectsTheCourseRenderersAreaLightQuirk) {
  const Scene s = load_collada_file(test::project_scene("cornell_spheres.dae")).scene;
  for (const test::EngineUnderTest& e : test::engines_under_test()) {
    RenderPair r = render_both(e, s, 16, 1, true);
    for (int c = 0; c < 3; ++c)
      EXPECT_GT(std::fabs(test::z_score(difference(r.hemisphere, r.light, c).whole, 0.0)), test::kZ5)
          << e.name << ", channel " << c;
  }
}

}  // namespace
}  // namespace pt
