// Image output (io/image_output.h): the course renderer's PNG encoding
// clamp((L sqrt 2)^(1/2.2)) on known values and against a double-precision
// evaluation; PNGs and sample-rate images read back with an independent
// decoder (stb_image), rows top first; PFM written and read back bit for bit,
// bottom row first in the file; OpenEXR read back (float bit for bit, half to
// half precision); the sample-rate colour map's endpoints.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "support/run_process.h"
#include "io/exr_image.h"
#include "io/image_output.h"
#include "io/scene_error.h"
#include "support/png_decode.h"
#include "support/test_support.h"

namespace pt {
namespace {

using test::ScratchDir;

/// L with (L sqrt 2)^(1/2.2) = v.
float linear_for(double v) { return static_cast<float>(std::pow(v, 2.2) / std::sqrt(2.0)); }

TEST(PngEncoding, KnownValues) {
  EXPECT_EQ(encode_channel(0.0f), 0);
  EXPECT_EQ(encode_channel(linear_for(0.2)), 51);
  EXPECT_EQ(encode_channel(linear_for(0.6)), 153);
  EXPECT_EQ(encode_channel(linear_for(1.0)), 255) << "L = 1/sqrt(2) is full white";
  EXPECT_EQ(encode_channel(1.0f), 255);
  EXPECT_EQ(encode_channel(10.0f), 255);
  EXPECT_EQ(encode_channel(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(encode_channel(-1.0f), 0);
  EXPECT_EQ(encode_channel(std::numeric_limits<float>::quiet_NaN()), 0);
}

// Against round(255 clamp((L sqrt 2)^(1/2.2))) in double over [0, 0.8]; where the
// double value lies within 1e-3 of a rounding boundary either neighbour is accepted.
TEST(PngEncoding, MatchesTheFormulaEverywhere) {
  for (int i = 0; i <= 100000; ++i) {
    float L = 0.8f * i / 100000.0f;
    double v = std::min(1.0, std::pow(double(L) * std::sqrt(2.0), 1.0 / 2.2)) * 255.0;
    double frac = v - std::floor(v);
    int got = encode_channel(L);
    if (std::fabs(frac - 0.5) < 1e-3) ASSERT_NEAR(got, v, 0.5 + 1e-3) << L;
    else ASSERT_EQ(got, static_cast<int>(std::lround(v))) << L;
  }
}

Film gradient_film(int w, int h) {
  Film f(w, h, 64);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      f.radiance[f.index(x, y)] = {0.01f * (1 + x + w * y), 0.3f - 0.02f * x, 0.05f * (y + 1)};
  return f;
}

TEST(PngOutput, DecodesToTheEncodedFilmTopRowFirst) {
  ScratchDir dir;
  const Film film = gradient_film(5, 3);
  write_image(dir / "out.png", film);
  test::DecodedImage img = test::decode_png_file(dir / "out.png");
  ASSERT_EQ(img.width, 5);
  ASSERT_EQ(img.height, 3);
  ASSERT_EQ(img.channels, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(img.pixels[(y * 5 + x) * 3 + c], encode_channel(film.radiance[film.index(x, y)][c]))
            << x << ", " << y << ", " << c;
}

TEST(PfmOutput, RoundTripsBitForBitWithTheBottomRowFirstInTheFile) {
  ScratchDir dir;
  Film film = gradient_film(4, 3);
  film.radiance[film.index(0, 0)] = {-2.5f, 1e30f, 1e-40f};  // negative, large, subnormal
  film.radiance[film.index(3, 2)] = {std::numeric_limits<float>::infinity(), 0.0f, -0.0f};
  write_image(dir / "out.PFM", film);
  int w = 0, h = 0;
  std::vector<float3> back = read_pfm(dir / "out.PFM", w, h);
  ASSERT_EQ(w, 4);
  ASSERT_EQ(h, 3);
  ASSERT_EQ(back.size(), film.radiance.size());
  EXPECT_EQ(std::memcmp(back.data(), film.radiance.data(), back.size() * sizeof(float3)), 0);

  const std::string file = test::file_bytes(dir / "out.PFM"), header = "PF\n4 3\n-1.0\n";
  ASSERT_EQ(file.size(), header.size() + 4 * 3 * 12);
  EXPECT_EQ(file.substr(0, header.size()), header);
  float first[3];
  std::memcpy(first, file.data() + header.size(), 12);
  const float3 bottom_left = film.radiance[film.index(0, 2)];
  EXPECT_EQ(first[0], bottom_left.x);
  EXPECT_EQ(first[1], bottom_left.y);
  EXPECT_EQ(first[2], bottom_left.z);
}

TEST(PfmOutput, MalformedFilesAreRejected) {
  ScratchDir dir;
  std::ofstream(dir / "magic.pfm") << "P6\n2 2\n255\n";
  std::ofstream(dir / "short.pfm") << "PF\n2 2\n-1.0\n" << std::string(20, '\0');
  std::ofstream(dir / "bigendian.pfm") << "PF\n1 1\n1.0\n" << std::string(12, '\0');
  int w, h;
  for (const char* name : {"magic.pfm", "short.pfm", "bigendian.pfm", "missing.pfm"})
    EXPECT_THROW(read_pfm(dir / name, w, h), InputError) << name;
}

// samples / maximum = r: blue (0) -> green (1/2) -> red (1), linear between.
TEST(SampleRateImage, ColourMapEndpointsAndMidpoints) {
  ScratchDir dir;
  Film film(5, 1, 64);
  film.samples = {0, 32, 64, 16, 48};
  write_sample_rate_image(dir / "rate.png", film);
  test::DecodedImage img = test::decode_png_file(dir / "rate.png");
  ASSERT_EQ(img.width, 5);
  ASSERT_EQ(img.channels, 3);
  const uint8_t expected[5][3] = {{0, 0, 255}, {0, 255, 0}, {255, 0, 0}, {0, 128, 128}, {128, 128, 0}};
  for (int x = 0; x < 5; ++x)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(img.pixels[x * 3 + c], expected[x][c]) << "pixel " << x << " channel " << c;
}

// -f out.exr: OpenEXR that an EXR reader (tinyexr's loader, as Blender's
// compositor would read it) returns as the film, rows top first: float
// channels bit for bit, half channels to half precision (11 bits).
TEST(ExrOutput, FloatRoundTripsBitForBitAndHalfToHalfPrecision) {
  ScratchDir dir;
  Film film = gradient_film(20, 17);           // above 16 x 16: the compressed path too
  for (float3& c : film.radiance) c = abs(c);  // radiance (the reader refuses negative texels)
  film.radiance[film.index(3, 0)] = {1000.0f, 0.001f, 0.0f};
  write_image(dir / "out.exr", film);
  write_image(dir / "half.EXR", film, PngQuantization::kNearest, ExrPixel::kHalf);
  const RgbImage full = read_exr((dir / "out.exr").string()), half = read_exr((dir / "half.EXR").string());
  ASSERT_EQ(full.width, 20);
  ASSERT_EQ(full.height, 17);
  ASSERT_EQ(half.texels.size(), film.radiance.size());
  EXPECT_EQ(std::memcmp(full.texels.data(), film.radiance.data(), full.texels.size() * sizeof(float3)), 0);
  for (size_t i = 0; i < film.radiance.size(); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(half.texels[i][c], film.radiance[i][c], std::fabs(film.radiance[i][c]) * 0x1p-11f + 1e-7f) << i;
  EXPECT_LT(std::filesystem::file_size(dir / "half.EXR"), std::filesystem::file_size(dir / "out.exr"));
}

TEST(OutputPaths, FormatByExtensionAndRateImageName) {
  EXPECT_EQ(image_format_for("a/b.exr"), ImageFormat::kExr);
  EXPECT_EQ(image_format_for("a/b.pfm"), ImageFormat::kPfm);
  EXPECT_EQ(image_format_for("b.PfM"), ImageFormat::kPfm);
  EXPECT_EQ(image_format_for("b.png"), ImageFormat::kPng);
  EXPECT_EQ(image_format_for("b"), ImageFormat::kPng);
  EXPECT_EQ(rate_image_path("dir/out.png"), std::filesystem::path("dir/out_rate.png"));
  EXPECT_THROW(write_image("/nonexistent-directory/out.png", gradient_film(2, 2)), InputError);
}

}  // namespace
}  // namespace pt
