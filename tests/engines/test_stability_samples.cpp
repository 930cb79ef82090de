// Stability of the sample pipeline, for every engine under test: adaptive
// sampling on black pixels (mean 0) and on directly seen lights stops at its
// first check without dividing by zero and never before its first batch;
// samples at the edge of the unit square, grazing rays and degenerate
// triangles never put NaN or infinity into the framebuffer, and no shared
// scene discards a single invalid sample in any direct-lighting mode. Every
// check is exact (counts, finiteness, exact values): no bias bound applies.
#include <cmath>
#include <limits>

#include "support/engines_under_test.h"
#include "io/camera_setup.h"
#include "kernels/scene/lights.h"
#include "kernels/render/pixel_accumulator.h"
#include "kernels/math/sampling.h"
#include "support/stability_scenes.h"
#include "support/test_support.h"

namespace pt {
namespace {

using test::engines_under_test;

// ---------------------------------------------------------- adaptive sampling

TEST(AdaptiveSampling, TheStoppingRuleIsDefinedForBlackAndConstantPixels) {
  PixelMoments none;
  EXPECT_FALSE(pixel_converged(none, 0, 0.05));  // no samples: keep going
  PixelMoments black;
  for (int i = 0; i < 8; ++i) black.add(0.0);
  EXPECT_FALSE(pixel_converged(black, 1, 0.05));  // one sample has no variance estimate
  EXPECT_TRUE(pixel_converged(black, 8, 0.05));   // 0 <= 0.05 * 0, not 0 / 0
  EXPECT_EQ(variance_of_mean(black, 8), 0.0);
  PixelMoments constant;
  for (int i = 0; i < 8; ++i) constant.add(3.0);
  EXPECT_TRUE(pixel_converged(constant, 8, 0.05));
  PixelMoments noisy;
  for (int i = 0; i < 8; ++i) noisy.add(i % 2 ? 0.0 : 2.0);
  EXPECT_FALSE(pixel_converged(noisy, 8, 0.05));
}

/// Where pixel (x, y) of a w x w image through camera_facing_minus_z() looks,
/// judged for its whole footprint (with a small margin): the light occupies
/// |X|, |Y| < 0.5 in tangent space, the floor Y < -0.5, |X| < |Y|.
enum class Region { kLight, kBlack, kFloor, kMixed };

Region region_of(int x, int y, int w) {
  const double m = 1e-3, size = 2.0 / w;
  double x0 = -1 + x * size - m, x1 = -1 + (x + 1) * size + m;
  double y1 = 1 - y * size + m, y0 = 1 - (y + 1) * size - m;
  if (x0 > -0.5 && x1 < 0.5 && y0 > -0.5 && y1 < 0.5) return Region::kLight;
  bool misses_light = x1 < -0.5 || x0 > 0.5 || y1 < -0.5 || y0 > 0.5;
  if (y0 > -0.5 && misses_light) return Region::kBlack;
  if (y1 < -0.5 && std::max(std::fabs(x0), std::fabs(x1)) < std::fabs(y1)) return Region::kFloor;
  return Region::kMixed;
}

TEST(AdaptiveSampling, BlackPixelsAndSeenLightsStopAtTheFirstCheckAndNeverBeforeTheFirstBatch) {
  Scene scene = test::light_seen_head_on();
  Camera cam = test::camera_facing_minus_z();
  const int w = 32, spp = 64;
  for (const test::EngineUnderTest& engine : engines_under_test())
    for (int batch : {1, 8, 128}) {
      RenderSettings rs{.width = w,
                        .height = w,
                        .samples_per_pixel = spp,
                        .max_depth = 3,
                        .adaptive_batch = batch,
                        .adaptive_tolerance = 0.05f,
                        .threads = 2};
      RenderOutput out = engine.render(scene, cam, rs);
      // The first check that can stop a pixel: after `batch` samples, but a
      // variance needs two; with batch > spp there is no check at all.
      const uint32_t first_stop = batch > spp ? spp : std::max(batch, 2);
      const std::string what = engine.name + " batch " + std::to_string(batch);
      EXPECT_EQ(out.stats.invalid_samples, 0u) << what;
      int counted[4] = {}, floor_continued = 0;
      for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x) {
          size_t i = out.film.index(x, y);
          uint32_t n = out.film.samples[i];
          ASSERT_TRUE(is_finite(out.film.radiance[i])) << what;
          ASSERT_GE(n, static_cast<uint32_t>(std::min(batch, spp))) << what << " stopped before its first batch";
          ASSERT_LE(n, static_cast<uint32_t>(spp)) << what;
          Region r = region_of(x, y, w);
          ++counted[static_cast<int>(r)];
          if (r == Region::kLight) {
            EXPECT_EQ(out.film.radiance[i], float3(3.0f)) << what << " at " << x << "," << y;
            EXPECT_EQ(n, first_stop) << what << " light pixel " << x << "," << y;
          } else if (r == Region::kBlack) {
            EXPECT_EQ(out.film.radiance[i], float3(0.0f)) << what << " at " << x << "," << y;
            EXPECT_EQ(n, first_stop) << what << " black pixel " << x << "," << y;
          } else if (r == Region::kFloor) {
            floor_continued += n > first_stop;
          }
        }
      // The classification found every kind, and noisy floor pixels sampled on.
      EXPECT_GT(counted[0] * counted[1] * counted[2], 0) << what;
      if (batch < spp) { EXPECT_GT(floor_continued, 0) << what << ": adaptive sampling stopped noisy pixels"; }
    }
}

// ------------------------------------------------------------ invalid samples

TEST(InvalidSamples, TheAccumulatorDropsAndCountsThem) {
  PixelAccumulator acc;
  EXPECT_TRUE(acc.add({1, 2, 3}));
  EXPECT_FALSE(acc.add({std::numeric_limits<float>::quiet_NaN(), 0, 0}));
  EXPECT_FALSE(acc.add({0, std::numeric_limits<float>::infinity(), 0}));
  EXPECT_EQ(acc.samples, 3u);  // counted as black samples
  EXPECT_EQ(acc.mean(), float3(1.0f / 3, 2.0f / 3, 1.0f));
}

TEST(InvalidSamples, WarpsStayFiniteAtTheEdgesOfTheUnitSquare) {
  const float below_one = std::nextafter(1.0f, 0.0f);
  const float edges[] = {0.0f, std::numeric_limits<float>::denorm_min(), 0.5f, below_one};
  AreaLight light{{0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}, float3(1.0f), 1.0f};
  auto unit = [](Vec3T<float> v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) &&
           std::fabs(v.x * v.x + v.y * v.y + v.z * v.z - 1.0f) < 1e-5f;
  };
  for (float u1 : edges)
    for (float u2 : edges) {
      EXPECT_TRUE(unit(sample_uniform_hemisphere(u1, u2))) << u1 << " " << u2;
      EXPECT_TRUE(unit(sample_cosine_hemisphere(u1, u2))) << u1 << " " << u2;
      EXPECT_TRUE(unit(sample_uniform_sphere(u1, u2))) << u1 << " " << u2;
      EXPECT_TRUE(unit(sample_sky_direction(u1, u2))) << u1 << " " << u2;
      AreaLightSampleT<float> ls = sample_area_light<float>(light, 0.3f, 0.0f, -0.2f, u1, u2);
      EXPECT_TRUE(std::isfinite(ls.pdf) && ls.pdf > 0 && unit(ls.wi)) << u1 << " " << u2;
    }
}

