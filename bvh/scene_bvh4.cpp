// SceneBvh4 construction.
#include "scene_bvh4.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <new>
#include <type_traits>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "bvh4_packet.h"
#include "ray_order.h"

namespace pt {

SceneBvh4::SceneBvh4(const Scene& scene, const Bvh4Options& options) : reorder_min_bytes_(options.reorder_min_bytes) {
  bvh_ = build_bvh4(scene.positions, scene.triangles, options, &stats_);
  spheres_.reserve(scene.spheres.size());
  for (const Sphere& s : scene.spheres) {
    spheres_.push_back({s.center, s.radius});
    bounds_.expand(BBox{s.center - float3(s.radius), s.center + float3(s.radius)});
  }
  for (const float3& p : scene.positions)
    if (is_finite(p)) bounds_.expand(p);
}

void SceneBvh4::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
  for (size_t i = 0; i < rays.size(); i += kLanes) {
    size_t n = std::min(kLanes, rays.size() - i);
    intersect_packet(&rays[i], &hits[i], n == 32 ? ~0u : (1u << n) - 1);
  }
}

namespace {

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

}  // namespace

void SceneBvh4::intersect_incoherent(std::span<const Ray> rays, std::span<Hit> hits) const {
  if (stats_.bytes < reorder_min_bytes_) {
    for_each_index(rays.size(), [&](size_t k) { intersect(rays[k], hits[k]); });
    return;
  }
  std::vector<uint32_t> order = coherent_order(rays, bounds_);
  RayBuffer sorted = gather_in_order(rays, order);
  for_each_index(rays.size(), [&](size_t k) { intersect(sorted[k], hits[order[k]]); });
}

void SceneBvh4::occluded_incoherent(std::span<const Ray> rays, std::span<uint8_t> blocked) const {
  if (stats_.bytes < reorder_min_bytes_) {
    for_each_index(rays.size(), [&](size_t k) { blocked[k] = occluded(rays[k]); });
    return;
  }
  std::vector<uint32_t> order = coherent_order(rays, bounds_);
  RayBuffer sorted = gather_in_order(rays, order);
  for_each_index(rays.size(), [&](size_t k) { blocked[order[k]] = occluded(sorted[k]); });
}

uint32_t SceneBvh4::occluded_packet(const Ray* rays, uint32_t lanes) const {
  lanes &= kLanes == 32 ? ~0u : (1u << kLanes) - 1;
  uint32_t blocked = 0;
  if (bvh_.form != TriangleForm::kMollerTrumbore) {
    for (uint32_t m = lanes; m != 0; m &= m - 1)
      if (occluded(rays[std::countr_zero(m)])) blocked |= 1u << std::countr_zero(m);
    return blocked;
  }
  for (uint32_t m = spheres_.empty() ? 0 : lanes; m != 0; m &= m - 1) {  // spheres first, per lane
    const Ray& r = rays[std::countr_zero(m)];
    if (!ray_is_traceable(r)) continue;
    for (const SphereShape& sp : spheres_) {
      float t;
      if (intersect_sphere(r.org, r.dir, r.tmin, r.tmax, sp.center, sp.radius, t)) {
        blocked |= 1u << std::countr_zero(m);
        break;
      }
    }
  }
  RayPacket p = load_ray_packet(rays, lanes & ~blocked);
  return blocked | (p.uniform ? bvh4_occluded_packet<true>(bvh_, p) : bvh4_occluded_packet<false>(bvh_, p));
}

void SceneBvh4::intersect_packet(const Ray* rays, Hit* hits, uint32_t lanes) const {
  lanes &= kLanes == 32 ? ~0u : (1u << kLanes) - 1;
  if (bvh_.form != TriangleForm::kMollerTrumbore) {
    for (uint32_t m = lanes; m != 0; m &= m - 1) intersect(rays[std::countr_zero(m)], hits[std::countr_zero(m)]);
    return;
  }
  RayPacket p = load_ray_packet(rays, lanes);
  PacketHits h;
  if (p.uniform) bvh4_intersect_packet<true>(bvh_, p, h);
  else bvh4_intersect_packet<false>(bvh_, p, h);
  alignas(64) float t[kLanes], u[kLanes], v[kLanes];
  alignas(64) int32_t prim[kLanes];
  p.tmax.store_aligned(t);
  h.u.store_aligned(u);
  h.v.store_aligned(v);
  h.prim.store_aligned(prim);
  for (uint32_t m = lanes; m != 0; m &= m - 1) {
    uint32_t i = std::countr_zero(m);
    Hit& hit = hits[i];
    uint32_t id = static_cast<uint32_t>(prim[i]);
    hit = id != kInvalidId ? Hit{t[i], u[i], v[i], id} : Hit{rays[i].tmax, 0.0f, 0.0f, kInvalidId};
    if (spheres_.empty() || !(p.active >> i & 1)) continue;
    for (uint32_t s = 0; s < spheres_.size(); ++s) {
      float ts;
      if (intersect_sphere(rays[i].org, rays[i].dir, rays[i].tmin, hit.t, spheres_[s].center, spheres_[s].radius, ts))
        hit = {ts, 0.0f, 0.0f, sphere_prim_id(s)};
    }
  }
}

}  // namespace pt
