// The BVH4 query table of one instruction-set level (compiled once per level,
// see kernels/simd/isa.h): the inline queries of scene_bvh4_queries.h behind
// function pointers, and their loops over ranges of rays.
#include <algorithm>

#include "bvh4_query_table.h"
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

void intersect_queue(const SceneBvh4& s, const RayArrays& rays, const HitArrays& hits, QueueScratch& scratch,
                     TraversalCounters* c) {
  if (c) return bvh4_queries::intersect_queue(s, rays, hits, scratch, *c);
  NoCounters none;
  bvh4_queries::intersect_queue(s, rays, hits, scratch, none);
}

void occluded_queue(const SceneBvh4& s, const RayArrays& rays, uint8_t* blocked, QueueScratch& scratch,
                    TraversalCounters* c) {
  if (c) return bvh4_queries::occluded_queue(s, rays, blocked, scratch, *c);
  NoCounters none;
  bvh4_queries::occluded_queue(s, rays, blocked, scratch, none);
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
    .intersect_queue = intersect_queue,
    .occluded_queue = occluded_queue,
};
}  // namespace PT_ISA_NS

}  // namespace pt
