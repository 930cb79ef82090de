// The BVH4 query table of one instruction-set level (compiled once per level,
// see kernels/simd/isa.h): the inline queries of scene_bvh4_queries.h behind
// function pointers, each with or without counters.
#include "bvh4_query_table.h"
#include "scene_bvh4_queries.h"

namespace pt {
namespace {

/// query(counters): with the caller's counters, or with counters that
/// compile away.
template <class Query>
decltype(auto) with_counters(TraversalCounters* c, Query&& query) {
  if (c) return query(*c);
  NoCounters none;
  return query(none);
}

bool intersect(const SceneBvh4& s, const Ray& ray, Hit& hit, TraversalCounters* c) {
  return with_counters(c, [&](auto& counters) { return bvh4_queries::intersect(s, ray, hit, counters); });
}

bool occluded(const SceneBvh4& s, const Ray& ray, TraversalCounters* c) {
  return with_counters(c, [&](auto& counters) { return bvh4_queries::occluded(s, ray, counters); });
}

void intersect_queue(const SceneBvh4& s, const RayArrays& rays, const HitArrays& hits, QueueScratch& scratch,
                     TraversalCounters* c) {
  with_counters(c, [&](auto& counters) { bvh4_queries::intersect_queue(s, rays, hits, scratch, counters); });
}

void occluded_queue(const SceneBvh4& s, const RayArrays& rays, uint8_t* blocked, QueueScratch& scratch,
                    TraversalCounters* c) {
  with_counters(c, [&](auto& counters) { bvh4_queries::occluded_queue(s, rays, blocked, scratch, counters); });
}

/// Counters that also report every node and leaf a walk takes.
struct VisitReport {
  static constexpr bool kEnabled = true;
  TraversalCounters& counters;
  void (*report)(void*, uint32_t);
  void* context;
  void visit(uint32_t ref) { report(context, ref); }
  void node() { counters.node(); }
  void nodes_tested(uint64_t n) { counters.nodes_tested(n); }
  void primitives_tested(uint32_t n) { counters.primitives_tested(n); }
};

void walk_tree(const SceneBvh4& s, const Ray& ray, Hit& hit, TraversalCounters& counters,
               void (*visit)(void*, uint32_t), void* context) {
  VisitReport report{counters, visit, context};
  bvh4_intersect(s.bvh(), ray, hit, report);
}

}  // namespace

inline namespace PT_ISA_NS {
extern const Bvh4QueryTable kBvh4Queries;
const Bvh4QueryTable kBvh4Queries = {
    .isa = PT_ISA,
    .intersect = intersect,
    .occluded = occluded,
    .intersect_queue = intersect_queue,
    .occluded_queue = occluded_queue,
    .walk_tree = walk_tree,
};
}  // namespace PT_ISA_NS

}  // namespace pt
