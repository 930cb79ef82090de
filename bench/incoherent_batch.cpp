// IncoherentBatches: optional reordering, then chunks of rays traced by the
// BVH4's range queries in parallel.
#include "incoherent_batch.h"

#include "bench_queries.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "ray_order.h"

namespace pt::bench {
namespace {

constexpr size_t kChunk = 1024;

/// Runs f(begin, end) over [0, n) in chunks, in parallel in the calling arena.
template <class F>
void for_each_chunk(size_t n, F&& f) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kChunk),
                    [&](const tbb::blocked_range<size_t>& r) { f(r.begin(), r.end()); });
}

/// The rays in coherent_order, copied: the copy's independent loads overlap,
/// while loads through the index inside the traversal loop would each stall.
/// Uninitialised storage filled in parallel (a vector, or new Ray[], would
/// first initialise it on one thread); memcpy starts the rays' lifetimes.
struct FreeRays {
  void operator()(Ray* p) const { ::operator delete(p, std::align_val_t(alignof(Ray))); }
};
using RayBuffer = std::unique_ptr<Ray[], FreeRays>;

RayBuffer gather_in_order(std::span<const Ray> rays, const std::vector<uint32_t>& order) {
  static_assert(std::is_trivially_copyable_v<Ray> && std::is_trivially_destructible_v<Ray>);
  RayBuffer sorted(static_cast<Ray*>(::operator new(rays.size() * sizeof(Ray), std::align_val_t(alignof(Ray)))));
  for_each_chunk(rays.size(), [&](size_t b, size_t e) {
    for (size_t k = b; k < e; ++k) std::memcpy(&sorted[k], &rays[order[k]], sizeof(Ray));
  });
  return sorted;
}

/// Traces rays[k] into out[k] with `each(rays, out)` (a SceneBvh4 range query),
/// in the order of coherent_order when `reorder`.
template <class Out, class Each>
void trace_batch(std::span<const Ray> rays, std::span<Out> out, bool reorder, const BBox& bounds, Each&& each) {
  if (!reorder) {
    for_each_chunk(rays.size(), [&](size_t b, size_t e) { each(rays.subspan(b, e - b), out.subspan(b, e - b)); });
    return;
  }
  std::vector<uint32_t> order = coherent_order(rays, bounds);
  RayBuffer sorted = gather_in_order(rays, order);
  for_each_chunk(rays.size(), [&](size_t begin, size_t end) {
    // oneTBB's partitioner may hand out ranges longer than the grain size.
    Out found[kChunk];
    for (size_t b = begin; b < end; b += kChunk) {
      size_t e = std::min(end, b + kChunk);
      each(std::span<const Ray>(&sorted[b], e - b), std::span<Out>(found, e - b));
      for (size_t k = b; k < e; ++k) out[order[k]] = found[k - b];
    }
  });
}

}  // namespace

IncoherentBatches::IncoherentBatches(const SceneBvh4& bvh, const Scene& scene, size_t reorder_min_bytes)
    : bvh_(bvh), reorder_(bvh.stats().bytes >= reorder_min_bytes) {
  for (const Sphere& s : scene.spheres) bounds_.expand(BBox{s.center - float3(s.radius), s.center + float3(s.radius)});
  for (const float3& p : scene.positions)
    if (is_finite(p)) bounds_.expand(p);
}

void IncoherentBatches::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
  trace_batch(rays, hits, reorder_, bounds_,
              [this](std::span<const Ray> r, std::span<Hit> h) { bench_queries().intersect_each(bvh_, r, h); });
}

void IncoherentBatches::occluded(std::span<const Ray> rays, std::span<uint8_t> blocked) const {
  trace_batch(rays, blocked, reorder_, bounds_,
              [this](std::span<const Ray> r, std::span<uint8_t> b) { bench_queries().occluded_each(bvh_, r, b); });
}

}  // namespace pt::bench
