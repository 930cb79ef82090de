// Coherent sets: up to 64 consecutive rays of a coherent queue (a pinhole
// camera's, or a directional light's shadow rays from first hits) traced as
// one unit, the way Embree's coherent streams trace them. A node is tested
// against the set's frustum (one 4-wide test that bounds every ray's entry
// and exit distances) and against the set's first ray; only a child that the
// frustum admits and that ray misses is tested packet by packet. So most
// nodes cost two 4-wide tests, whatever the set holds, where packets of K
// rays (bvh4_packet.h) pay four K-wide tests per packet. A child keeps its
// parent's rays; they are culled packet by packet only at a leaf, by each
// ray's own slab test of the leaf's box, and then test its triangles as
// packets do. When every ray has one direction (a directional light's), the
// part of each triangle's test that depends on the direction alone is
// computed once per leaf, not once per packet and triangle.
//
// Every ray gets the hit its own traversal gives (exact ties aside): the
// frustum is conservative (its bounds widened past the rounding of its own
// arithmetic and of the rays'), a child is dropped only by the frustum or by
// every ray's own test, and a ray tests a leaf's triangles only where its own
// slab test enters the leaf.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "bvh4_node_test.h"
#include "bvh4_packet.h"
#include "bvh4_traverse.h"
#include "triangle4_intersect.h"

#if !PT_PER_LEVEL
#error "bvh4_coherent_set.h is for code compiled once per instruction-set level"
#endif

