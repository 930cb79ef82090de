// The BVH4 query table of one instruction-set level (compiled once per level,
// see kernels/isa.h): the inline queries of scene_bvh4_queries.h behind
// function pointers, plus the batch entry points.
#include <cstring>
#include <memory>
#include <new>
#include <type_traits>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "bvh4_query_table.h"
#include "ray_order.h"
#include "scene_bvh4_queries.h"

namespace pt {
namespace {

bool intersect_one(const SceneBvh4& s, const Ray& ray, Hit& hit, TraversalCounters* c) {
  return c ? bvh4_queries::intersect(s, ray, hit, *c) : bvh4_queries::intersect(s, ray, hit);
}

bool occluded_one(const SceneBvh4& s, const Ray& ray, TraversalCounters* c) {
  return c ? bvh4_queries::occluded(s, ray, *c) : bvh4_queries::occluded(s, ray);
}

void intersect_each(const SceneBvh4& s, std::span<const Ray> rays, std::span<Hit> hits) {
  for (size_t i = 0; i < rays.size(); ++i) bvh4_queries::intersect(s, rays[i], hits[i]);
}

void occluded_each(const SceneBvh4& s, std::span<const Ray> rays, std::span<uint8_t> blocked) {
  for (size_t i = 0; i < rays.size(); ++i) blocked[i] = bvh4_queries::occluded(s, rays[i]);
}

void intersect_packets(const SceneBvh4& s, std::span<const Ray> rays, std::span<Hit> hits) {
  for (size_t i = 0; i < rays.size(); i += kLanes)
    bvh4_queries::intersect_packet(s, &rays[i], &hits[i], lanes_below(std::min(kLanes, rays.size() - i)));
}

/// Runs f(k) for k in [0, n) in parallel in the calling arena.
template <class F> void for_each_index(size_t n, F&& f) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) f(k);
  });
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
  for_each_index(rays.size(), [&](size_t k) { std::memcpy(&sorted[k], &rays[order[k]], sizeof(Ray)); });
  return sorted;
}

void intersect_incoherent(const SceneBvh4& s, std::span<const Ray> rays, std::span<Hit> hits) {
  if (s.stats().bytes < s.reorder_min_bytes()) {
    for_each_index(rays.size(), [&](size_t k) { bvh4_queries::intersect(s, rays[k], hits[k]); });
    return;
  }
  std::vector<uint32_t> order = coherent_order(rays, s.bounds());
  RayBuffer sorted = gather_in_order(rays, order);
  for_each_index(rays.size(), [&](size_t k) { bvh4_queries::intersect(s, sorted[k], hits[order[k]]); });
}

void occluded_incoherent(const SceneBvh4& s, std::span<const Ray> rays, std::span<uint8_t> blocked) {
  if (s.stats().bytes < s.reorder_min_bytes()) {
    for_each_index(rays.size(), [&](size_t k) { blocked[k] = bvh4_queries::occluded(s, rays[k]); });
    return;
  }
  std::vector<uint32_t> order = coherent_order(rays, s.bounds());
  RayBuffer sorted = gather_in_order(rays, order);
  for_each_index(rays.size(), [&](size_t k) { blocked[order[k]] = bvh4_queries::occluded(s, sorted[k]); });
}

}  // namespace

namespace PT_ISA_NS {
extern const Bvh4QueryTable kBvh4Queries;
const Bvh4QueryTable kBvh4Queries = {
    .isa = PT_ISA,
    .packet_lanes = static_cast<uint32_t>(kLanes),
    .intersect = intersect_one,
    .occluded = occluded_one,
    .intersect_each = intersect_each,
    .occluded_each = occluded_each,
    .intersect_packets = intersect_packets,
    .intersect_packet = bvh4_queries::intersect_packet,
    .occluded_packet = bvh4_queries::occluded_packet,
    .intersect_incoherent = intersect_incoherent,
    .occluded_incoherent = occluded_incoherent,
};
}  // namespace PT_ISA_NS

}  // namespace pt
