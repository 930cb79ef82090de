// Coherent sets: up to 64 consecutive rays of a coherent queue (a pinhole
// camera's, or a directional light's shadow rays from first hits) traced as
// one unit, the way Embree's coherent streams trace them, for closest hit
// and any hit alike (kAnyHit). A node is tested against the set's frustum
// (one 4-wide test that bounds every ray's entry and exit distances) and
// against the set's first ray; only a child that the frustum admits and that
// ray misses is tested K rays at a time. So most nodes cost two 4-wide
// tests, whatever the set holds. A child keeps its parent's rays; they are
// culled K at a time only at a leaf, by each ray's own slab test of the
// leaf's box, and then test its triangles (bvh4_leaf_test.h). The rays of a
// set that lie in different direction octants go as one set per octant.
//
// Every ray gets the hit its own walk gives, bit for bit: the frustum is
// conservative (its bounds widened past the rounding of its own arithmetic
// and of the rays'), a child is dropped only by the frustum or by every ray's
// own test, a ray tests a leaf's triangles only where its own slab test
// enters the leaf, and the leaf test is the walks' own.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "bvh4_leaf_test.h"
#include "bvh4_node_test.h"
#include "bvh4_ray_walk.h"
#include "kernels/math/ray_arrays.h"
#include "kernels/simd/isa_namespace.h"
#include "queue_lanes.h"
#include "triangle4_intersect.h"

#if !PT_PER_LEVEL
#error "bvh4_coherent_set.h is for code compiled once per instruction-set level"
#endif

