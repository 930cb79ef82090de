// The queries of SceneBvh4 as inline functions, for code compiled once per
// instruction-set level: bvh4_queries_isa.cpp wraps them into the level's
// table, and the engines' hot loops call them with no dispatch. Spheres are
// tested after the BVH walk (closest hit) or before it (any hit). A whole
// queue goes as coherent sets of 64 rays when it comes in coherent runs
// (queue_coherence.h, bvh4_coherent_set.h); for any hit at up to 8 lanes, as
// octant sets when it is short, its directions span the sphere and the tree
// outgrows L2 (bvh4_octant_sets.h); else as a stream (bvh4_stream.h).
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

#include "kernels/simd/isa_namespace.h"
#include "bvh4_coherent_set.h"
#include "bvh4_octant_sets.h"
#include "bvh4_packet.h"
#include "bvh4_stream.h"
#include "bvh4_traverse.h"
#include "queue_coherence.h"
#include "queue_prefetch.h"
#include "kernels/scene/sphere_intersect.h"
#include "kernels/scene/sphere_intersect_lanes.h"
#include "scene_bvh4.h"

#if !PT_PER_LEVEL
#error "scene_bvh4_queries.h is for code compiled once per instruction-set level"
#endif

namespace pt::bvh4_queries {
inline namespace PT_ISA_NS {

/// The spheres (tested outside the BVH, one by one): the closest within
/// [tmin, hit.t) replaces `hit`. Whether one did.
inline bool closest_sphere(std::span<const SceneBvh4::SphereShape> spheres, const Ray& ray, Hit& hit) {
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
inline bool any_sphere(std::span<const SceneBvh4::SphereShape> spheres, const Ray& ray) {
  for (const SceneBvh4::SphereShape& sp : spheres) {
    float t;
    if (intersect_sphere(ray.org, ray.dir, ray.tmin, ray.tmax, sp.center, sp.radius, t)) return true;
  }
  return false;
}

template <class C>
inline bool intersect(const SceneBvh4& s, const Ray& ray, Hit& hit, C& c) {
  const Bvh4& bvh = s.bvh();
  bool found = bvh.form == TriangleForm::kWatertight ? bvh4_intersect<TriangleForm::kWatertight>(bvh, ray, hit, c)
                                                     : bvh4_intersect<TriangleForm::kMollerTrumbore>(bvh, ray, hit, c);
  std::span<const SceneBvh4::SphereShape> spheres = s.spheres();
  if (spheres.empty() || !ray_is_traceable(ray)) return found;
  c.primitives_tested(static_cast<uint32_t>(spheres.size()));
  return closest_sphere(spheres, ray, hit) || found;
}

template <class C>
inline bool occluded(const SceneBvh4& s, const Ray& ray, C& c) {
  std::span<const SceneBvh4::SphereShape> spheres = s.spheres();
  if (!spheres.empty() && ray_is_traceable(ray)) {
    c.primitives_tested(static_cast<uint32_t>(spheres.size()));
    if (any_sphere(spheres, ray)) return true;
  }
  const Bvh4& bvh = s.bvh();
  return bvh.form == TriangleForm::kWatertight ? bvh4_occluded<TriangleForm::kWatertight>(bvh, ray, c)
                                               : bvh4_occluded<TriangleForm::kMollerTrumbore>(bvh, ray, c);
}

inline bool intersect(const SceneBvh4& s, const Ray& ray, Hit& hit) {
  NoCounters c;
  return intersect(s, ray, hit, c);
}
inline bool occluded(const SceneBvh4& s, const Ray& ray) {
  NoCounters c;
  return occluded(s, ray, c);
}

/// The lanes of `lanes` (traceable rays) whose ray a sphere blocks, K rays at
/// once: any_sphere's answers, bit for bit. Out of line, as the other sphere
/// passes: it is called once per K rays and would grow the queries it sits in.
[[gnu::noinline]] inline uint32_t spheres_block_lanes(std::span<const SceneBvh4::SphereShape> spheres,
                                                      const vfloatK (&org)[3], const vfloatK (&dir)[3],
                                                      const vfloatK& tmin, const vfloatK& tmax, uint32_t lanes) {
  uint32_t blocked = 0;
  for (const SceneBvh4::SphereShape& sp : spheres) {
    if (blocked == lanes) break;
    blocked |= lane_mask(intersect_sphere_lanes(org, dir, tmin, tmax, sp.center, sp.radius).hit) & lanes;
  }
  return blocked;
}

/// closest_sphere over the lanes of `lanes` (traceable rays) K at a time:
/// where sphere i lies within [tmin, t), in the spheres' order, the lane's t,
/// u, v and prim take {t, 0, 0, sphere_prim_id(i)}. The lanes that changed.
/// Out of line, likewise.
[[gnu::noinline]] inline uint32_t closest_spheres_lanes(std::span<const SceneBvh4::SphereShape> spheres,
                                                        const vfloatK (&org)[3], const vfloatK (&dir)[3],
                                                        const vfloatK& tmin, vfloatK& t, vfloatK& u, vfloatK& v,
                                                        vintK& prim, uint32_t lanes) {
  uint32_t found = 0;
  for (uint32_t i = 0; i < spheres.size(); ++i) {
    const SphereLaneHits<vfloatK> h = intersect_sphere_lanes(org, dir, tmin, t, spheres[i].center, spheres[i].radius);
    const uint32_t m = lane_mask(h.hit) & lanes;
    if (m == 0) continue;
    const vboolK on = lanes_of_mask(m);
    t = xsimd::select(on, h.t, t);
    u = xsimd::select(on, vfloatK(0.0f), u);
    v = xsimd::select(on, vfloatK(0.0f), v);
    prim = xsimd::select(xsimd::bool_cast(on), vintK(static_cast<int32_t>(sphere_prim_id(i))), prim);
    found |= m;
  }
  return found;
}

/// The active lanes of a packet whose ray a triangle blocks.
inline uint32_t triangle_blocked_lanes(const SceneBvh4& s, const RayPacket& p) {
  return p.uniform ? bvh4_occluded_packet<true>(s.bvh(), p) : bvh4_occluded_packet<false>(s.bvh(), p);
}

/// One packet of occlusion queries: the lanes of `lanes` (< kLanes) whose ray is blocked.
inline uint32_t occluded_packet(const SceneBvh4& s, const Ray* rays, uint32_t lanes) {
  lanes &= lanes_below(kLanes);
  uint32_t blocked = 0;
  if (s.bvh().form != TriangleForm::kMollerTrumbore) {
    for (uint32_t m = lanes; m != 0; m &= m - 1)
      if (occluded(s, rays[std::countr_zero(m)])) blocked |= 1u << std::countr_zero(m);
    return blocked;
  }
  RayPacket p = load_ray_packet(rays, lanes);
  if (!s.spheres().empty()) {
    blocked = spheres_block_lanes(s.spheres(), p.org, p.dir, p.tmin, p.tmax, p.active);
    if (blocked != 0) p = load_ray_packet(rays, lanes & ~blocked);
  }
  return blocked | triangle_blocked_lanes(s, p);
}

/// One packet of closest-hit queries: rays[i] -> hits[i] for the lanes of `lanes` (< kLanes).
inline void intersect_packet(const SceneBvh4& s, const Ray* rays, Hit* hits, uint32_t lanes) {
  lanes &= lanes_below(kLanes);
  if (s.bvh().form != TriangleForm::kMollerTrumbore) {
    for (uint32_t m = lanes; m != 0; m &= m - 1) intersect(s, rays[std::countr_zero(m)], hits[std::countr_zero(m)]);
    return;
  }
  RayPacket p = load_ray_packet(rays, lanes);
  PacketHits h;
  if (p.uniform) bvh4_intersect_packet<true>(s.bvh(), p, h);
  else bvh4_intersect_packet<false>(s.bvh(), p, h);
  // A miss (or an untraceable ray) keeps t = tmax, u = v = 0 and prim =
  // kInvalidId: the packet changes a lane's values only where it hits.
  if (!s.spheres().empty())
    closest_spheres_lanes(s.spheres(), p.org, p.dir, p.tmin, p.tmax, h.u, h.v, h.prim, p.active);
  const PacketHitLanes l(p, h);
  for (uint32_t m = lanes; m != 0; m &= m - 1) {
    uint32_t i = std::countr_zero(m);
    hits[i] = Hit{l.t[i], l.u[i], l.v[i], static_cast<uint32_t>(l.prim[i])};
  }
}

/// The spheres' closest hits over a queue whose hits the tree has given, K
/// rays at a time (closest_sphere's answers). Kept out of line, as the
/// packets below: inlined, it changed how the stream's parts were compiled.
template <class C>
[[gnu::noinline]] void closest_spheres_of_queue(std::span<const SceneBvh4::SphereShape> spheres, const RayArrays& rays,
                                                const HitArrays& hits, C& c) {
  for (size_t i0 = 0; i0 < rays.size; i0 += kLanes) {  // each ray under the hit the tree gave it
    const size_t n = std::min(kLanes, rays.size - i0);
    const RayPacket r = load_ray_packet(rays, i0, n);  // active: the traceable rays
    c.primitives_tested(static_cast<uint32_t>(spheres.size() * std::popcount(r.active)));
    alignas(64) float t[kLanes], u[kLanes], v[kLanes];
    alignas(64) int32_t prim[kLanes];
    for (size_t k = 0; k < kLanes; ++k) {
      const Hit h = hits.load(i0 + (k < n ? k : 0));
      t[k] = h.t, u[k] = h.u, v[k] = h.v, prim[k] = static_cast<int32_t>(h.prim);
    }
    vfloatK vt = vfloatK::load_aligned(t), vu = vfloatK::load_aligned(u), vv = vfloatK::load_aligned(v);
    vintK vprim = vintK::load_aligned(prim);
    uint32_t found = closest_spheres_lanes(spheres, r.org, r.dir, r.tmin, vt, vu, vv, vprim, r.active);
    if (found == 0) continue;
    vt.store_aligned(t), vu.store_aligned(u), vv.store_aligned(v), vprim.store_aligned(prim);
    for (; found != 0; found &= found - 1) {
      const size_t k = std::countr_zero(found);
      hits.store(i0 + k, Hit{t[k], u[k], v[k], static_cast<uint32_t>(prim[k])});
    }
  }
}

/// blocked[i] = 1 for every ray of a queue that a sphere blocks, K rays at a
/// time (any_sphere's answers); the others are left as they are. Out of line
/// for the same reason.
template <class C>
[[gnu::noinline]] void spheres_block_queue(std::span<const SceneBvh4::SphereShape> spheres, const RayArrays& rays,
                                           uint8_t* blocked, C& c) {
  for (size_t i0 = 0; i0 < rays.size; i0 += kLanes) {
    const size_t n = std::min(kLanes, rays.size - i0);
    const RayPacket r = load_ray_packet(rays, i0, n);  // active: the traceable rays
    c.primitives_tested(static_cast<uint32_t>(spheres.size() * std::popcount(r.active)));
    for (uint32_t m = spheres_block_lanes(spheres, r.org, r.dir, r.tmin, r.tmax, r.active); m != 0; m &= m - 1)
      blocked[i0 + std::countr_zero(m)] = 1;
  }
}

/// Whether a queue has fewer rays than a stream tests across lanes at its
/// root: the stream would hand them all to single-ray walks there, so they go
/// ray by ray from the start, without the stream's setup (a scene's last
/// bounces leave queues of a few rays).
inline bool too_short_for_stream(const RayArrays& rays) { return rays.size < stream_detail::kStreamMinRays; }

/// Whether the queue comes in coherent runs of K rays, which sets trace
/// faster than a stream does (queue_coherence.h).
inline bool in_coherent_runs(const SceneBvh4& s, const RayArrays& rays) {
  if (rays.size < 4 * kLanes) return false;  // as in_coherent_runs, without the scene's extent
  return in_coherent_runs(rays, kCoherentSpread * scene_extent(s.bvh()), kLanes);
}

/// A packet's closest hits (the tree's, then the spheres') into rays
/// [i0, i0 + n) of the queue's hits. A miss (or an untraceable ray) keeps t =
/// tmax, u = v = 0 and prim = kInvalidId: the packet changes a lane's values
/// only where it hits.
inline void store_packet_hits(std::span<const SceneBvh4::SphereShape> spheres, RayPacket& p, PacketHits& h,
                              const HitArrays& hits, size_t i0, size_t n) {
  if (!spheres.empty()) closest_spheres_lanes(spheres, p.org, p.dir, p.tmin, p.tmax, h.u, h.v, h.prim, p.active);
  if (n == kLanes) {
    p.tmax.store_unaligned(hits.t + i0);
    h.u.store_unaligned(hits.u + i0);
    h.v.store_unaligned(hits.v + i0);
    h.prim.store_unaligned(reinterpret_cast<int32_t*>(hits.prim + i0));
    return;
  }
  const PacketHitLanes l(p, h);
  for (size_t k = 0; k < n; ++k) hits.store(i0 + k, Hit{l.t[k], l.u[k], l.v[k], static_cast<uint32_t>(l.prim[k])});
}

/// Closest hits of a coherent queue, as sets of kSetRays consecutive rays
/// (bvh4_coherent_set.h); a set whose rays do not share a direction octant
/// goes packet by packet. Out of line: it runs once per queue.
[[gnu::noinline]] inline void intersect_queue_as_sets(const SceneBvh4& s, const RayArrays& rays,
                                                      const HitArrays& hits) {
  std::span<const SceneBvh4::SphereShape> spheres = s.spheres();
  CoherentSet set;
  for (size_t i0 = 0; i0 < rays.size; i0 += kSetRays) {
    const size_t n = std::min<size_t>(kSetRays, rays.size - i0);
    for (size_t k = 0; k < kSetRays; k += 16) prefetch_queue_rays(rays, i0 + kSetRays + k);  // the next set
    if (set_detail::load_set(rays, i0, n, set)) {
      bvh4_intersect_set(s.bvh(), set);
    } else {
      for (uint32_t j = 0; j < set.packets; ++j) {
        RayPacket& p = set.packet[j];
        if (p.uniform) bvh4_intersect_packet<true>(s.bvh(), p, set.hits[j]);
        else bvh4_intersect_packet<false>(s.bvh(), p, set.hits[j]);
      }
    }
    for (uint32_t j = 0; j < set.packets; ++j)
      store_packet_hits(spheres, set.packet[j], set.hits[j], hits, i0 + j * kLanes,
                        std::min<size_t>(kLanes, n - j * kLanes));
  }
}

/// Closest hits of a whole queue: hits as intersect() gives them, ray by ray.
/// Traced as coherent sets when the queue comes in coherent runs, as a
/// stream otherwise, and ray by ray in the watertight form, when the queue is
/// too short for a stream and, for counted queries, when the queue comes in
/// coherent runs (sets count nothing).
template <class C>
inline void intersect_queue(const SceneBvh4& s, const RayArrays& rays, const HitArrays& hits, QueueScratch& scratch,
                            C& c) {
  const bool coherent = s.bvh().form == TriangleForm::kMollerTrumbore && in_coherent_runs(s, rays);
  if (s.bvh().form != TriangleForm::kMollerTrumbore || (C::kEnabled && coherent) || too_short_for_stream(rays)) {
    for (size_t i = 0; i < rays.size; ++i) {
      Hit h;
      intersect(s, rays.ray(i), h, c);
      hits.store(i, h);
    }
    return;
  }
  if (coherent) {
    intersect_queue_as_sets(s, rays, hits);
    return;
  }
  bvh4_intersect_stream(s.bvh(), rays, hits, scratch, c);
  std::span<const SceneBvh4::SphereShape> spheres = s.spheres();
  if (spheres.empty()) return;
  closest_spheres_of_queue(spheres, rays, hits, c);
}

/// blocked[i] = occluded(rays.ray(i)) for every ray of a coherent queue, as
/// sets of kSetRays consecutive rays (spheres first, lane by lane); a set
/// whose rays do not share a direction octant goes packet by packet. Out of
/// line: it runs once per queue.
[[gnu::noinline]] inline void occluded_queue_as_sets(const SceneBvh4& s, const RayArrays& rays, uint8_t* blocked) {
  std::span<const SceneBvh4::SphereShape> spheres = s.spheres();
  CoherentSet set;
  for (size_t i0 = 0; i0 < rays.size; i0 += kSetRays) {
    const size_t n = std::min<size_t>(kSetRays, rays.size - i0);
    for (size_t k = 0; k < kSetRays; k += 16) prefetch_queue_rays(rays, i0 + kSetRays + k);  // the next set
    const bool shared = set_detail::load_set(rays, i0, n, set);
    uint64_t hit = 0;
    for (uint32_t j = 0; j < set.packets; ++j) {
      RayPacket& p = set.packet[j];
      if (spheres.empty()) continue;
      const uint32_t m = spheres_block_lanes(spheres, p.org, p.dir, p.tmin, p.tmax, p.active);
      p.active &= ~m;
      hit |= uint64_t(m) << (j * kLanes);
    }
    set.active &= ~hit;
    if (shared) {
      hit |= bvh4_occluded_set(s.bvh(), set);
    } else {
      for (uint32_t j = 0; j < set.packets; ++j)
        hit |= uint64_t(triangle_blocked_lanes(s, set.packet[j])) << (j * kLanes);
    }
    for (size_t k = 0; k < n; ++k) blocked[i0 + k] = hit >> k & 1;
  }
}

/// blocked[i] = occluded(rays.ray(i)) for every ray of a queue: ray by ray
/// in the watertight form and when the queue is too short for a stream.
template <class C>
inline void occluded_queue(const SceneBvh4& s, const RayArrays& rays, uint8_t* blocked, QueueScratch& scratch, C& c) {
  if (s.bvh().form != TriangleForm::kMollerTrumbore || too_short_for_stream(rays)) {
    for (size_t i = 0; i < rays.size; ++i) blocked[i] = occluded(s, rays.ray(i), c);
    return;
  }
  std::span<const SceneBvh4::SphereShape> spheres = s.spheres();
  // Coherent queues (a directional light's shadow rays from first hits) go
  // as sets. Sets count nothing: counted queries take the stream.
  if (!C::kEnabled && in_coherent_runs(s, rays)) {
    occluded_queue_as_sets(s, rays, blocked);
    return;
  }
  if (rays.size > 0) std::memset(blocked, 0, rays.size);  // an empty queue may come with no array
  if (!spheres.empty()) spheres_block_queue(spheres, rays, blocked, c);
  // Short queues of directions over the whole sphere (a sky's samples) in a
  // tree past L2 share few tests across rays: octant sets, whose rays share
  // node loads (up to 8 lanes; at 16 the stream's tests are wide enough).
  if (goes_as_octant_sets(s.bvh(), rays, kLanes, l2_cache_bytes()))
    bvh4_occluded_octant_sets(s.bvh(), rays, blocked, c);
  else bvh4_occluded_stream(s.bvh(), rays, blocked, scratch, c);
}

}  // namespace PT_ISA_NS
}  // namespace pt::bvh4_queries
