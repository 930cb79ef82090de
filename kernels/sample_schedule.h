// How a pass-based engine walks the samples: each pass takes the next samples
// of every pixel still active, up to the next adaptive check (every BATCH
// samples) or at most kMaxPassSamples without adaptive sampling. Pixels are
// visited in 8x8 tiles so that neighbouring camera rays travel together.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "render_settings.h"

namespace pt {

inline constexpr uint32_t kMaxPassSamples = 64;
inline constexpr int kPixelTile = 8;

/// Samples in the pass that starts after `done` samples (0 when finished).
inline uint32_t pass_length(const RenderSettings& rs, uint32_t done) {
  uint32_t total = static_cast<uint32_t>(rs.samples_per_pixel);
  if (done >= total) return 0;
  uint32_t until = rs.adaptive() ? static_cast<uint32_t>(rs.adaptive_batch) - done % rs.adaptive_batch
                                 : kMaxPassSamples;
  return std::min(until, total - done);
}

/// Whether the adaptive test runs after `done` samples.
inline bool adaptive_check_due(const RenderSettings& rs, uint32_t done) {
  return rs.adaptive() && done % static_cast<uint32_t>(rs.adaptive_batch) == 0;
}

/// Pixel indices (y * width + x) of the render region in 8x8-tile order.
inline std::vector<uint32_t> tiled_pixel_order(const RenderSettings& rs) {
  Region r = rs.area();
  std::vector<uint32_t> order;
  order.reserve(size_t(r.width) * r.height);
  for (int ty = r.y; ty < r.y + r.height; ty += kPixelTile)
    for (int tx = r.x; tx < r.x + r.width; tx += kPixelTile)
      for (int y = ty; y < std::min(ty + kPixelTile, r.y + r.height); ++y)
        for (int x = tx; x < std::min(tx + kPixelTile, r.x + r.width); ++x)
          order.push_back(static_cast<uint32_t>(y) * rs.width + x);
  return order;
}

}  // namespace pt
