// Film to RGBA: thresholds found by bisection over the encoder itself.
#include "frame_image.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace pt::live {
namespace {

/// The smallest non-negative float whose encoding is at least `code`
/// (encode_channel is non-decreasing in its argument), searched over the
/// bit patterns of [0, 2], which order as the floats do.
float lowest_encoded_as(uint8_t code, PngQuantization q) {
  uint32_t lo = 0, hi = std::bit_cast<uint32_t>(2.0f);  // encode(2) = 255
  while (lo < hi) {
    uint32_t mid = lo + (hi - lo) / 2;
    if (encode_channel(std::bit_cast<float>(mid), q) >= code) hi = mid;
    else lo = mid + 1;
  }
  return std::bit_cast<float>(lo);
}

}  // namespace

ChannelEncoder::ChannelEncoder(PngQuantization q) {
  std::array<float, 257> lowest{};  // lowest[k]: the smallest value encoded as k or more; lowest[256] = +inf
  for (int k = 1; k < 256; ++k) lowest[k] = lowest_encoded_as(static_cast<uint8_t>(k), q);
  lowest[256] = std::numeric_limits<float>::infinity();
  int code = 0;
  for (size_t b = 0; b < kBuckets; ++b) {
    const float start = std::bit_cast<float>(uint32_t(b << kBucketBits));
    const float end = std::bit_cast<float>(uint32_t(((b + 1) << kBucketBits) - 1));
    while (code < 255 && lowest[code + 1] <= start) ++code;
    first_[b] = uint8_t(code);
    threshold_[b] = lowest[code + 1] <= end ? lowest[code + 1] : std::numeric_limits<float>::infinity();
    if (code + 2 <= 255 && lowest[code + 2] <= end) std::abort();  // two thresholds in a bucket: the premise fails
  }
}

const ChannelEncoder& channel_encoder(PngQuantization q) {
  static const ChannelEncoder nearest(PngQuantization::kNearest), truncate(PngQuantization::kTruncate);
  return q == PngQuantization::kTruncate ? truncate : nearest;
}

std::string film_rgba(const Film& film, Display display, const ChannelEncoder& encode, uint32_t target) {
  const size_t n = size_t(film.width) * film.height;
  std::string out(n * 4, '\xff');
  uint8_t* p = reinterpret_cast<uint8_t*>(out.data());
  if (display == Display::kSampleRate) {
    for (size_t i = 0; i < n; ++i) sample_rate_rgb8(film.samples[i], target, p + 4 * i);
    return out;
  }
  for (size_t i = 0; i < n; ++i) {
    const float3& c = film.radiance[i];
    p[4 * i] = encode(c.x);
    p[4 * i + 1] = encode(c.y);
    p[4 * i + 2] = encode(c.z);
  }
  return out;
}

}  // namespace pt::live
