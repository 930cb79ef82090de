// The accumulated state of a pass-based render: every pixel's running sums and
// how many samples every active pixel has completed. It is what a checkpoint
// saves and what a resumed render starts from.
#pragma once

#include <cstdint>
#include <vector>

#include "pixel_accumulator.h"

namespace pt {

struct Accumulation {
  std::vector<PixelAccumulator> pixels;  ///< width * height, row-major
  uint32_t samples_done = 0;             ///< completed passes, in samples per active pixel
};

}  // namespace pt
