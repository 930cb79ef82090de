// Frames carry the command line's PNG values: the threshold table encodes
// every float as encode_channel does (checked at and around every threshold
// and on a million values across the range), and a film's frame equals the
// PNG written from it, decoded independently.
#include <bit>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "live/frame_image.h"
#include "support/png_decode.h"
#include "support/run_process.h"

namespace pt::live {
namespace {

class Encoder : public ::testing::TestWithParam<PngQuantization> {};

TEST_P(Encoder, AgreesWithEncodeChannelEverywhere) {
  const PngQuantization q = GetParam();
  const ChannelEncoder encode(q);
  auto check = [&](float x) {
    ASSERT_EQ(encode(x), encode_channel(x, q)) << "at " << x << " (bits " << std::bit_cast<uint32_t>(x) << ")";
  };
  // Around every code boundary: the first float of each code and 3 floats either side.
  for (uint32_t bits = 0, code = 0; code < 255;) {
    uint32_t lo = bits, hi = std::bit_cast<uint32_t>(2.0f);
    while (lo < hi) {
      uint32_t mid = lo + (hi - lo) / 2;
      if (encode_channel(std::bit_cast<float>(mid), q) > code) hi = mid;
      else lo = mid + 1;
    }
    for (int d = -3; d <= 3; ++d) check(std::bit_cast<float>(lo + d));
    bits = lo;
    code = encode_channel(std::bit_cast<float>(lo), q);
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), exponent(-40.0f, 3.0f);
  for (int i = 0; i < 500000; ++i) check(unit(rng));
  for (int i = 0; i < 500000; ++i) check(std::pow(10.0f, exponent(rng)));
  for (float x : {0.0f, -0.0f, -1.0f, std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::infinity(),
                  -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                  std::numeric_limits<float>::max()})
    check(x);
}

INSTANTIATE_TEST_SUITE_P(Quantizations, Encoder,
                         ::testing::Values(PngQuantization::kNearest, PngQuantization::kTruncate),
                         [](const auto& info) {
                           return info.param == PngQuantization::kNearest ? "Nearest" : "Truncate";
                         });

Film test_film() {
  Film f(7, 5, 16);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> v(0.0f, 1.2f);
  for (size_t i = 0; i < f.radiance.size(); ++i) {
    f.radiance[i] = {v(rng), v(rng) * 0.1f, v(rng) * 3.0f};
    f.samples[i] = uint32_t(i % 17);
  }
  return f;
}

TEST(FilmRgba, IsThePngsPixelsWithOpaqueAlpha) {
  test::ScratchDir dir;
  const Film f = test_film();
  for (PngQuantization q : {PngQuantization::kNearest, PngQuantization::kTruncate}) {
    write_image(dir / "f.png", f, q);
    test::DecodedImage png = test::decode_png_file(dir / "f.png");
    ASSERT_EQ(png.channels, 3);
    const std::string rgba = film_rgba(f, Display::kImage, ChannelEncoder(q), 16);
    ASSERT_EQ(rgba.size(), size_t(f.width) * f.height * 4);
    for (size_t i = 0; i < f.radiance.size(); ++i) {
      for (int c = 0; c < 3; ++c) ASSERT_EQ(uint8_t(rgba[4 * i + c]), png.pixels[3 * i + c]) << i;
      ASSERT_EQ(uint8_t(rgba[4 * i + 3]), 255);
    }
  }
}

TEST(FilmRgba, TheSampleRateViewIsTheRateImage) {
  test::ScratchDir dir;
  const Film f = test_film();
  write_sample_rate_image(dir / "rate.png", f);
  test::DecodedImage png = test::decode_png_file(dir / "rate.png");
  const std::string rgba = film_rgba(f, Display::kSampleRate, ChannelEncoder(PngQuantization::kNearest), 16);
  for (size_t i = 0; i < f.samples.size(); ++i)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(uint8_t(rgba[4 * i + c]), png.pixels[3 * i + c]) << i;
}

}  // namespace
}  // namespace pt::live
