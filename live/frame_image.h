// Frames of the live view: what one published image is (8-bit RGBA pixels
// and what the page's overlay shows about them) and how a film becomes one.
// The pixels are the command line's PNG values: the same encoding of each
// channel (io/image_output.h), so a frame and a PNG of the same render agree
// byte for byte; it is computed from a table of the 255 thresholds between
// codes instead of a power per channel.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "io/image_output.h"
#include "kernels/render/film.h"
#include "kernels/scene/camera.h"
#include "view_settings.h"

namespace pt::live {

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
  Display display = Display::kImage;
  Camera camera;  ///< the view's camera at the view's size (the overlays project with it)
};

struct Frame {
  FrameInfo info;
  std::string rgba;  ///< width * height * 4 bytes, top row first, alpha 255
};

/// encode_channel(x, q) for every float x, by binary search over thresholds.
class ChannelEncoder {
 public:
  explicit ChannelEncoder(PngQuantization q);
  uint8_t operator()(float linear) const;

 private:
  std::array<float, 256> lowest_{};  ///< lowest_[k]: the smallest value encoded as k or more (k >= 1)
};

/// The film's pixels as the page shows them: the PNG's values, or for
/// Display::kSampleRate the sample-rate image's colours (of `target` samples).
std::string film_rgba(const Film& film, Display display, const ChannelEncoder& encode, uint32_t target);

}  // namespace pt::live
