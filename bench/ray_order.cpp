// ray_order_key and a two-pass radix sort over it.
#include "ray_order.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

namespace pt::bench {
namespace {

constexpr int kCellBits = 3;  // per axis: 8 cells
constexpr uint32_t kCells = 1u << kCellBits;
constexpr int kRadixBits = 9;
constexpr uint32_t kBuckets = 1u << kRadixBits;

/// Interleaves the low three bits of x, y, z.
uint32_t morton3(uint32_t x, uint32_t y, uint32_t z) {
  uint32_t m = 0;
  for (int b = 0; b < kCellBits; ++b)
    m |= (x >> b & 1) << (3 * b) | (y >> b & 1) << (3 * b + 1) | (z >> b & 1) << (3 * b + 2);
  return m;
}

uint32_t cell(float x, float lo, float inv_extent) {
  float f = (x - lo) * inv_extent;
  return f >= 1.0f ? kCells - 1 : (f > 0.0f ? static_cast<uint32_t>(f * kCells) : 0u);  // NaN -> 0
}

}  // namespace

uint32_t ray_order_key(const Ray& ray, const BBox& bounds) {
  float3 e = bounds.extent();
  auto inv = [](float x) { return x > 0.0f ? 1.0f / x : 0.0f; };
  uint32_t origin = morton3(cell(ray.org.x, bounds.lower.x, inv(e.x)), cell(ray.org.y, bounds.lower.y, inv(e.y)),
                            cell(ray.org.z, bounds.lower.z, inv(e.z)));
  float l1 = std::fabs(ray.dir.x) + std::fabs(ray.dir.y) + std::fabs(ray.dir.z);
  float s = l1 > 0.0f ? 0.5f / l1 : 0.0f;  // components to [-0.5, 0.5]
  uint32_t direction =
      morton3(cell(ray.dir.x * s, -0.5f, 1.0f), cell(ray.dir.y * s, -0.5f, 1.0f), cell(ray.dir.z * s, -0.5f, 1.0f));
  return origin << (3 * kCellBits) | direction;
}

std::vector<uint32_t> coherent_order(std::span<const Ray> rays, const BBox& bounds) {
  const size_t n = rays.size();
  std::vector<uint32_t> keys(n), order(n), keys2(n), order2(n);
  // Fixed chunks (not the scheduler's ranges): each chunk's rays keep their
  // order within a bucket, so the result is the same for any thread count.
  const size_t chunks = std::clamp<size_t>(n / 16384, 1, 64);
  auto chunk_begin = [&](size_t c) { return n * c / chunks; };
  auto for_each_chunk = [&](auto&& f) {
    tbb::parallel_for(size_t(0), chunks, [&](size_t c) { f(c, chunk_begin(c), chunk_begin(c + 1)); });
  };
  for_each_chunk([&](size_t, size_t begin, size_t end) {
    for (size_t i = begin; i != end; ++i) {
      keys[i] = ray_order_key(rays[i], bounds);
      order[i] = static_cast<uint32_t>(i);
    }
  });
  std::vector<std::array<uint32_t, kBuckets>> offset(chunks);
  for (int pass = 0; pass < 2; ++pass) {  // least significant digit first: stable
    const int shift = pass * kRadixBits;
    for_each_chunk([&](size_t c, size_t begin, size_t end) {
      offset[c].fill(0);
      for (size_t i = begin; i != end; ++i) ++offset[c][(keys[i] >> shift) & (kBuckets - 1)];
    });
    uint32_t sum = 0;  // bucket-major, chunk-minor exclusive prefix sum
    for (uint32_t b = 0; b < kBuckets; ++b)
      for (size_t c = 0; c < chunks; ++c) sum += std::exchange(offset[c][b], sum);
    for_each_chunk([&](size_t c, size_t begin, size_t end) {
      for (size_t i = begin; i != end; ++i) {
        uint32_t slot = offset[c][(keys[i] >> shift) & (kBuckets - 1)]++;
        keys2[slot] = keys[i];
        order2[slot] = order[i];
      }
    });
    keys.swap(keys2);
    order.swap(order2);
  }
  return order;
}

}  // namespace pt::bench
