// Packets of K = kLanes coherent rays (the camera rays of a pixel block)
// through the 4-wide BVH. SIMD runs across the rays: each child box and each
// leaf triangle is tested against the whole packet at once, children hit by
// any active ray are visited nearest first, and the stack holds (node, rays)
// pairs. When the packet agrees on the direction signs (the usual case for
// camera rays) the slab test reads only near and far planes, as the single-ray
// test does. A subtree that fewer than kPacketMinRays of the packet's rays
// enter is traversed by each of them alone (tiny triangles split packets near
// the leaves). Moller-Trumbore leaves only; for incoherent rays the
// single-ray traversal (bvh4_traverse.h) is faster.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "bvh4.h"
#include "bvh4_node_test.h"
#include "bvh4_traverse.h"
#include "kernels/math/ray.h"
#include "kernels/math/ray_arrays.h"
#include "kernels/simd/simd.h"

#if !PT_PER_LEVEL
#error "bvh4_packet.h is for code compiled once per instruction-set level"
#endif

namespace pt {
inline namespace PT_ISA_NS {

/// K rays in SoA form with the per-packet constants of the slab test.
struct RayPacket {
  vfloatK org[3], dir[3], rdir[3], org_rdir[3], tmin, tmax;
  const Ray* rays = nullptr;           ///< the rays of the lanes as records, or null: they are `queue`'s from `first`
  const RayArrays* queue = nullptr;    ///< the queue of the lanes' rays when they have no records
  size_t first = 0;                    ///< the first lane's index in `queue`
  uint32_t active = 0;                 ///< lanes that trace (requested and traceable)
  bool uniform = false;                ///< all active lanes share the sign of each direction component
  uint32_t near[3] = {}, far[3] = {};  ///< plane rows when uniform

  /// Lane i's ray, for the single-ray traversal of a sparse subtree: made
  /// only for the lanes that need it, not for every ray of a queue.
  Ray ray(uint32_t i) const { return rays ? rays[i] : queue->ray(first + i); }
};

/// Closest hits of a packet in SoA form; lanes without a hit keep prim = kInvalidId.
struct PacketHits {
  vfloatK u = vfloatK(0.0f), v = vfloatK(0.0f);
  vintK prim = vintK(-1);  ///< primitive ids as int32 bit patterns; -1 = kInvalidId
};

/// A packet's tmax and hits as per-lane arrays, for work done lane by lane.
struct PacketHitLanes {
  alignas(64) float t[kLanes], u[kLanes], v[kLanes];
  alignas(64) int32_t prim[kLanes];  ///< primitive ids as int32 bit patterns

  PacketHitLanes(const RayPacket& p, const PacketHits& h) {
    p.tmax.store_aligned(t);
    h.u.store_aligned(u);
    h.v.store_aligned(v);
    h.prim.store_aligned(prim);
  }
  void load_into(RayPacket& p, PacketHits& h) const {
    p.tmax = vfloatK::load_aligned(t);
    h.u = vfloatK::load_aligned(u);
    h.v = vfloatK::load_aligned(v);
    h.prim = vintK::load_aligned(prim);
  }
};

/// Fills the packet's per-lane constants from its org, dir, tmin and tmax:
/// the traceable lanes of `lanes`, the reciprocal directions and whether the
/// active lanes agree on the direction signs.
inline void finish_ray_packet(RayPacket& p, uint32_t lanes) {
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
}

/// Loads rays[i] for the lanes i set in `lanes` (other entries are not read).
/// (GCC would vectorise the transposition below back into gathers.)
#if defined(__GNUC__) && !defined(__clang__)
__attribute__((optimize("no-tree-vectorize")))
#endif
inline RayPacket
load_ray_packet(const Ray* rays, uint32_t lanes) {
  RayPacket p;
  p.rays = rays;
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
  finish_ray_packet(p, lanes);
  return p;
}

/// Loads a packet of K consecutive rays of a queue held as arrays into p,
/// rays [i0, i0 + n) with n <= K, the lanes past n copying the first ray.
/// The packet reads its rays back from the queue (RayPacket::ray), which must
/// outlive it.
inline void load_ray_packet(const RayArrays& q, size_t i0, size_t n, RayPacket& p) {
  p.rays = nullptr;
  p.queue = &q;
  p.first = i0;
  const uint32_t lanes = lanes_below(n);
  auto load = [&](const float* a) {
    if (n == kLanes) return vfloatK::load_unaligned(a + i0);
    alignas(64) float v[kLanes];
    for (size_t l = 0; l < kLanes; ++l) v[l] = a[i0 + (l < n ? l : 0)];
    return vfloatK::load_aligned(v);
  };
  for (int a = 0; a < 3; ++a) p.org[a] = load(q.org[a]), p.dir[a] = load(q.dir[a]);
  p.tmin = q.tmin ? load(q.tmin) : vfloatK(0.0f);
  p.tmax = load(q.tmax);
  finish_ray_packet(p, lanes);
}

/// The packet of rays [i0, i0 + n) of a queue held as arrays (as above).
inline RayPacket load_ray_packet(const RayArrays& q, size_t i0, size_t n) {
  RayPacket p;
  load_ray_packet(q, i0, n, p);
  return p;
}

namespace packet_detail {

/// Entry and exit distances of all rays through child c of `node`.
template <bool kUniform>
inline void child_slabs(const Bvh4Node& node, int c, const RayPacket& p, vfloatK& tnear, vfloatK& tfar) {
  if constexpr (kUniform) {
    auto plane = [&](uint32_t row) { return vfloatK(node.bounds[row][c]); };
    tnear = xsimd::max(xsimd::max(fused_mul_sub_k(plane(p.near[0]), p.rdir[0], p.org_rdir[0]),
                                  fused_mul_sub_k(plane(p.near[1]), p.rdir[1], p.org_rdir[1])),
                       xsimd::max(fused_mul_sub_k(plane(p.near[2]), p.rdir[2], p.org_rdir[2]), p.tmin));
    tfar = xsimd::min(xsimd::min(fused_mul_sub_k(plane(p.far[0]), p.rdir[0], p.org_rdir[0]),
                                 fused_mul_sub_k(plane(p.far[1]), p.rdir[1], p.org_rdir[1])),
                      xsimd::min(fused_mul_sub_k(plane(p.far[2]), p.rdir[2], p.org_rdir[2]), p.tmax));
  } else {
    tnear = p.tmin;
    tfar = p.tmax;
    for (int a = 0; a < 3; ++a) {
      vfloatK t0 = fused_mul_sub_k(vfloatK(node.bounds[2 * a][c]), p.rdir[a], p.org_rdir[a]);
      vfloatK t1 = fused_mul_sub_k(vfloatK(node.bounds[2 * a + 1][c]), p.rdir[a], p.org_rdir[a]);
      tnear = xsimd::max(tnear, xsimd::min(t0, t1));
      tfar = xsimd::min(tfar, xsimd::max(t0, t1));
    }
  }
}

/// The hits among the packet's rays in `lanes`, from a test's numerators.
PT_ALWAYS_INLINE bool finish_packet(const MtNumerators<vfloatK>& n, uint32_t lanes, const RayPacket& p,
                                    LaneHits<vfloatK>& out) {
  return finish_lanes(n.det, n.t_num, n.u_num, n.v_num, n.inside & lanes_of_mask(lanes), p.tmin, p.tmax, out,
                      [](vboolK m) { return lane_mask(m) != 0; });
}

/// Moller-Trumbore of triangle `lane` of block b against the packet's rays in
/// `lanes` (the blocks' test, mt_numerators and finish_lanes, with the
/// triangle repeated over the rays): the lanes hit within [tmin, tmax).
inline bool triangle_against_packet(const TriangleBlock4& b, int lane, uint32_t lanes, const RayPacket& p,
                                    LaneHits<vfloatK>& out) {
  const TriangleRows<vfloatK> t(b, lane);
  return finish_packet(mt_numerators(t.v0, t.e1, t.e2, p), lanes, p, out);
}

/// Shortens tmax and records the hit in the lanes where triangle `lane` of
/// block b is closer.
inline void intersect_triangle_packet(const TriangleBlock4& b, int lane, uint32_t lanes, RayPacket& p, PacketHits& h) {
  LaneHits<vfloatK> hit;
  if (!triangle_against_packet(b, lane, lanes, p, hit)) return;
  p.tmax = xsimd::select(hit.hit, hit.t, p.tmax);
  h.u = xsimd::select(hit.hit, hit.u, h.u);
  h.v = xsimd::select(hit.hit, hit.v, h.v);
  h.prim = xsimd::select(xsimd::bool_cast(hit.hit), vintK(static_cast<int32_t>(b.prim[lane])), h.prim);
}

/// Lanes of `lanes` whose rays hit triangle `lane` of block b within [tmin, tmax).
inline uint32_t occluders_in_packet(const TriangleBlock4& b, int lane, uint32_t lanes, const RayPacket& p) {
  LaneHits<vfloatK> hit;
  return triangle_against_packet(b, lane, lanes, p, hit) ? lane_mask(hit.hit) : 0;
}

/// occluders_in_packet for rays in `lanes` that all have the direction of the
/// block's `terms`: the same bits, without the direction's share of the test.
inline uint32_t occluders_in_packet(const TriangleBlock4& b, const BlockDirectionTerms& terms, int lane, uint32_t lanes,
                                    const RayPacket& p) {
  const TriangleRows<vfloatK> t(b, lane);
  LaneHits<vfloatK> hit;
  return finish_packet(mt_numerators(t.v0, t.e1, t.e2, terms.of<vfloatK>(lane), p), lanes, p, hit) ? lane_mask(hit.hit)
                                                                                                   : 0;
}

/// Rays a packet must have in a subtree to traverse it as a packet: with
/// fewer, each goes on through the subtree alone (bvh4_traverse.h), where a
/// node test costs one 4-wide test instead of four K-wide ones and a leaf one
/// test per block instead of one per triangle.
inline constexpr int kPacketMinRays = kLanes == 16 ? 4 : kLanes == 8 ? 3 : 2;

/// Closest hits of the rays in `lanes` below `ref`, ray by ray, each under its
/// packet's current tmax; p.tmax and h take the hits found.
inline void intersect_rays_below(const Bvh4& bvh, uint32_t ref, uint32_t lanes, RayPacket& p, PacketHits& h) {
  PacketHitLanes l(p, h);
  bool found = false;
  NoCounters counters;
  for (uint32_t m = lanes; m != 0; m &= m - 1) {
    uint32_t i = std::countr_zero(m);
    Hit hit{l.t[i], l.u[i], l.v[i], static_cast<uint32_t>(l.prim[i])};
    if (!bvh4_intersect_below<TriangleForm::kMollerTrumbore>(bvh, ref, p.ray(i), hit, counters)) continue;
    l.t[i] = hit.t, l.u[i] = hit.u, l.v[i] = hit.v, l.prim[i] = static_cast<int32_t>(hit.prim);
    found = true;
  }
  if (found) l.load_into(p, h);
}

/// The lanes of `lanes` whose rays are blocked below `ref`, ray by ray.
inline uint32_t occluded_rays_below(const Bvh4& bvh, uint32_t ref, uint32_t lanes, const RayPacket& p) {
  uint32_t blocked = 0;
  NoCounters counters;
  for (uint32_t m = lanes; m != 0; m &= m - 1) {
    uint32_t i = std::countr_zero(m);
    if (bvh4_occluded_below<TriangleForm::kMollerTrumbore>(bvh, ref, p.ray(i), counters)) blocked |= 1u << i;
  }
  return blocked;
}

struct PacketEntry {
  uint32_t ref, lanes;
  float dist;
};

/// Tests the four children; pushes all hit children but the nearest (far
/// first), starting to load them, and returns the nearest, or kEmptyRef when
/// none is hit.
template <bool kUniform>
inline uint32_t visit_node(const Bvh4& bvh, const Bvh4Node& node, const RayPacket& p, uint32_t& lanes,
                           PacketEntry*& sp) {
  PacketEntry hit[4];
  int n = 0;
  for (int c = 0; c < 4; ++c) {
    if (!kUniform && node.child[c] == bvh4_ref::kEmptyRef) continue;  // empty slots pass min/max slabs
    vfloatK tnear, tfar;
    child_slabs<kUniform>(node, c, p, tnear, tfar);
    uint32_t m = lanes & lane_mask(tnear <= tfar);
    if (m == 0) continue;
    hit[n++] = {node.child[c], m, reduce_min_k(xsimd::select(lanes_of_mask(m), tnear, vfloatK(INFINITY)))};
  }
  for (int i = 1; i < n; ++i)  // insertion sort, far first
    for (int j = i; j > 0 && hit[j - 1].dist < hit[j].dist; --j) std::swap(hit[j - 1], hit[j]);
  if (n == 0) return bvh4_ref::kEmptyRef;
  for (int i = 0; i + 1 < n; ++i) {
    *sp++ = hit[i];
    prefetch_ref(bvh, hit[i].ref);
  }
  lanes = hit[n - 1].lanes;
  return hit[n - 1].ref;
}

}  // namespace packet_detail

/// Any-hit occlusion (Moller-Trumbore form) of the packet's active rays:
/// returns the lanes blocked within [tmin, tmax). A lane stops traversing once
/// blocked; the packet stops when every lane is.
template <bool kUniform>
inline uint32_t bvh4_occluded_packet(const Bvh4& bvh, const RayPacket& p) {
  using namespace packet_detail;
  uint32_t blocked = 0;
  if (bvh.empty() || p.active == 0) return 0;
  PacketEntry stack[kBvh4StackSize];
  PacketEntry* sp = stack;
  uint32_t cur = bvh.root, lanes = p.active;
  for (;;) {
    while (!bvh4_ref::is_leaf(cur) && std::popcount(lanes) >= kPacketMinRays) {
      cur = visit_node<kUniform>(bvh, bvh.node(cur), p, lanes, sp);
      if (cur == bvh4_ref::kEmptyRef) goto pop;
    }
    if (std::popcount(lanes) < kPacketMinRays) {
      blocked |= occluded_rays_below(bvh, cur, lanes, p);
    } else {
      for (uint32_t i = 0, n = bvh4_ref::leaf_block_count(cur); i < n && lanes; ++i) {
        const TriangleBlock4& b = bvh.leaf_blocks(cur)[i];
        for (int t = 0; t < 4 && lanes; ++t)
          if (b.prim[t] != kInvalidId) {
            uint32_t hit = occluders_in_packet(b, t, lanes, p);
            blocked |= hit;
            lanes &= ~hit;
          }
      }
    }
    if (blocked == p.active) return blocked;
  pop:
    do {  // skip entries whose rays are all blocked already
      if (sp == stack) return blocked;
      --sp;
    } while ((sp->lanes & ~blocked) == 0);
    cur = sp->ref;
    lanes = sp->lanes & ~blocked;
  }
}

/// Closest hits (Moller-Trumbore form) of the packet's active rays; p.tmax
/// ends as each ray's hit distance (or its tmax on a miss).
template <bool kUniform>
inline void bvh4_intersect_packet(const Bvh4& bvh, RayPacket& p, PacketHits& h) {
  using namespace packet_detail;
  if (bvh.empty() || p.active == 0) return;
  PacketEntry stack[kBvh4StackSize];
  PacketEntry* sp = stack;
  uint32_t cur = bvh.root, lanes = p.active;
  for (;;) {
    while (!bvh4_ref::is_leaf(cur) && std::popcount(lanes) >= kPacketMinRays) {
      cur = visit_node<kUniform>(bvh, bvh.node(cur), p, lanes, sp);
      if (cur == bvh4_ref::kEmptyRef) goto pop;
    }
    if (std::popcount(lanes) < kPacketMinRays) {
      intersect_rays_below(bvh, cur, lanes, p, h);
    } else {
      for (uint32_t i = 0, n = bvh4_ref::leaf_block_count(cur); i < n; ++i) {
        const TriangleBlock4& b = bvh.leaf_blocks(cur)[i];
        for (int t = 0; t < 4; ++t)
          if (b.prim[t] != kInvalidId) intersect_triangle_packet(b, t, lanes, p, h);
      }
    }
  pop:
    do {  // skip entries that every ray of theirs has already passed
      if (sp == stack) return;
      --sp;
    } while (sp->dist > reduce_max_k(xsimd::select(lanes_of_mask(sp->lanes), p.tmax, vfloatK(-INFINITY))));
    cur = sp->ref;
    lanes = sp->lanes;
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt
