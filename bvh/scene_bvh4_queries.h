// The queries of SceneBvh4 as inline functions, for code compiled once per
// instruction-set level: bvh4_queries_isa.cpp puts them in the level's table,
// and the engines' hot loops call them with no dispatch. Spheres are tested
// after the tree (closest hit) or before it (any hit). A whole queue goes by
// the rule of choose_queue_method (queue_coherence.h): ray by ray, as
// coherent sets (bvh4_coherent_set.h), for any hit as octant sets
// (bvh4_octant_sets.h), or as a stream (bvh4_stream.h). Blocks
// is the leaves' triangle test (bvh4_leaf_test.h): the queue methods are
// written for Moller-Trumbore leaves, and watertight ones go ray by ray.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>

#include "bvh4_coherent_set.h"
#include "bvh4_octant_sets.h"
#include "bvh4_ray_walk.h"
#include "bvh4_stream.h"
#include "kernels/scene/sphere_intersect.h"
#include "kernels/scene/sphere_intersect_lanes.h"
#include "kernels/simd/isa_namespace.h"
#include "queue_coherence.h"
#include "queue_lanes.h"
#include "scene_bvh4.h"
#include "traversal_counters.h"

#if !PT_PER_LEVEL
#error "scene_bvh4_queries.h is for code compiled once per instruction-set level"
#endif

namespace pt::bvh4_queries {
inline namespace PT_ISA_NS {

using Spheres = std::span<const SceneBvh4::SphereShape>;

/// The spheres (tested outside the BVH, one by one): the closest within
/// [tmin, hit.t) replaces `hit`. Whether one did.
inline bool closest_sphere(Spheres spheres, const Ray& ray, Hit& hit) {
  bool found = false;
  for (uint32_t i = 0; i < spheres.size(); ++i) {
    float t;
    if (!intersect_sphere(ray.org, ray.dir, ray.tmin, hit.t, spheres[i].center, spheres[i].radius, t)) continue;
    hit = {t, 0.0f, 0.0f, sphere_prim_id(i)};
    found = true;
  }
  return found;
}

/// Whether a sphere lies on the ray within [tmin, tmax).
inline bool any_sphere(Spheres spheres, const Ray& ray) {
  for (const SceneBvh4::SphereShape& sp : spheres) {
    float t;
    if (intersect_sphere(ray.org, ray.dir, ray.tmin, ray.tmax, sp.center, sp.radius, t)) return true;
  }
  return false;
}

/// The closest hit of one ray (SceneBvh4::intersect). Accel: a SceneBvh4,
/// or what has its bvh() and spheres().
template <class Blocks = MtBlocks, class Accel, class C>
inline bool intersect(const Accel& s, const Ray& ray, Hit& hit, C& c) {
  bool found = bvh4_intersect<Blocks>(s.bvh(), ray, hit, c);
  Spheres spheres = s.spheres();
  if (spheres.empty() || !ray_is_traceable(ray)) return found;
  c.primitives_tested(static_cast<uint32_t>(spheres.size()));
  return closest_sphere(spheres, ray, hit) || found;
}

/// Whether something blocks one ray (SceneBvh4::occluded).
template <class Blocks = MtBlocks, class Accel, class C>
inline bool occluded(const Accel& s, const Ray& ray, C& c) {
  Spheres spheres = s.spheres();
  if (!spheres.empty() && ray_is_traceable(ray)) {
    c.primitives_tested(static_cast<uint32_t>(spheres.size()));
    if (any_sphere(spheres, ray)) return true;
  }
  return bvh4_occluded<Blocks>(s.bvh(), ray, c);
}

/// The lanes of `lanes` (traceable rays) whose ray a sphere blocks, K rays at
/// once: any_sphere's answers, bit for bit. Out of line, as the other sphere
/// passes: it is called once per K rays and would grow the queries it sits in.
[[gnu::noinline]] inline uint32_t spheres_block_lanes(Spheres spheres, const vfloatK (&org)[3], const vfloatK (&dir)[3],
                                                      const vfloatK& tmin, const vfloatK& tmax, uint32_t lanes) {
  uint32_t blocked = 0;
  for (const SceneBvh4::SphereShape& sp : spheres) {
    if (blocked == lanes) break;
    blocked |= lane_mask(intersect_sphere_lanes(org, dir, tmin, tmax, sp.center, sp.radius).hit) & lanes;
  }
  return blocked;
}

/// closest_sphere over the lanes of `lanes` (traceable rays) K at a time:
/// where sphere i lies within [tmin, h.t), in the spheres' order, the lane's
/// hit takes {t, 0, 0, sphere_prim_id(i)}. The lanes that changed. Out of
/// line, likewise.
[[gnu::noinline]] inline uint32_t closest_spheres_lanes(Spheres spheres, const TriangleLanes& r, LaneHitState& h,
                                                        uint32_t lanes) {
  uint32_t found = 0;
  for (uint32_t i = 0; i < spheres.size(); ++i) {
    const SphereLaneHits<vfloatK> sh =
        intersect_sphere_lanes(r.org, r.dir, r.tmin, h.t, spheres[i].center, spheres[i].radius);
    const uint32_t m = lane_mask(sh.hit) & lanes;
    if (m == 0) continue;
    const vboolK on = lanes_of_mask(m);
    h.t = xsimd::select(on, sh.t, h.t);
    h.u = xsimd::select(on, vfloatK(0.0f), h.u);
    h.v = xsimd::select(on, vfloatK(0.0f), h.v);
    h.prim = xsimd::select(xsimd::bool_cast(on), vintK(static_cast<int32_t>(sphere_prim_id(i))), h.prim);
    found |= m;
  }
  return found;
}

/// Lanes [0, n) of K hits into hits [i0, i0 + n) of a queue.
inline void store_lanes(const LaneHitState& h, const HitArrays& hits, size_t i0, size_t n) {
  if (n == kLanes) {
    h.t.store_unaligned(hits.t + i0);
    h.u.store_unaligned(hits.u + i0);
    h.v.store_unaligned(hits.v + i0);
    h.prim.store_unaligned(reinterpret_cast<int32_t*>(hits.prim + i0));
    return;
  }
  alignas(64) float t[kLanes], u[kLanes], v[kLanes];
  alignas(64) int32_t prim[kLanes];
  h.t.store_aligned(t), h.u.store_aligned(u), h.v.store_aligned(v), h.prim.store_aligned(prim);
  for (size_t k = 0; k < n; ++k) hits.store(i0 + k, Hit{t[k], u[k], v[k], static_cast<uint32_t>(prim[k])});
}

/// The spheres' closest hits over a queue whose hits the tree has given, K
/// rays at a time, each under the hit the tree gave it (closest_sphere's
/// answers). Kept out of line: inlined, it changed how the stream's parts
/// were compiled.
template <class C>
[[gnu::noinline]] void closest_spheres_of_queue(Spheres spheres, const RayArrays& rays, const HitArrays& hits, C& c) {
  for (size_t i0 = 0; i0 < rays.size; i0 += kLanes) {
    const size_t n = std::min(kLanes, rays.size - i0);
    const QueueLanes r(rays, i0);
    c.primitives_tested(static_cast<uint32_t>(spheres.size() * std::popcount(r.traceable)));
    alignas(64) float t[kLanes], u[kLanes], v[kLanes];
    alignas(64) int32_t prim[kLanes];
    for (size_t k = 0; k < kLanes; ++k) {
      const Hit h = hits.load(i0 + (k < n ? k : 0));
      t[k] = h.t, u[k] = h.u, v[k] = h.v, prim[k] = static_cast<int32_t>(h.prim);
    }
    LaneHitState h{vfloatK::load_aligned(t), vfloatK::load_aligned(u), vfloatK::load_aligned(v),
                   vintK::load_aligned(prim)};
    const TriangleLanes lanes{{r.org[0], r.org[1], r.org[2]}, {r.dir[0], r.dir[1], r.dir[2]}, r.tmin};
    if (closest_spheres_lanes(spheres, lanes, h, r.traceable) != 0) store_lanes(h, hits, i0, n);
  }
}

/// blocked[i] = 1 for every ray of a queue that a sphere blocks, K rays at a
/// time (any_sphere's answers); the others are left as they are. Out of line
/// for the same reason.
template <class C>
[[gnu::noinline]] void spheres_block_queue(Spheres spheres, const RayArrays& rays, uint8_t* blocked, C& c) {
  for (size_t i0 = 0; i0 < rays.size; i0 += kLanes) {
    const QueueLanes r(rays, i0);
    c.primitives_tested(static_cast<uint32_t>(spheres.size() * std::popcount(r.traceable)));
    for (uint32_t m = spheres_block_lanes(spheres, r.org, r.dir, r.tmin, r.tmax, r.traceable); m != 0; m &= m - 1)
      blocked[i0 + std::countr_zero(m)] = 1;
  }
}

/// A coherent queue as sets of kSetRays consecutive rays. Closest hit: the
/// tree's hits, then the spheres', into `hits`. Any hit: blocked[i] for every
/// ray, the spheres tested first, lane by lane. Out of line: it runs once per
/// queue.
template <bool kAnyHit, class C>
[[gnu::noinline]] void trace_queue_as_sets(const SceneBvh4& s, const RayArrays& rays, const HitArrays& hits,
                                           uint8_t* blocked, C& c) {
  Spheres spheres = s.spheres();
  CoherentSet set;
  for (size_t i0 = 0; i0 < rays.size; i0 += kSetRays) {
    const size_t n = std::min<size_t>(kSetRays, rays.size - i0);
    for (size_t k = 0; k < kSetRays; k += 16) prefetch_queue_rays(rays, i0 + kSetRays + k);  // the next set
    set_detail::load_set(rays, i0, n, set);
    uint64_t by_sphere = 0;
    for (uint32_t j = 0; kAnyHit && j < set.packets && !spheres.empty(); ++j) {
      const SetPacket& p = set.packet[j];
      const uint32_t lanes = set_detail::lanes_of_packet(set.traceable, j);
      c.primitives_tested(static_cast<uint32_t>(spheres.size() * std::popcount(lanes)));
      by_sphere |= uint64_t(spheres_block_lanes(spheres, p.ray.org, p.ray.dir, p.ray.tmin, p.hit.t, lanes))
                   << (j * kLanes);
    }
    set.traceable &= ~by_sphere;
    trace_set_by_octant<kAnyHit>(s.bvh(), set, c);
    if constexpr (kAnyHit) {
      for (size_t k = 0; k < n; ++k) blocked[i0 + k] = (set.blocked | by_sphere) >> k & 1;
      continue;
    }
    for (uint32_t j = 0; j < set.packets; ++j) {
      SetPacket& p = set.packet[j];
      const uint32_t lanes = set_detail::lanes_of_packet(set.traceable, j);
      if (!spheres.empty()) {
        c.primitives_tested(static_cast<uint32_t>(spheres.size() * std::popcount(lanes)));
        closest_spheres_lanes(spheres, p.ray, p.hit, lanes);
      }
      store_lanes(p.hit, hits, i0 + j * kLanes, std::min<size_t>(kLanes, n - j * kLanes));
    }
  }
}

/// Closest hits of a whole queue (SceneBvh4::intersect_queue): hits as
/// intersect() gives them, ray by ray.
template <class Blocks = MtBlocks, class C>
inline void intersect_queue(const SceneBvh4& s, const RayArrays& rays, const HitArrays& hits, QueueScratch& scratch,
                            C& c) {
  switch (choose_queue_method<Blocks, false>(s.bvh(), rays)) {
    case QueueMethod::kRays:
      for (size_t i = 0; i < rays.size; ++i) {
        Hit h;
        intersect<Blocks>(s, rays.ray(i), h, c);
        hits.store(i, h);
      }
      return;
    case QueueMethod::kSets: trace_queue_as_sets<false>(s, rays, hits, nullptr, c); return;
    case QueueMethod::kOctantSets:  // any hit only
    case QueueMethod::kStream: break;
  }
  bvh4_intersect_stream(s.bvh(), rays, hits, scratch, c);
  if (!s.spheres().empty()) closest_spheres_of_queue(s.spheres(), rays, hits, c);
}

/// blocked[i] = occluded(rays.ray(i)) for every ray of a whole queue
/// (SceneBvh4::occluded_queue).
template <class Blocks = MtBlocks, class C>
inline void occluded_queue(const SceneBvh4& s, const RayArrays& rays, uint8_t* blocked, QueueScratch& scratch, C& c) {
  const QueueMethod method = choose_queue_method<Blocks, true>(s.bvh(), rays);
  switch (method) {
    case QueueMethod::kRays:
      for (size_t i = 0; i < rays.size; ++i) blocked[i] = occluded<Blocks>(s, rays.ray(i), c);
      return;
    case QueueMethod::kSets: trace_queue_as_sets<true>(s, rays, HitArrays{}, blocked, c); return;
    case QueueMethod::kOctantSets:
    case QueueMethod::kStream: break;
  }
  if (rays.size > 0) std::memset(blocked, 0, rays.size);  // an empty queue may come with no array
  if (!s.spheres().empty()) spheres_block_queue(s.spheres(), rays, blocked, c);
  if (method == QueueMethod::kOctantSets) bvh4_occluded_octant_sets(s.bvh(), rays, blocked, c);
  else bvh4_occluded_stream(s.bvh(), rays, blocked, scratch, c);
}

}  // namespace PT_ISA_NS
}  // namespace pt::bvh4_queries
