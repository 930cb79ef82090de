// The benchmark's query table of one instruction-set level (bench_queries.h).
#include "bench_queries.h"
#include "bvh/scene_bvh4_queries.h"
#include "watertight_blocks.h"

namespace pt::bench {
namespace {

void intersect_each(const SceneBvh4& s, std::span<const Ray> rays, std::span<Hit> hits) {
  NoCounters c;
  for (size_t i = 0; i < rays.size(); ++i) bvh4_queries::intersect(s, rays[i], hits[i], c);
}

void occluded_each(const SceneBvh4& s, std::span<const Ray> rays, std::span<uint8_t> blocked) {
  NoCounters c;
  for (size_t i = 0; i < rays.size(); ++i) blocked[i] = bvh4_queries::occluded(s, rays[i], c);
}

/// The scene's queries over `tree` in watertight form: its spheres are `s`'s.
struct WatertightScene {
  const Bvh4& tree;
  const SceneBvh4& s;
  const Bvh4& bvh() const { return tree; }
  std::span<const SceneBvh4::SphereShape> spheres() const { return s.spheres(); }
};

bool watertight_intersect(const Bvh4& tree, const SceneBvh4& s, const Ray& ray, Hit& hit, TraversalCounters* c) {
  NoCounters none;
  const WatertightScene w{tree, s};
  return c ? bvh4_queries::intersect<WatertightBlocks>(w, ray, hit, *c)
           : bvh4_queries::intersect<WatertightBlocks>(w, ray, hit, none);
}

bool watertight_occluded(const Bvh4& tree, const SceneBvh4& s, const Ray& ray, TraversalCounters* c) {
  NoCounters none;
  const WatertightScene w{tree, s};
  return c ? bvh4_queries::occluded<WatertightBlocks>(w, ray, *c)
           : bvh4_queries::occluded<WatertightBlocks>(w, ray, none);
}

}  // namespace
}  // namespace pt::bench

namespace pt {
inline namespace PT_ISA_NS {
extern const bench::BenchQueryTable kBenchQueries;
const bench::BenchQueryTable kBenchQueries = {
    .isa = PT_ISA,
    .intersect_each = bench::intersect_each,
    .occluded_each = bench::occluded_each,
    .watertight_intersect = bench::watertight_intersect,
    .watertight_occluded = bench::watertight_occluded,
};
}  // namespace PT_ISA_NS
}  // namespace pt
