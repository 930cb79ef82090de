// --cs184-compat against the course renderer's own images (../shared/refs/
// course: CBbunny and CBspheres_lambertian at -m 1, 2 and 5, 256 x 192, 256
// samples, -l 4, adaptive sampling off, through the course's camera files).
// Every engine renders the same settings with the course's quirks; the image
// must match in mean illuminance within 1%, and in every 8 x 8 block.
//
// Decoding: the course writes each channel as floor(255 (L sqrt 2)^(1/2.2)),
// truncated, so a code v stands for the encoded values [v, v + 1) / 255: it is
// decoded at the middle of that interval, and its rounding variance is that of
// a uniform variable over the interval's linear width (d^2 / 12); code 0, most
// often an exact black, decodes to 0 with variance d^2 / 3. Pixels with a
// saturated channel (255) and the 48 x 5 watermark are left out.
//
// Block bound: the difference of the two block means (illuminance) divided by
// its standard deviation sqrt(sum over the block's pixels of (2 var_ours +
// var_rounding)) / n, where var_ours is our pixel's variance of its mean (the
// course's estimator has the same variance: same estimator, same samples) must
// stay below 5.5 (two-sided 3.8e-8 per block; 768 blocks x 6 images x 3
// engines: false failure < 6e-4). The image mean's own noise is below 0.1%
// (ours and the course's together 0.14%), so the 1% bound on the mean ratio
// detects a 1.2% bias with probability 0.95; a block check one of 7.1 (5.5 +
// 1.645) standard deviations of that block's mean difference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "support/engines_under_test.h"
#include "io/camera_setup.h"
#include "kernels/render/film.h"
#include "support/png_decode.h"
#include "support/test_support.h"