namespace pt {
inline namespace PT_ISA_NS {

/// Rays a coherent set holds at most (one bit each in a 64-bit mask).
inline constexpr uint32_t kSetRays = 64;
inline constexpr uint32_t kSetPackets = kSetRays / kLanes;

/// Up to kSetRays rays as packets of K, with each ray's slab constants also
/// by ray (for the first ray's test) and the frustum of the traceable ones.
struct CoherentSet {
  RayPacket packet[kSetPackets];
  PacketHits hits[kSetPackets];
  uint32_t packets = 0;
  uint64_t active = 0;  ///< the traceable rays, bit 8 j + i for lane i of packet j (K = 8)
  alignas(64) float rdir[3][kSetRays];
  alignas(64) float org_rdir[3][kSetRays];
  alignas(64) float tmin[kSetRays];
  alignas(64) float tmax[kSetRays];  ///< as loaded (the first ray's test, a heuristic, goes on without its later hits)
  // The frustum, per axis over the traceable rays. A ray's distance to the
  // plane x_a = b is (b - org) * rdir; over the set's range of org and rdir
  // (rdir of one sign) its least value is reached at org_near and one end of
  // rdir, its greatest at org_far and the other.
  uint32_t near[3] = {}, far[3] = {};   ///< plane rows, as RayPacket's (shared by every packet)
  vfloat4 rdir_lo[3], rdir_hi[3];       ///< least and greatest reciprocal direction
  vfloat4 org_near[3], org_far[3];      ///< the origin coordinates that bound the near and far distances
  vfloat4 slack_rdir[3], slack_org[3];  ///< the widening: (|b| slack_rdir + slack_org) for plane b
  float tmin_lo = 0.0f, tmax_hi = 0.0f;
};

namespace set_detail {

/// Relative widening of the frustum's bounds: 2^-20, four times the sum of
/// the relative rounding errors of the rays' distances (org * rdir rounded,
/// then b * rdir - that, fused or not) and of the frustum's own (b - org,
/// rounded, times rdir, rounded), each at most 2^-24 of |b| |rdir| + |org| |rdir|.
inline constexpr float kSlack = 1.0f / (1 << 20);

/// Whether every traceable ray of a loaded set (s.active != 0) has the first
/// one's direction, bit for bit (a directional light's shadow rays); `dir`
/// takes that direction.
inline bool in_one_direction(const CoherentSet& s, vfloat4 (&dir)[3]) {
  const RayPacket& first = s.packet[std::countr_zero(s.active) / kLanes];
  alignas(64) float d[3][kLanes];
  for (int a = 0; a < 3; ++a) first.dir[a].store_aligned(d[a]);
  const int lane = std::countr_zero(first.active);
  for (int a = 0; a < 3; ++a) dir[a] = vfloat4(d[a][lane]);
  for (uint32_t j = 0; j < s.packets; ++j) {
    const RayPacket& p = s.packet[j];
    const vboolK same =
        same_bits(p.dir[0], d[0][lane]) & same_bits(p.dir[1], d[1][lane]) & same_bits(p.dir[2], d[2][lane]);
    if ((lane_mask(same) & p.active) != p.active) return false;
  }
  return true;
}

/// Loads rays [i0, i0 + n) of the queue (n <= kSetRays) as packets, and
/// their frustum. Returns false when the traceable rays do not share one
/// direction octant (the set then goes packet by packet).
inline bool load_set(const RayArrays& rays, size_t i0, size_t n, CoherentSet& s) {
  s.packets = static_cast<uint32_t>((n + kLanes - 1) / kLanes);
  s.active = 0;
  const vfloatK inf(INFINITY), ninf(-INFINITY);
  vfloatK rlo[3] = {inf, inf, inf}, rhi[3] = {ninf, ninf, ninf}, olo[3] = {inf, inf, inf}, ohi[3] = {ninf, ninf, ninf};
  vfloatK tlo = inf, thi = ninf;
  bool first = true, shared = true;
  for (uint32_t j = 0; j < s.packets; ++j) {
    RayPacket& p = s.packet[j];
    load_ray_packet(rays, i0 + j * kLanes, std::min<size_t>(kLanes, n - j * kLanes), p);
    s.hits[j].u = s.hits[j].v = vfloatK(0.0f);
    s.hits[j].prim = vintK(-1);
    if (p.active == 0) continue;
    if (first) {
      std::copy(p.near, p.near + 3, s.near);
      std::copy(p.far, p.far + 3, s.far);
      first = false;
    }
    shared = shared && p.uniform && std::equal(p.near, p.near + 3, s.near);
    s.active |= uint64_t(p.active) << (j * kLanes);
    const vboolK on = lanes_of_mask(p.active);
    for (int a = 0; a < 3; ++a) {
      rlo[a] = xsimd::min(rlo[a], xsimd::select(on, p.rdir[a], inf));
      rhi[a] = xsimd::max(rhi[a], xsimd::select(on, p.rdir[a], ninf));
      olo[a] = xsimd::min(olo[a], xsimd::select(on, p.org[a], inf));
      ohi[a] = xsimd::max(ohi[a], xsimd::select(on, p.org[a], ninf));
      p.rdir[a].store_aligned(s.rdir[a] + j * kLanes);
      p.org_rdir[a].store_aligned(s.org_rdir[a] + j * kLanes);
    }
    tlo = xsimd::min(tlo, xsimd::select(on, p.tmin, inf));
    thi = xsimd::max(thi, xsimd::select(on, p.tmax, ninf));
    p.tmin.store_aligned(s.tmin + j * kLanes);
    p.tmax.store_aligned(s.tmax + j * kLanes);
  }
  if (!shared) return false;
  if (s.active == 0) return true;
  for (int a = 0; a < 3; ++a) {
    const float lo = reduce_min_k(rlo[a]), hi = reduce_max_k(rhi[a]);
    const float o_lo = reduce_min_k(olo[a]), o_hi = reduce_max_k(ohi[a]);
    const bool positive = lo >= 0.0f;  // every rdir of the set has this sign
    s.rdir_lo[a] = vfloat4(lo), s.rdir_hi[a] = vfloat4(hi);
    s.org_near[a] = vfloat4(positive ? o_hi : o_lo);
    s.org_far[a] = vfloat4(positive ? o_lo : o_hi);
    const float r_abs = std::max(std::fabs(lo), std::fabs(hi));
    s.slack_rdir[a] = vfloat4(r_abs * kSlack);
    s.slack_org[a] = vfloat4(std::max(std::fabs(o_lo), std::fabs(o_hi)) * r_abs * kSlack);
  }
  s.tmin_lo = reduce_min_k(tlo);
  s.tmax_hi = reduce_max_k(thi);
  return true;
}

/// The children of `node` that some ray of the set may enter (a bit each),
/// with a lower bound on every ray's entry distance into each in `fnear`.
/// An empty slot (lower +inf, upper -inf) gives NaN on every axis (inf -
/// inf), so its last axis leaves both bounds NaN and it fails.
PT_ALWAYS_INLINE uint32_t frustum_admits(const Bvh4Node& node, const CoherentSet& s, vfloat4& fnear) {
  auto plane = [&](uint32_t row) { return vfloat4::load_aligned(node.bounds[row]); };
  vfloat4 lo = vfloat4(s.tmin_lo), hi = vfloat4(s.tmax_hi);
  for (int a = 0; a < 3; ++a) {
    const vfloat4 bn = plane(s.near[a]), bf = plane(s.far[a]);
    const vfloat4 dn = bn - s.org_near[a], df = bf - s.org_far[a];
    const vfloat4 wn = xsimd::abs(bn) * s.slack_rdir[a] + s.slack_org[a];
    const vfloat4 wf = xsimd::abs(bf) * s.slack_rdir[a] + s.slack_org[a];
    lo = xsimd::max(lo, xsimd::min(dn * s.rdir_lo[a], dn * s.rdir_hi[a]) - wn);
    hi = xsimd::min(hi, xsimd::max(df * s.rdir_lo[a], df * s.rdir_hi[a]) + wf);
  }
  fnear = lo;
  return movemask(lo <= hi);
}

/// The children of `node` that ray `i` of the set enters, by its own test.
PT_ALWAYS_INLINE uint32_t ray_enters(const Bvh4Node& node, const CoherentSet& s, uint32_t i) {
  NodeRay r;
  for (int a = 0; a < 3; ++a) {
    r.rdir[a] = vfloat4(s.rdir[a][i]);
    r.org_rdir[a] = vfloat4(s.org_rdir[a][i]);
    r.near[a] = s.near[a] * uint32_t(sizeof(float[4]));
    r.far[a] = s.far[a] * uint32_t(sizeof(float[4]));
  }
  vfloat4 tnear;
  return intersect_node(node, r, vfloat4(s.tmin[i]), vfloat4(s.tmax[i]), tnear);
}

/// The rays of `mask` that enter child c of `node`, each by its own test.
PT_ALWAYS_INLINE uint64_t rays_entering(const Bvh4Node& node, int c, const CoherentSet& s, uint64_t mask) {
  uint64_t in = 0;
  for (uint32_t j = 0; j < s.packets; ++j) {
    const uint32_t lanes = static_cast<uint32_t>(mask >> (j * kLanes)) & lanes_below(kLanes);
    if (lanes == 0) continue;
    vfloatK tnear, tfar;
    packet_detail::child_slabs<true>(node, c, s.packet[j], tnear, tfar);
    in |= uint64_t(lanes & lane_mask(tnear <= tfar)) << (j * kLanes);
  }
  return in;
}

struct SetEntry {
  uint32_t ref;     ///< the node or leaf
  uint32_t parent;  ///< its parent node, or kEmptyRef for the root
  float dist;       ///< no ray of the set enters it before this distance
  uint32_t slot;    ///< its place among the parent's children
  uint64_t mask;    ///< the rays that may enter it
};

/// Visits `node` with the rays of `mask`: pushes every child some of them
/// may enter but the nearest (far first), which it returns with its rays
/// and entry bound (kEmptyRef when none).
PT_ALWAYS_INLINE uint32_t visit_node(const Bvh4& bvh, uint32_t ref, const CoherentSet& s, uint64_t& mask,
                                     uint32_t& slot, float& dist, SetEntry*& sp) {
  const Bvh4Node& node = bvh.node(ref);
  vfloat4 fnear;
  uint32_t admitted = frustum_admits(node, s, fnear);
  if (admitted == 0) return bvh4_ref::kEmptyRef;
  uint64_t child_mask[4] = {mask, mask, mask, mask};
  for (uint32_t m = admitted & ~ray_enters(node, s, static_cast<uint32_t>(std::countr_zero(mask))); m; m &= m - 1) {
    const int c = std::countr_zero(m);
    child_mask[c] = rays_entering(node, c, s, mask);
    if (child_mask[c] == 0) admitted &= ~(1u << c);
  }
  if (admitted == 0) return bvh4_ref::kEmptyRef;
  alignas(16) float d[4];
  fnear.store_aligned(d);
  SetEntry hit[4];
  int n = 0;
  for (uint32_t m = admitted; m; m &= m - 1) {
    const uint32_t c = static_cast<uint32_t>(std::countr_zero(m));
    hit[n++] = {node.child[c], ref, d[c], c, child_mask[c]};
  }
  for (int i = 1; i < n; ++i)  // insertion sort, far first
    for (int j = i; j > 0 && hit[j - 1].dist < hit[j].dist; --j) std::swap(hit[j - 1], hit[j]);
  for (int i = 0; i + 1 < n; ++i) {
    *sp++ = hit[i];
    prefetch_ref(bvh, hit[i].ref);
  }
  mask = hit[n - 1].mask;
  slot = hit[n - 1].slot;
  dist = hit[n - 1].dist;
  return hit[n - 1].ref;
}

/// Goes down from a popped entry to the leaf its nearest entered children
/// lead to, pushing the others: `e` then names that leaf, its parent and
/// slot, and the rays that may enter it. False where no child on the way is
/// entered.
PT_ALWAYS_INLINE bool descend_to_leaf(const Bvh4& bvh, const CoherentSet& s, SetEntry& e, SetEntry*& sp) {
  while (!bvh4_ref::is_leaf(e.ref)) {
    const uint32_t node = e.ref;
    e.ref = visit_node(bvh, node, s, e.mask, e.slot, e.dist, sp);
    if (e.ref == bvh4_ref::kEmptyRef) return false;
    e.parent = node;
  }
  return true;
}

/// The lanes of packet j that are in `mask` and enter leaf `slot` of
/// `parent` by their own test (all of them under the root).
PT_ALWAYS_INLINE uint32_t lanes_in_leaf(const Bvh4& bvh, uint32_t parent, uint32_t slot, const CoherentSet& s,
                                        uint32_t j, uint64_t mask) {
  uint32_t lanes = static_cast<uint32_t>(mask >> (j * kLanes)) & lanes_below(kLanes);
  if (lanes == 0 || parent == bvh4_ref::kEmptyRef) return lanes;
  vfloatK tnear, tfar;
  packet_detail::child_slabs<true>(bvh.node(parent), static_cast<int>(slot), s.packet[j], tnear, tfar);
  return lanes & lane_mask(tnear <= tfar);
}

/// A packet with at most this many rays in a leaf tests it ray by ray (with
/// the block tests of single rays, bvh4_traverse.h) rather than every
/// triangle across all K lanes: a lone ray (2, K/4 and K/2 measured alike).
inline constexpr uint32_t kLeafRaysAlone = 1;

/// Closest hits of the packet's rays in `lanes` among a leaf's triangles:
/// its tmax and hits take the nearer ones.
inline void leaf_closest(const TriangleBlock4* blocks, uint32_t n_blocks, uint32_t lanes, RayPacket& p, PacketHits& h) {
  if (static_cast<uint32_t>(std::popcount(lanes)) > kLeafRaysAlone) {
    for (uint32_t i = 0; i < n_blocks; ++i)
      for (int t = 0; t < 4; ++t)
        if (blocks[i].prim[t] != kInvalidId) packet_detail::intersect_triangle_packet(blocks[i], t, lanes, p, h);
    return;
  }
  PacketHitLanes l(p, h);
  bool found = false;
  NoCounters counters;
  for (uint32_t m = lanes; m; m &= m - 1) {
    const uint32_t i = static_cast<uint32_t>(std::countr_zero(m));
    Hit hit{l.t[i], l.u[i], l.v[i], static_cast<uint32_t>(l.prim[i])};
    float tmax = hit.t;
    vfloat4 vtmax(tmax);
    intersect_leaf_closest<TriangleForm::kMollerTrumbore>(blocks, n_blocks, MtBlockRay(p.ray(i)), tmax, vtmax, hit,
                                                          counters);
    if (!(hit.t < l.t[i])) continue;
    l.t[i] = hit.t, l.u[i] = hit.u, l.v[i] = hit.v, l.prim[i] = static_cast<int32_t>(hit.prim);
    found = true;
  }
  if (found) l.load_into(p, h);
}

/// The packet's rays in `lanes` that a leaf's triangles block; `terms`, when
/// not null, are each block's direction terms for the one direction of them all.
inline uint32_t leaf_blocked(const TriangleBlock4* blocks, uint32_t n_blocks, uint32_t lanes, const RayPacket& p,
                             const BlockDirectionTerms* terms = nullptr) {
  uint32_t blocked = 0;
  if (static_cast<uint32_t>(std::popcount(lanes)) <= kLeafRaysAlone) {
    alignas(64) float tmax[kLanes];
    p.tmax.store_aligned(tmax);
    NoCounters counters;
    for (uint32_t m = lanes; m; m &= m - 1) {
      const uint32_t i = static_cast<uint32_t>(std::countr_zero(m));
      if (leaf_occludes<TriangleForm::kMollerTrumbore>(blocks, n_blocks, MtBlockRay(p.ray(i)), vfloat4(tmax[i]),
                                                       counters))
        blocked |= 1u << i;
    }
    return blocked;
  }
  for (uint32_t i = 0; i < n_blocks && lanes; ++i)
    for (int t = 0; t < 4 && lanes; ++t)
      if (blocks[i].prim[t] != kInvalidId) {
        const uint32_t hit = terms ? packet_detail::occluders_in_packet(blocks[i], terms[i], t, lanes, p)
                                   : packet_detail::occluders_in_packet(blocks[i], t, lanes, p);
        lanes &= ~hit;
        blocked |= hit;
      }
  return blocked;
}

}  // namespace set_detail

/// Closest hits (Moller-Trumbore form) of a loaded set's rays into its
/// packets (tmax and hits, as bvh4_intersect_packet leaves them).
inline void bvh4_intersect_set(const Bvh4& bvh, CoherentSet& s) {
  using namespace set_detail;
  if (bvh.empty() || s.active == 0) return;
  SetEntry stack[kBvh4StackSize];
  SetEntry* sp = stack;
  *sp++ = {bvh.root, bvh4_ref::kEmptyRef, -INFINITY, 0, s.active};
  while (sp != stack) {
    SetEntry e = *--sp;
    if (e.dist > s.tmax_hi) continue;  // every ray has a nearer hit by now
    if (!descend_to_leaf(bvh, s, e, sp)) continue;
    const TriangleBlock4* blocks = bvh.leaf_blocks(e.ref);
    const uint32_t n_blocks = bvh4_ref::leaf_block_count(e.ref);
    bool found = false;
    for (uint32_t j = 0; j < s.packets; ++j) {
      const uint32_t lanes = lanes_in_leaf(bvh, e.parent, e.slot, s, j, e.mask);
      if (lanes == 0) continue;
      const vfloatK before = s.packet[j].tmax;
      leaf_closest(blocks, n_blocks, lanes, s.packet[j], s.hits[j]);
      found = found || (lane_mask(s.packet[j].tmax != before) & s.packet[j].active) != 0;  // (NaN lanes aside)
    }
    if (!found) continue;
    vfloatK hi(-INFINITY);
    for (uint32_t j = 0; j < s.packets; ++j)
      hi = xsimd::max(hi, xsimd::select(lanes_of_mask(s.packet[j].active), s.packet[j].tmax, vfloatK(-INFINITY)));
    s.tmax_hi = reduce_max_k(hi);
  }
}

/// Any-hit occlusion (Moller-Trumbore form) of a loaded set's rays: the
/// blocked rays, bit for bit as CoherentSet::active.
inline uint64_t bvh4_occluded_set(const Bvh4& bvh, const CoherentSet& s) {
  using namespace set_detail;
  uint64_t blocked = 0;
  if (bvh.empty() || s.active == 0) return 0;
  vfloat4 dir[3];
  const bool one_direction = in_one_direction(s, dir);
  SetEntry stack[kBvh4StackSize];
  SetEntry* sp = stack;
  *sp++ = {bvh.root, bvh4_ref::kEmptyRef, -INFINITY, 0, s.active};
  while (sp != stack) {
    SetEntry e = *--sp;
    e.mask &= ~blocked;
    if (e.mask == 0 || !descend_to_leaf(bvh, s, e, sp)) continue;
    const TriangleBlock4* blocks = bvh.leaf_blocks(e.ref);
    const uint32_t n_blocks = bvh4_ref::leaf_block_count(e.ref);
    LeafDirectionTerms terms;
    for (uint32_t j = 0; j < s.packets; ++j) {
      const uint32_t lanes = lanes_in_leaf(bvh, e.parent, e.slot, s, j, e.mask);
      if (lanes == 0) continue;
      const bool by_terms = one_direction && static_cast<uint32_t>(std::popcount(lanes)) > kLeafRaysAlone;
      blocked |= uint64_t(leaf_blocked(blocks, n_blocks, lanes, s.packet[j],
                                       by_terms ? terms.get(blocks, n_blocks, dir) : nullptr))
                 << (j * kLanes);
    }
    if (blocked == s.active) break;
  }
  return blocked;
}

}  // namespace PT_ISA_NS
}  // namespace pt