namespace pt {
inline namespace PT_ISA_NS {

/// Rays a coherent set holds at most (one bit each in a 64-bit mask).
inline constexpr uint32_t kSetRays = 64;
inline constexpr uint32_t kSetPackets = kSetRays / kLanes;

/// K rays of a set: their triangle-test and slab constants and their hits so
/// far (hit.t: the nearest hit, or the end of the segment for any hit).
struct SetPacket {
  TriangleLanes ray;
  vfloatK rdir[3], org_rdir[3];
  LaneHitState hit;
  NodeLanes node_lanes() const {
    return {{rdir[0], rdir[1], rdir[2]}, {org_rdir[0], org_rdir[1], org_rdir[2]}, ray.tmin, hit.t};
  }
};

/// Up to kSetRays consecutive rays of a queue as packets of K, with each
/// ray's slab constants also by ray (for the first ray's test), and the
/// frustum of the rays being traced (`active`, one direction octant).
struct CoherentSet {
  SetPacket packet[kSetPackets];
  const RayArrays* queue = nullptr;
  size_t first = 0;        ///< the set's first ray in the queue
  uint32_t packets = 0;    ///< packets loaded
  uint64_t traceable = 0;  ///< the traceable rays: bit j K + i for lane i of packet j
  uint64_t active = 0;     ///< the rays being traced: traceable rays of one octant
  uint64_t blocked = 0;    ///< any hit: the rays found blocked
  alignas(64) float rdir[3][kSetRays];
  alignas(64) float org_rdir[3][kSetRays];
  alignas(64) float tmin[kSetRays];
  alignas(64) float tmax[kSetRays];  ///< as loaded (the first ray's test, a heuristic, goes on without later hits)
  // The frustum, per axis over the active rays. A ray's distance to the plane
  // x_a = b is (b - org) * rdir; over the set's range of org and rdir (rdir
  // of one sign) its least value is reached at org_near and one end of
  // rdir, its greatest at org_far and the other.
  OctantPlanes planes;                  ///< the active rays' near and far plane rows
  vfloat4 rdir_lo[3], rdir_hi[3];       ///< least and greatest reciprocal direction
  vfloat4 org_near[3], org_far[3];      ///< the origin coordinates that bound the near and far distances
  vfloat4 slack_rdir[3], slack_org[3];  ///< the widening: (|b| slack_rdir + slack_org) for plane b
  float tmin_lo = 0.0f, tmax_hi = 0.0f;

  /// Ray k of the set as a record (for a lone ray's leaf test).
  Ray ray(uint32_t k) const { return queue->ray(first + k); }
};

namespace set_detail {

/// Relative widening of the frustum's bounds: 2^-20, four times the sum of
/// the relative rounding errors of the rays' distances (org * rdir rounded,
/// then b * rdir - that, fused or not) and of the frustum's own (b - org,
/// rounded, times rdir, rounded), each at most 2^-24 of |b| |rdir| + |org| |rdir|.
inline constexpr float kSlack = 1.0f / (1 << 20);

/// The lanes of packet j in a 64-bit mask of the set's rays.
PT_ALWAYS_INLINE uint32_t lanes_of_packet(uint64_t mask, uint32_t j) {
  return static_cast<uint32_t>(mask >> (j * kLanes)) & lanes_below(kLanes);
}

/// Loads rays [i0, i0 + n) of the queue (n <= kSetRays) into s, with their
/// slab constants and which of them are traceable; every ray's hit starts
/// as a miss at its tmax.
inline void load_set(const RayArrays& rays, size_t i0, size_t n, CoherentSet& s) {
  s.queue = &rays;
  s.first = i0;
  s.packets = static_cast<uint32_t>((n + kLanes - 1) / kLanes);
  s.traceable = s.blocked = 0;
  for (uint32_t j = 0; j < s.packets; ++j) {
    SetPacket& p = s.packet[j];
    const size_t at = i0 + j * kLanes;
    QueueLanes r(rays, at);
    const uint32_t lanes = r.traceable & lanes_below(std::min<size_t>(kLanes, n - j * kLanes));
    p.ray = {{r.org[0], r.org[1], r.org[2]}, {r.dir[0], r.dir[1], r.dir[2]}, r.tmin};
    p.hit = {r.tmax, vfloatK(0.0f), vfloatK(0.0f), vintK(-1)};
    for (int a = 0; a < 3; ++a) p.rdir[a] = r.rdir[a], p.org_rdir[a] = r.org_rdir[a];
    s.traceable |= uint64_t(lanes) << (j * kLanes);
    for (int a = 0; a < 3; ++a) {
      p.rdir[a].store_aligned(s.rdir[a] + j * kLanes);
      p.org_rdir[a].store_aligned(s.org_rdir[a] + j * kLanes);
    }
    p.ray.tmin.store_aligned(s.tmin + j * kLanes);
    p.hit.t.store_aligned(s.tmax + j * kLanes);
  }
}

/// The traceable rays of each direction octant (bit a of the octant: the
/// reciprocal direction on axis a is negative), packet by packet from the
/// lanes' sign masks.
inline void rays_by_octant(const CoherentSet& s, uint64_t (&by_octant)[8]) {
  std::fill(by_octant, by_octant + 8, uint64_t(0));
  for (uint32_t j = 0; j < s.packets; ++j) {
    const uint32_t lanes = lanes_of_packet(s.traceable, j);
    if (lanes == 0) continue;
    uint32_t negative[3];
    for (int a = 0; a < 3; ++a) negative[a] = lane_mask(s.packet[j].rdir[a] < vfloatK(0.0f));
    for (uint32_t octant = 0; octant < 8; ++octant) {
      uint32_t in = lanes;
      for (int a = 0; a < 3; ++a) in &= (octant >> a & 1) ? negative[a] : ~negative[a];
      by_octant[octant] |= uint64_t(in) << (j * kLanes);
    }
  }
}

/// Makes the rays of `mask` (traceable, of direction octant `octant`) the
/// set's active rays and computes their frustum.
inline void aim_set(CoherentSet& s, uint64_t mask, uint32_t octant) {
  s.active = mask;
  s.planes = OctantPlanes(octant);
  const vfloatK inf(INFINITY), ninf(-INFINITY);
  vfloatK rlo[3] = {inf, inf, inf}, rhi[3] = {ninf, ninf, ninf}, olo[3] = {inf, inf, inf}, ohi[3] = {ninf, ninf, ninf};
  vfloatK tlo = inf, thi = ninf;
  for (uint32_t j = 0; j < s.packets; ++j) {
    const SetPacket& p = s.packet[j];
    const vboolK on = lanes_of_mask(lanes_of_packet(mask, j));
    for (int a = 0; a < 3; ++a) {
      rlo[a] = xsimd::min(rlo[a], xsimd::select(on, p.rdir[a], inf));
      rhi[a] = xsimd::max(rhi[a], xsimd::select(on, p.rdir[a], ninf));
      olo[a] = xsimd::min(olo[a], xsimd::select(on, p.ray.org[a], inf));
      ohi[a] = xsimd::max(ohi[a], xsimd::select(on, p.ray.org[a], ninf));
    }
    tlo = xsimd::min(tlo, xsimd::select(on, p.ray.tmin, inf));
    thi = xsimd::max(thi, xsimd::select(on, p.hit.t, ninf));
  }
  for (int a = 0; a < 3; ++a) {
    const float lo = reduce_min_k(rlo[a]), hi = reduce_max_k(rhi[a]);
    const float o_lo = reduce_min_k(olo[a]), o_hi = reduce_max_k(ohi[a]);
    const bool positive = (octant >> a & 1) == 0;  // every rdir of the active rays has this sign
    s.rdir_lo[a] = vfloat4(lo), s.rdir_hi[a] = vfloat4(hi);
    s.org_near[a] = vfloat4(positive ? o_hi : o_lo);
    s.org_far[a] = vfloat4(positive ? o_lo : o_hi);
    const float r_abs = std::max(std::fabs(lo), std::fabs(hi));
    s.slack_rdir[a] = vfloat4(r_abs * kSlack);
    s.slack_org[a] = vfloat4(std::max(std::fabs(o_lo), std::fabs(o_hi)) * r_abs * kSlack);
  }
  s.tmin_lo = reduce_min_k(tlo);
  s.tmax_hi = reduce_max_k(thi);
}

/// Whether every active ray has the first active ray's direction, bit for
/// bit (a directional light's shadow rays); `dir` takes that direction.
inline bool in_one_direction(const CoherentSet& s, vfloat4 (&dir)[3]) {
  const uint32_t k = static_cast<uint32_t>(std::countr_zero(s.active));
  const float d[3] = {s.queue->dir[0][s.first + k], s.queue->dir[1][s.first + k], s.queue->dir[2][s.first + k]};
  for (int a = 0; a < 3; ++a) dir[a] = vfloat4(d[a]);
  for (uint32_t j = 0; j < s.packets; ++j) {
    const TriangleLanes& r = s.packet[j].ray;
    const vboolK same = same_bits(r.dir[0], d[0]) & same_bits(r.dir[1], d[1]) & same_bits(r.dir[2], d[2]);
    const uint32_t lanes = lanes_of_packet(s.active, j);
    if ((lane_mask(same) & lanes) != lanes) return false;
  }
  return true;
}

/// The children of `node` that some active ray may enter (a bit each), with
/// a lower bound on every ray's entry distance into each in `fnear`. An
/// empty slot (lower +inf, upper -inf) gives NaN on every axis (inf - inf),
/// so its last axis leaves both bounds NaN and it fails.
PT_ALWAYS_INLINE uint32_t frustum_admits(const Bvh4Node& node, const CoherentSet& s, vfloat4& fnear) {
  auto plane = [&](uint32_t row) { return vfloat4::load_aligned(node.bounds[row]); };
  vfloat4 lo = vfloat4(s.tmin_lo), hi = vfloat4(s.tmax_hi);
  for (int a = 0; a < 3; ++a) {
    const vfloat4 bn = plane(s.planes.near[a]), bf = plane(s.planes.far[a]);
    const vfloat4 dn = bn - s.org_near[a], df = bf - s.org_far[a];
    const vfloat4 wn = xsimd::abs(bn) * s.slack_rdir[a] + s.slack_org[a];
    const vfloat4 wf = xsimd::abs(bf) * s.slack_rdir[a] + s.slack_org[a];
    lo = xsimd::max(lo, xsimd::min(dn * s.rdir_lo[a], dn * s.rdir_hi[a]) - wn);
    hi = xsimd::min(hi, xsimd::max(df * s.rdir_lo[a], df * s.rdir_hi[a]) + wf);
  }
  fnear = lo;
  return movemask(lo <= hi);
}

/// The children of `node` that ray `k` of the set enters, by its own test.
PT_ALWAYS_INLINE uint32_t ray_enters(const Bvh4Node& node, const CoherentSet& s, uint32_t k) {
  uint32_t near[3], far[3];
  s.planes.offsets(near, far);
  const vfloat4 rdir[3] = {vfloat4(s.rdir[0][k]), vfloat4(s.rdir[1][k]), vfloat4(s.rdir[2][k])};
  const vfloat4 org_rdir[3] = {vfloat4(s.org_rdir[0][k]), vfloat4(s.org_rdir[1][k]), vfloat4(s.org_rdir[2][k])};
  vfloat4 tnear;
  return movemask(
      children_entered(child_planes(node, near, far), rdir, org_rdir, vfloat4(s.tmin[k]), vfloat4(s.tmax[k]), tnear));
}

/// The rays of `mask` that enter child c of `node`, each by its own test.
PT_ALWAYS_INLINE uint64_t rays_entering(const Bvh4Node& node, int c, const CoherentSet& s, uint64_t mask) {
  uint64_t in = 0;
  for (uint32_t j = 0; j < s.packets; ++j) {
    const uint32_t lanes = lanes_of_packet(mask, j);
    if (lanes == 0) continue;
    vfloatK tnear;
    in |= uint64_t(lanes & lane_mask(lanes_enter_child(node, c, s.packet[j].node_lanes(), s.planes, tnear)))
          << (j * kLanes);
  }
  return in;
}

/// 24 bytes. A node or leaf on a set's stack.
struct SetEntry {
  uint32_t ref;     ///< the node or leaf
  uint32_t parent;  ///< its parent node, or kEmptyRef for the root
  float dist;       ///< no ray of the set enters it before this distance
  uint32_t slot;    ///< its place among the parent's children
  uint64_t mask;    ///< the rays that may enter it
};

/// Visits the node of `e` with the rays of e.mask: pushes every child some of
/// them may enter but the nearest (far first), which it makes e (ref, parent,
/// slot, entry bound and rays); false when they enter none.
template <class C>
PT_ALWAYS_INLINE bool visit_node(const Bvh4& bvh, const CoherentSet& s, SetEntry& e, SetEntry*& sp, C& counters) {
  const Bvh4Node& node = bvh.node(e.ref);
  counters.nodes_tested(std::popcount(e.mask));
  vfloat4 fnear;
  uint32_t admitted = frustum_admits(node, s, fnear);
  if (admitted == 0) return false;
  uint64_t child_mask[4] = {e.mask, e.mask, e.mask, e.mask};
  for (uint32_t m = admitted & ~ray_enters(node, s, static_cast<uint32_t>(std::countr_zero(e.mask))); m; m &= m - 1) {
    const int c = std::countr_zero(m);
    child_mask[c] = rays_entering(node, c, s, e.mask);
    if (child_mask[c] == 0) admitted &= ~(1u << c);
  }
  if (admitted == 0) return false;
  alignas(16) float d[4];
  fnear.store_aligned(d);
  SetEntry hit[4];
  int n = 0;
  for (uint32_t m = admitted; m; m &= m - 1) {
    const uint32_t c = static_cast<uint32_t>(std::countr_zero(m));
    hit[n++] = {node.child[c], e.ref, d[c], c, child_mask[c]};
  }
  for (int i = 1; i < n; ++i)  // insertion sort, far first
    for (int j = i; j > 0 && hit[j - 1].dist < hit[j].dist; --j) std::swap(hit[j - 1], hit[j]);
  for (int i = 0; i + 1 < n; ++i) {
    *sp++ = hit[i];
    prefetch_ref(bvh, hit[i].ref);
  }
  e = hit[n - 1];
  return true;
}

/// The lanes of packet j that are in `mask` and enter leaf `slot` of
/// `parent` by their own test (all of them under the root).
PT_ALWAYS_INLINE uint32_t lanes_in_leaf(const Bvh4& bvh, const SetEntry& e, const CoherentSet& s, uint32_t j) {
  const uint32_t lanes = lanes_of_packet(e.mask, j);
  if (lanes == 0 || e.parent == bvh4_ref::kEmptyRef) return lanes;
  vfloatK tnear;
  return lanes & lane_mask(lanes_enter_child(bvh.node(e.parent), static_cast<int>(e.slot), s.packet[j].node_lanes(),
                                             s.planes, tnear));
}

/// A packet with at most this many rays in a leaf tests it ray by ray, with
/// the walks' block tests, rather than every triangle across K lanes: a lone
/// ray (2, K/4 and K/2 measured alike).
inline constexpr uint32_t kLeafRaysAlone = 1;

/// The leaf test of the lanes of packet j: closest hit takes nearer hits
/// into the packet and returns the lanes whose hit changed; any hit returns
/// the lanes blocked. `terms`: as leaf_lanes takes them.
template <bool kAnyHit, class C>
PT_ALWAYS_INLINE uint32_t test_leaf(const TriangleBlock4* blocks, uint32_t n_blocks, CoherentSet& s, uint32_t j,
                                    uint32_t lanes, const BlockDirectionTerms* terms, C& counters) {
  SetPacket& p = s.packet[j];
  if (static_cast<uint32_t>(std::popcount(lanes)) > kLeafRaysAlone)
    return leaf_lanes<kAnyHit>(blocks, n_blocks, p.ray, lanes, p.hit, terms, counters);
  alignas(64) float t[kLanes], u[kLanes], v[kLanes];
  alignas(64) int32_t prim[kLanes];
  p.hit.t.store_aligned(t), p.hit.u.store_aligned(u), p.hit.v.store_aligned(v), p.hit.prim.store_aligned(prim);
  uint32_t changed = 0;
  for (uint32_t m = lanes; m; m &= m - 1) {
    const uint32_t i = static_cast<uint32_t>(std::countr_zero(m));
    Hit hit{t[i], u[i], v[i], static_cast<uint32_t>(prim[i])};
    float tmax = hit.t;
    vfloat4 vtmax(tmax);
    const bool blocked =
        leaf_hit<kAnyHit, MtBlocks>(blocks, n_blocks, MtBlockRay(s.ray(j * kLanes + i)), {tmax, vtmax, hit}, counters);
    if (kAnyHit ? !blocked : !(hit.t < t[i])) continue;
    t[i] = hit.t, u[i] = hit.u, v[i] = hit.v, prim[i] = static_cast<int32_t>(hit.prim);
    changed |= 1u << i;
  }
  if (!kAnyHit && changed) {
    p.hit = {vfloatK::load_aligned(t), vfloatK::load_aligned(u), vfloatK::load_aligned(v), vintK::load_aligned(prim)};
  }
  return changed;
}

}  // namespace set_detail

/// Traces the active rays of a loaded and aimed set (set_detail::aim_set).
/// Closest hit: each packet's hit takes its rays' closest hits. Any hit: the
/// blocked rays join s.blocked.
template <bool kAnyHit, class C>
inline void trace_set(const Bvh4& bvh, CoherentSet& s, C& counters) {
  using namespace set_detail;
  if (bvh.empty() || s.active == 0) return;
  vfloat4 dir[3];
  const bool one_direction = kAnyHit && in_one_direction(s, dir);
  SetEntry stack[kBvh4StackSize];
  SetEntry* sp = stack;
  *sp++ = {bvh.root, bvh4_ref::kEmptyRef, -INFINITY, 0, s.active};
  while (sp != stack) {
    SetEntry e = *--sp;
    if constexpr (kAnyHit) {
      e.mask &= ~s.blocked;
      if (e.mask == 0) continue;
    } else if (e.dist > s.tmax_hi) {
      continue;  // every ray has a nearer hit by now
    }
    bool entered = true;
    while (entered && !bvh4_ref::is_leaf(e.ref)) entered = visit_node(bvh, s, e, sp, counters);
    if (!entered) continue;
    const TriangleBlock4* blocks = bvh.leaf_blocks(e.ref);
    const uint32_t n_blocks = bvh4_ref::leaf_block_count(e.ref);
    LeafDirectionTerms terms;
    uint64_t changed = 0;
    for (uint32_t j = 0; j < s.packets; ++j) {
      const uint32_t lanes = lanes_in_leaf(bvh, e, s, j);
      if (lanes == 0) continue;
      const bool by_terms = one_direction && static_cast<uint32_t>(std::popcount(lanes)) > kLeafRaysAlone;
      changed |= uint64_t(test_leaf<kAnyHit>(blocks, n_blocks, s, j, lanes,
                                             by_terms ? terms.get(blocks, n_blocks, dir) : nullptr, counters))
                 << (j * kLanes);
    }
    if constexpr (kAnyHit) {
      s.blocked |= changed;
      if ((s.blocked & s.active) == s.active) break;
    } else if (changed) {
      vfloatK hi(-INFINITY);
      for (uint32_t j = 0; j < s.packets; ++j)
        hi = xsimd::max(
            hi, xsimd::select(lanes_of_mask(lanes_of_packet(s.active, j)), s.packet[j].hit.t, vfloatK(-INFINITY)));
      s.tmax_hi = reduce_max_k(hi);
    }
  }
}

/// Traces the traceable rays of a loaded set (set_detail::load_set; the
/// caller may have dropped some from s.traceable since) as sets, one per
/// direction octant they lie in. Closest hit: s.packet[j].hit holds the hits
/// (misses keep t = tmax and prim -1). Any hit: s.blocked the rays blocked.
template <bool kAnyHit, class C>
inline void trace_set_by_octant(const Bvh4& bvh, CoherentSet& s, C& counters) {
  uint64_t by_octant[8];
  set_detail::rays_by_octant(s, by_octant);
  for (uint32_t octant = 0; octant < 8; ++octant) {
    if (by_octant[octant] == 0) continue;
    set_detail::aim_set(s, by_octant[octant], octant);
    trace_set<kAnyHit>(bvh, s, counters);
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt
