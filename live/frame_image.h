// Frames of the live view: what one published image is (its film, the
// 8-bit RGBA pixels made from it, and what the page's overlay shows about
// it) and how a film becomes pixels. The pixels are the command line's PNG
// values: the same encoding of each channel (io/image_output.h), so a frame
// and a PNG of the same render agree byte for byte; it is computed from a
// table of the 255 thresholds between codes instead of a power per channel.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "io/image_output.h"
#include "kernels/render/film.h"
#include "kernels/scene/camera.h"
#include "view_settings.h"

namespace pt::live {

/// encode_channel(x, q) for every float x, from tables: the non-negative
/// floats below 2 fall in 2^14 buckets of 2^16 consecutive bit patterns, and a
/// bucket holds at most one of the 255 thresholds between codes (they lie at
/// least ~10^5 patterns apart), so a value's code is its bucket's first code,
/// plus one past the bucket's threshold: no branch on the value.
class ChannelEncoder {
 public:
  explicit ChannelEncoder(PngQuantization q);
  uint8_t operator()(float linear) const {
    const uint32_t bits = std::bit_cast<uint32_t>(linear);
    if (bits >= 0x40000000u) return bits <= 0x7f800000u ? 255 : 0;  // [2, +inf]: 255; NaN, -0 and below: 0
    const uint32_t b = bits >> kBucketBits;
    return uint8_t(first_[b] + (linear >= threshold_[b]));
  }

 private:
  static constexpr int kBucketBits = 16;
  static constexpr size_t kBuckets = (size_t(0x40000000) >> kBucketBits);  ///< bit patterns of [0, 2)
  std::array<uint8_t, kBuckets> first_{};                                  ///< the code of the bucket's first value
  std::array<float, kBuckets> threshold_{};  ///< the smallest value of the bucket with the next code, else +inf
};

/// The encoder of each quantization, built once.
const ChannelEncoder& channel_encoder(PngQuantization q);

/// The film's pixels as the page shows them: the PNG's values, or for
/// Display::kSampleRate the sample-rate image's colours (of `target` samples).
std::string film_rgba(const Film& film, Display display, const ChannelEncoder& encode, uint32_t target);

/// What the page needs to know about a frame besides its pixels.
struct FrameInfo {
  uint64_t id = 0;            ///< increases with every frame published
  uint64_t view_version = 0;  ///< the camera and settings it shows
  int width = 0, height = 0;  ///< of the pixels (smaller than the view while the camera moves)
  int view_width = 0, view_height = 0;
  uint32_t samples = 0;       ///< samples per pixel taken (the most any pixel took)
  uint32_t target = 0;        ///< -s
  bool complete = false;      ///< no pixel takes more samples: -s reached, or adaptive sampling stopped them all
  double seconds = 0;         ///< wall time since the view last changed
  double render_seconds = 0;  ///< time spent rendering this view
  uint64_t rays = 0;          ///< rays traced for this view
  /// The render's own estimate of its relative RMSE (kernels/render/error_estimate.h); < 0: none yet
  double estimated_relative_rmse = -1;
  Display display = Display::kImage;
  Camera camera;  ///< the view's camera at the view's size (the overlays project with it)
};

/// A published frame. Its pixels are converted from the film on first use,
/// by the thread that first sends them: not the render thread, which goes on
/// rendering, and not at all for a frame nobody asks for. Once converted, the
/// frame lets its film go: a frame that is still being sent holds its pixels only.
class Frame {
 public:
  Frame(const FrameInfo& i, std::shared_ptr<const Film> film, PngQuantization q)
      : info(i), film_(std::move(film)), quantization_(q) {}
  const FrameInfo info;
  /// width * height * 4 bytes, top row first, alpha 255.
  const std::string& rgba() const {
    std::call_once(converted_, [this] {
      rgba_ = film_rgba(*film_, info.display, channel_encoder(quantization_), info.target);
      film_.reset();
    });
    return rgba_;
  }

 private:
  mutable std::shared_ptr<const Film> film_;
  PngQuantization quantization_;
  mutable std::once_flag converted_;
  mutable std::string rgba_;
};

}  // namespace pt::live
