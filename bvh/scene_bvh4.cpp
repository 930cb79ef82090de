// SceneBvh4 construction.
#include "scene_bvh4.h"

namespace pt {

SceneBvh4::SceneBvh4(const Scene& scene, const Bvh4Options& options) : SceneBvh4(scene, options, active_isa()) {}

SceneBvh4::SceneBvh4(const Scene& scene, const Bvh4Options& options, Isa isa) : queries_(&bvh4_query_table(isa)) {
  bvh_ = build_bvh4(scene.positions, scene.triangles, options, &stats_);
  spheres_.reserve(scene.spheres.size());
  for (const Sphere& s : scene.spheres) spheres_.push_back({s.center, s.radius});
}

}  // namespace pt
