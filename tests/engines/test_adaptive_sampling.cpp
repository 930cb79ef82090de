// Adaptive sampling (-a BATCH TOL): a pixel whose samples are all equal has
// sigma = 0 and stops after the first batch; a pixel whose relative noise
// needs more samples than the maximum is sampled to the maximum; every pixel
// stops at a check (every BATCH samples, or with Sobol points at the powers of
// two from BATCH up); with adaptive sampling off every pixel takes the
// maximum. Checked through Film::samples, for every engine. No estimate is
// compared with a value, so no bias bound applies: the counts are exact, and
// the one statement about noise (a noisy pixel never stops early) fails only
// on a > 7-sigma event of its sample spread (below 1e-9 over the test).
#include <string>

#include <gtest/gtest.h>

#include "support/engines_under_test.h"
#include "io/camera_setup.h"
#include "support/scene_builders.h"
#include "support/test_support.h"

namespace pt {
namespace {

constexpr int kBatch = 32, kMax = 256;

RenderSettings adaptive_settings() {
  RenderSettings rs = test::fixed_settings(16, 16, kMax);
  rs.adaptive_batch = kBatch;
  rs.adaptive_tolerance = 0.05f;
  return rs;
}

Scene plane(bool sky) {
  Scene s;
  const float h = 10.0f;
  test::add_quad(s, {-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}, {0, 1, 0}, test::add_material(s, float3(0.5f)));
  if (sky) s.sky = SkyLight{float3(1.0f)};
  else s.directional_lights.push_back({normalize(float3{1, 2, 0}), float3(2.0f)});
  test::finish_scene(s);
  return s;
}

// A plane under a directional light: every sample of a pixel that sees only
// the plane is the same number (the light has no noise), and so is every
// sample of a pixel that sees nothing (0).
TEST(AdaptiveSampling, ConstantPixelsStopAfterTheFirstBatch) {
  const Scene s = plane(false);
  const Camera down = test::look_at({0, 1, 0.5f}, {0, 0, 0}, 0.5f, 0.5f);
  const Camera up = test::look_at({0, 1, 0.5f}, {0, 2, 0}, 0.5f, 0.5f);
  for (const test::EngineUnderTest& e : test::engines_under_test())
    for (const Camera& camera : {down, up}) {
      RenderOutput out = e.render(s, camera, adaptive_settings());
      for (size_t i = 0; i < out.film.samples.size(); ++i)
        ASSERT_EQ(out.film.samples[i], uint32_t(kBatch)) << e.name << " pixel " << i;
    }
}

// A plane under a uniform sky with one light sample: each sample is
// 2 rho Ls u (u uniform), relative sigma 1/sqrt(3), so the stopping rule
// 1.96 sigma / sqrt(n) <= 0.05 mean needs n >= 512 > the maximum 256. (Stopping
// earlier needs a sample sigma below 0.66 of the true one after >= 32 samples,
// a > 7-sigma event for this distribution.)
TEST(AdaptiveSampling, NoisyPixelsAreSampledToTheMaximum) {
  const Scene s = plane(true);
  const Camera camera = test::look_at({0, 1, 0.5f}, {0, 0, 0}, 0.5f, 0.5f);  // sees only the plane
  for (const test::EngineUnderTest& e : test::engines_under_test()) {
    RenderOutput out = e.render(s, camera, adaptive_settings());
    for (size_t i = 0; i < out.film.samples.size(); ++i)
      ASSERT_EQ(out.film.samples[i], uint32_t(kMax)) << e.name << " pixel " << i;
    EXPECT_EQ(out.stats.samples, uint64_t(kMax) * out.film.samples.size());
  }
}

// On the Cornell scene pixels converge at different checks. With independent
// numbers each stops on a batch boundary (or at the maximum); with Sobol points
// only at the powers of two from BATCH up (32, 64, 128; else the maximum), where
// its points are complete nets. Some stop early while others do not. Adaptive
// sampling off (tolerance 0): the maximum everywhere.
TEST(AdaptiveSampling, StopsOnlyAtChecksAndOffMeansEverySample) {
  const Scene s = load_collada_file(test::project_scene("cornell_spheres.dae")).scene;
  const Camera camera = resolve_camera(s, 16, 16);
  for (PixelSampler sampler : {PixelSampler::kIndependent, PixelSampler::kSobol})
    for (const test::EngineUnderTest& e : test::engines_under_test()) {
      RenderSettings rs = adaptive_settings();
      rs.max_depth = 2;
      rs.sampler = sampler;
      RenderOutput out = e.render(s, camera, rs);
      int early = 0, full = 0, off_power_of_two = 0;
      for (uint32_t n : out.film.samples) {
        ASSERT_TRUE(n % kBatch == 0 || n == uint32_t(kMax)) << e.name << ": " << n << " samples";
        if (sampler == PixelSampler::kSobol) {
          ASSERT_TRUE((n & (n - 1)) == 0 || n == uint32_t(kMax)) << e.name << ": " << n << " Sobol samples";
        }
        ASSERT_GE(n, uint32_t(kBatch));
        early += n < uint32_t(kMax);
        full += n == uint32_t(kMax);
        off_power_of_two += (n & (n - 1)) != 0;
      }
      EXPECT_GT(early, 0) << e.name;
      EXPECT_GT(full, 0) << e.name;
      // Power: independent numbers do stop between powers of two here (96, 160, ...).
      if (sampler == PixelSampler::kIndependent) { EXPECT_GT(off_power_of_two, 0) << e.name; }
      rs.adaptive_tolerance = 0.0f;
      out = e.render(s, camera, rs);
      for (uint32_t n : out.film.samples) ASSERT_EQ(n, uint32_t(kMax)) << e.name;
    }
}

// With Sobol points and a batch that is not a power of two, the first check
// is at the next power of two (48 -> 64), and constant pixels stop there.
TEST(AdaptiveSampling, SobolChecksStartAtThePowerOfTwoAboveTheBatch) {
  const Scene s = plane(false);
  const Camera down = test::look_at({0, 1, 0.5f}, {0, 0, 0}, 0.5f, 0.5f);
  for (const test::EngineUnderTest& e : test::engines_under_test()) {
    RenderSettings rs = adaptive_settings();
    rs.adaptive_batch = 48;
    rs.sampler = PixelSampler::kSobol;
    RenderOutput out = e.render(s, down, rs);
    for (size_t i = 0; i < out.film.samples.size(); ++i)
      ASSERT_EQ(out.film.samples[i], 64u) << e.name << " pixel " << i;
    rs.sampler = PixelSampler::kIndependent;
    out = e.render(s, down, rs);
    for (size_t i = 0; i < out.film.samples.size(); ++i)
      ASSERT_EQ(out.film.samples[i], 48u) << e.name << " pixel " << i;
  }
}

}  // namespace
}  // namespace pt