const DirectLighting kAllDirect[] = {DirectLighting::kLightSampling, DirectLighting::kHemisphere,
                                     DirectLighting::kCosine, DirectLighting::kMis};

/// Renders every direct mode (and the independent sampler) with every engine and
/// expects a finite framebuffer and zero discarded samples.
void expect_no_invalid_samples(const Scene& scene, const Camera& cam, int w, int h, int spp, const std::string& what) {
  for (const test::EngineUnderTest& engine : engines_under_test())
    for (int mode = 0; mode < 5; ++mode) {
      RenderSettings rs = test::fixed_settings(w, h, spp);
      rs.max_depth = 4;
      rs.seed = 0;
      rs.direct = kAllDirect[mode % 4];
      rs.sampler = mode == 4 ? PixelSampler::kIndependent : PixelSampler::kSobol;
      RenderOutput out = engine.render(scene, cam, rs);
      EXPECT_EQ(out.stats.invalid_samples, 0u) << what << ", " << engine.name << ", mode " << mode;
      for (const float3& c : out.film.radiance) ASSERT_TRUE(is_finite(c)) << what << ", " << engine.name;
    }
}

TEST(InvalidSamples, NoneFromDegenerateTrianglesOrGrazingRays) {
  Scene scene = test::floor_with_degenerate_triangles();
  expect_no_invalid_samples(scene, test::camera_above_floor(), 24, 24, 16, "degenerate triangles from above");
  expect_no_invalid_samples(scene, test::camera_grazing_floor(), 24, 24, 16, "grazing the floor");
}

// Cosine sampling with -l > 1 under delta lights (whose light count differs from
// the sampled-light count): every hit-finding estimator's queue must fit.
TEST(InvalidSamples, CosineSamplingWithManyLightSamplesOnDeltaLights) {
  Scene scene = test::floor_under_delta_lights(true, true);
  for (const test::EngineUnderTest& engine : engines_under_test()) {
    RenderSettings rs{.width = 16,
                      .height = 16,
                      .samples_per_pixel = 4,
                      .light_samples = 4,
                      .max_depth = 3,
                      .adaptive_tolerance = 0.0f,
                      .direct = DirectLighting::kCosine};
    RenderOutput out = engine.render(scene, test::camera_above_floor(), rs);
    EXPECT_EQ(out.stats.invalid_samples, 0u) << engine.name;
  }
}

TEST(InvalidSamples, NoneOnAnySharedScene) {
  PT_REQUIRE_SHARED_SCENES();
  for (const std::string& name : test::shared_scene_names()) {
    Scene scene = load_collada_file(test::shared_scene(name)).scene;
    expect_no_invalid_samples(scene, resolve_camera(scene, 32, 24), 32, 24, 4, name);
  }
}

}  // namespace
}  // namespace pt
