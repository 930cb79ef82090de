// bin_by_material: the kind of each lane's material, then one compressed
// append per kind present in the chunk.
#include "kernels/simd/isa_namespace.h"
#include "material_queues.h"

#include "lane_output.h"
#include "soa_lanes.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

void bin_by_material(const WaveContext& ctx, const RayQueue& rays, const HitQueue& hits, MaterialQueues& q) {
  for (size_t k = 0; k < kMaterialKindCount; ++k) {
    q.rays[k].clear();
    q.hits[k].clear();
  }
  const Scene& scene = ctx.scene;
  alignas(64) int32_t kind[kLanes];
  for (size_t i0 = 0; i0 < rays.size; i0 += kLanes) {
    const size_t lanes = std::min(kLanes, rays.size - i0);
    uint32_t present = 0;
    for (size_t l = 0; l < kLanes; ++l) {
      uint32_t k = 0;  // misses and padding: diffuse
      if (l < lanes) {
        uint32_t prim = hits.prim[i0 + l];
        if (prim != kInvalidId) {
          Hit h{0, 0, 0, prim};
          uint32_t m = h.is_sphere() ? scene.spheres[h.index()].material : scene.triangle_material[h.index()];
          k = static_cast<uint32_t>(ctx.materials.kind[m]);
        }
      }
      kind[l] = static_cast<int32_t>(k);
      if (l < lanes) present |= 1u << k;
    }
    const vintK kinds = vintK::load_aligned(kind);
    const uint32_t valid = lanes_below(lanes);
    const RayLanes ray_lanes = load_lanes(rays, i0);
    const HitLanes hit_lanes = load_lanes(hits, i0);
    for (uint32_t k = 0; present; ++k, present >>= 1) {
      if (!(present & 1u)) continue;
      uint32_t mask = valid & lane_mask(as_float_mask(kinds == vintK(static_cast<int32_t>(k))));
      append_lanes(q.rays[k], mask, ray_lanes);
      append_lanes(q.hits[k], mask, hit_lanes);
    }
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
