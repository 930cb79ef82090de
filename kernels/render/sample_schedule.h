// How a pass-based engine walks the samples: each pass takes the next samples
// of every pixel still active, up to the next adaptive check (every BATCH
// samples, or with Sobol points at the powers of two from BATCH up) or at
// most kMaxPassSamples without adaptive sampling. Pixels are visited in 8x8
// tiles so that neighbouring camera rays travel together.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "kernels/simd/isa_namespace.h"
#include "kernels/render/render_settings.h"

namespace pt {
inline namespace PT_ISA_NS {

inline constexpr uint32_t kMaxPassSamples = 64;
inline constexpr int kPixelTile = 8;

/// The first sample count at which the adaptive test may run: BATCH, or with
/// Sobol points the power of two at or above it.
inline uint32_t first_adaptive_check(const RenderSettings& rs) {
  uint32_t batch = static_cast<uint32_t>(std::max(rs.adaptive_batch, 1));
  if (rs.sampler != PixelSampler::kSobol) return batch;
  uint32_t n = 1;
  while (n < batch) n *= 2;
  return n;
}

/// Whether the adaptive test runs after `done` samples of every active pixel:
/// every BATCH samples with independent numbers (the assignment's rule); with
/// Sobol points at the powers of two from BATCH up, the only counts at which
/// a pixel's points of every dimension pair are a complete (0, k, 2)-net, so
/// a pixel never stops part-way through its strata.
inline bool adaptive_check_due(const RenderSettings& rs, uint32_t done) {
  if (!rs.adaptive() || done == 0) return false;
  if (rs.sampler == PixelSampler::kSobol) return done >= first_adaptive_check(rs) && (done & (done - 1)) == 0;
  return done % static_cast<uint32_t>(rs.adaptive_batch) == 0;
}

/// Samples in the pass that starts after `done` samples (0 when finished):
/// up to the next adaptive check, and at most kMaxPassSamples (or BATCH, when
/// larger) at a time.
inline uint32_t pass_length(const RenderSettings& rs, uint32_t done) {
  uint32_t total = static_cast<uint32_t>(rs.samples_per_pixel);
  if (done >= total) return 0;
  uint32_t until = kMaxPassSamples;
  if (rs.adaptive() && rs.sampler == PixelSampler::kSobol) {
    uint32_t next = first_adaptive_check(rs);
    while (next <= done) next *= 2;
    until = std::min(next - done, std::max(kMaxPassSamples, static_cast<uint32_t>(rs.adaptive_batch)));
  } else if (rs.adaptive()) {
    until = static_cast<uint32_t>(rs.adaptive_batch) - done % rs.adaptive_batch;
  }
  return std::min(until, total - done);
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

}  // namespace PT_ISA_NS
}  // namespace pt
