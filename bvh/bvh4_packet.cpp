// Loading a ray packet: transposes the AoS rays into SoA lanes and computes the
// slab-test constants.
#include "bvh4_packet.h"

#include "bvh4_node_test.h"

namespace pt {

// GCC would vectorise the transposition below back into gathers.
#if defined(__GNUC__) && !defined(__clang__)
__attribute__((optimize("no-tree-vectorize")))
#endif
RayPacket load_ray_packet(const Ray* rays, uint32_t lanes) {
  RayPacket p;
  if (lanes == 0) return p;
  // Transposed through the stack: 8 scalar copies per ray and 8 aligned
  // vector loads cost a fraction of 8 gathers (slow on AMD's cores).
  const uint32_t first = std::countr_zero(lanes);
  alignas(64) float field[8][kLanes];
  for (uint32_t i = 0; i < kLanes; ++i) {  // lanes not requested copy the first requested ray
    const Ray& r = rays[(lanes >> i) & 1 ? i : first];
    field[0][i] = r.org.x, field[1][i] = r.org.y, field[2][i] = r.org.z, field[3][i] = r.tmin;
    field[4][i] = r.dir.x, field[5][i] = r.dir.y, field[6][i] = r.dir.z, field[7][i] = r.tmax;
  }
  p.org[0] = vfloatK::load_aligned(field[0]), p.org[1] = vfloatK::load_aligned(field[1]);
  p.org[2] = vfloatK::load_aligned(field[2]), p.tmin = vfloatK::load_aligned(field[3]);
  p.dir[0] = vfloatK::load_aligned(field[4]), p.dir[1] = vfloatK::load_aligned(field[5]);
  p.dir[2] = vfloatK::load_aligned(field[6]), p.tmax = vfloatK::load_aligned(field[7]);
  vboolK traceable = p.tmin < p.tmax;  // false for NaN
  for (int a = 0; a < 3; ++a) traceable = traceable & xsimd::isfinite(p.org[a]) & xsimd::isfinite(p.dir[a]);
  p.active = lanes & lane_mask(traceable);
  p.uniform = true;
  const vfloatK min_dir(NodeRay::kMinDir);
  for (int a = 0; a < 3; ++a) {
    vfloatK safe = xsimd::select(xsimd::abs(p.dir[a]) < min_dir, xsimd::copysign(min_dir, p.dir[a]), p.dir[a]);
    p.rdir[a] = vfloatK(1.0f) / safe;
    p.org_rdir[a] = p.org[a] * p.rdir[a];
    uint32_t negative = lane_mask(p.rdir[a] < vfloatK(0.0f)) & p.active;
    p.uniform = p.uniform && (negative == 0 || negative == p.active);
    p.near[a] = 2 * a + (negative != 0);
    p.far[a] = 2 * a + (negative == 0);
  }
  return p;
}

}  // namespace pt
