// The accumulated state of a pass-based render: the running sums of every
// pixel of the render region and how many samples every active pixel has
// completed. It is what a checkpoint saves and what a resumed render starts
// from. Sized by the region, so rendering one tile of a large image costs
// the tile's pixels, not the image's.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/render/pixel_accumulator.h"
#include "kernels/render/render_settings.h"

namespace pt {

struct Accumulation {
  Region area;                           ///< the pixels held: the render region
  int image_width = 0;                   ///< of the whole image (pixel indices are y * width + x)
  std::vector<PixelAccumulator> pixels;  ///< area.width * area.height, row-major inside the area
  uint32_t samples_done = 0;             ///< completed passes, in samples per active pixel

  /// The accumulator of image pixel `pixel` (inside the area).
  PixelAccumulator& at(uint32_t pixel) { return pixels[slot(pixel)]; }
  const PixelAccumulator& at(uint32_t pixel) const { return pixels[slot(pixel)]; }
  size_t slot(uint32_t pixel) const {
    const uint32_t w = static_cast<uint32_t>(image_width);
    return size_t(pixel / w - uint32_t(area.y)) * uint32_t(area.width) + (pixel % w - uint32_t(area.x));
  }
};

}  // namespace pt