namespace pt {
namespace {

constexpr int kWidth = 256, kHeight = 192, kBlock = 8;
constexpr double kBlockZ = 5.5;

std::filesystem::path refs() { return test::shared_course_refs_dir(); }

/// Linear value of code v: the middle of its truncation interval, except for
/// 0, most often an exact black; and the variance of the rounding around it
/// (uniform over the interval; for 0, the second moment of [0, width) about 0).
double decode(int v) { return v == 0 ? 0.0 : std::pow((v + 0.5) / 255.0, 2.2) / std::sqrt(2.0); }
double rounding_variance(int v) {
  double width = (std::pow((v + 1) / 255.0, 2.2) - std::pow(v / 255.0, 2.2)) / std::sqrt(2.0);
  return width * width / (v == 0 ? 3.0 : 12.0);
}

constexpr double kLuma[3] = {0.2126, 0.7152, 0.0722};  // as illuminance() weighs channels

struct Comparison {
  double mean_ratio = 0.0;  ///< mean illuminance, ours / course
  double worst_z = 0.0;     ///< of the 8 x 8 blocks
  int worst_x = 0, worst_y = 0;
  int blocks = 0, blocks_over = 0;  ///< blocks compared, blocks beyond kBlockZ
};

Comparison compare(const Film& ours, const test::DecodedImage& course) {
  std::vector<double> y_course(size_t(kWidth) * kHeight), var_course(y_course.size());
  std::vector<bool> use(y_course.size(), true);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      size_t i = size_t(y) * kWidth + x;
      const uint8_t* px = &course.pixels[i * size_t(course.channels)];
      if ((y >= kHeight - 5 && x < 48) || px[0] == 255 || px[1] == 255 || px[2] == 255) use[i] = false;
      for (int c = 0; c < 3; ++c) {
        y_course[i] += kLuma[c] * decode(px[c]);
        var_course[i] += kLuma[c] * kLuma[c] * rounding_variance(px[c]);
      }
    }
  Comparison r;
  double sum_ours = 0.0, sum_course = 0.0;
  for (size_t i = 0; i < use.size(); ++i)
    if (use[i]) sum_ours += illuminance(ours.radiance[i]), sum_course += y_course[i];
  r.mean_ratio = sum_ours / sum_course;
  for (int by = 0; by < kHeight; by += kBlock)
    for (int bx = 0; bx < kWidth; bx += kBlock) {
      double d = 0.0, var = 0.0;
      int n = 0;
      for (int y = by; y < by + kBlock; ++y)
        for (int x = bx; x < bx + kBlock; ++x) {
          size_t i = size_t(y) * kWidth + x;
          if (!use[i]) continue;
          d += illuminance(ours.radiance[i]) - y_course[i];
          var += 2.0 * ours.variance[i] + var_course[i];
          ++n;
        }
      if (n < kBlock * kBlock / 2 || var <= 0.0) continue;
      double z = std::fabs(d) / std::sqrt(var);
      ++r.blocks;
      r.blocks_over += z >= kBlockZ;
      if (z > r.worst_z) r.worst_z = z, r.worst_x = bx, r.worst_y = by;
    }
  return r;
}

TEST(CourseImages, CompatReproducesTheCourseRenderersImages) {
  PT_REQUIRE_SHARED_SCENES();
  PT_REQUIRE_SHARED_DIR(refs());
  for (const char* scene_name : {"CBbunny", "CBspheres_lambertian"}) {
    Scene scene = load_collada_file(test::shared_scene(std::string(scene_name) + ".dae")).scene;
    Camera camera =
        resolve_camera(read_camera_settings_file(refs() / ("cam_fullview_" + std::string(scene_name) + "_256x192.txt")),
                       kWidth, kHeight);
    for (int depth : {1, 2, 5}) {
      std::string png = "course_" + std::string(scene_name) + "_m" + std::to_string(depth) + "_s256_l4.png";
      test::DecodedImage course = test::decode_png_file(refs() / png);
      ASSERT_EQ(course.width, kWidth) << png;
      ASSERT_EQ(course.height, kHeight) << png;
      ASSERT_GE(course.channels, 3) << png;
      RenderSettings rs{.width = kWidth,
                        .height = kHeight,
                        .samples_per_pixel = 256,
                        .light_samples = 4,
                        .max_depth = depth,
                        .adaptive_tolerance = 0.0f,
                        .seed = 11,
                        .threads = 2,
                        .cs184_light_quirk = true,
                        .cs184_invisible_sky = true,
                        .cs184_light_pdf = true};
      for (const test::EngineUnderTest& engine : test::engines_under_test()) {
        // The default engine on every image, the others (same paths, same seed) on one.
        if (engine.name != "wavefront" && (depth != 2 || std::string(scene_name) != "CBspheres_lambertian")) continue;
        std::string what = engine.name + " on " + png;
        Comparison c = compare(engine.render(scene, camera, rs).film, course);
        EXPECT_NEAR(c.mean_ratio, 1.0, 0.01) << what << ": mean illuminance ours / course";
        EXPECT_EQ(c.blocks_over, 0) << what << ": blocks beyond |z| = " << kBlockZ << "; worst at (" << c.worst_x
                                    << ", " << c.worst_y << "), |z| = " << c.worst_z;
        std::printf("  %s: mean ours / course %.4f, worst of %d 8x8 blocks |z| = %.2f\n", what.c_str(), c.mean_ratio,
                    c.blocks, c.worst_z);
      }
    }
  }
}

// Power: without the course's light-sampling pdf (the quirk the comparison
// exists for) the same comparison fails.
TEST(CourseImages, TheComparisonRejectsTheImageWithoutTheLightPdfQuirk) {
  PT_REQUIRE_SHARED_SCENES();
  PT_REQUIRE_SHARED_DIR(refs());
  Scene scene = load_collada_file(test::shared_scene("CBbunny.dae")).scene;
  Camera camera =
      resolve_camera(read_camera_settings_file(refs() / "cam_fullview_CBbunny_256x192.txt"), kWidth, kHeight);
  test::DecodedImage course = test::decode_png_file(refs() / "course_CBbunny_m1_s256_l4.png");
  ASSERT_EQ(course.width, kWidth);
  RenderSettings rs{.width = kWidth,
                    .height = kHeight,
                    .samples_per_pixel = 64,
                    .light_samples = 4,
                    .max_depth = 1,
                    .adaptive_tolerance = 0.0f,
                    .threads = 2,
                    .cs184_light_quirk = true,
                    .cs184_invisible_sky = true};
  Comparison c = compare(test::engines_under_test()[1].render(scene, camera, rs).film, course);
  EXPECT_GT(std::fabs(c.mean_ratio - 1.0), 0.01) << "mean ratio " << c.mean_ratio;
  EXPECT_GT(c.blocks_over, c.blocks / 10) << "of " << c.blocks << " blocks";
  std::printf("  without the pdf quirk: mean ours / course %.4f, %d of %d blocks beyond |z| = %.1f\n", c.mean_ratio,
              c.blocks_over, c.blocks, kBlockZ);
}

}  // namespace
}  // namespace pt
