// Loading a ray packet: gathers the AoS rays into SoA lanes and computes the
// slab-test constants.
#include "bvh4_packet.h"

#include "bvh4_node_test.h"

namespace pt {

RayPacket load_ray_packet(const Ray* rays, uint32_t lanes) {
  RayPacket p;
  if (lanes == 0) return p;
  const int32_t first = std::countr_zero(lanes);
  alignas(64) int32_t index[kLanes];
  for (std::size_t i = 0; i < kLanes; ++i)  // lanes not requested read the first requested ray
    index[i] = ((lanes >> i) & 1 ? int32_t(i) : first) * int32_t(sizeof(Ray) / sizeof(float));
  const vintK offsets = vintK::load_aligned(index);
  const float* base = reinterpret_cast<const float*>(rays);
  auto field = [&](int f) { return gather(base + f, offsets); };
  p.org[0] = field(0), p.org[1] = field(1), p.org[2] = field(2), p.tmin = field(3);
  p.dir[0] = field(4), p.dir[1] = field(5), p.dir[2] = field(6), p.tmax = field(7);
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
