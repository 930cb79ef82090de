// The leaf test of the 4-wide BVH, for closest hit and any hit alike
// (kAnyHit), in its two shapes:
//   leaf_hit    one ray against a leaf's blocks, four triangles per test
//               (Moller-Trumbore blocks two at a time in eight lanes where
//               the level has them, with the result of testing them one after
//               the other), for walks of single rays (bvh4_ray_walk.h);
//   leaf_lanes  K rays against a leaf's triangles, one triangle per test
//               repeated over the rays, for sets and streams of rays.
// Both take a leaf's triangles in block order and each block's four under
// the nearest t from before the block, as the block test does, and the
// nearest of them on a tie the first: every ray gets the same hit, bit for
// bit, whichever shape tests it.
#pragma once

#include <bit>
#include <cstdint>

#include "bvh4.h"
#include "kernels/math/ray.h"
#include "kernels/simd/isa_namespace.h"
#include "kernels/simd/simd.h"
#include "triangle4_intersect.h"

namespace pt {
inline namespace PT_ISA_NS {

/// The Moller-Trumbore block test, the leaves' form. A walk takes its leaf
/// test from such a type: the per-ray constants, the test of one block, and
/// whether blocks go two at a time (bench/watertight_blocks.h has another).
struct MtBlocks {
  using RayConstants = MtBlockRay;
  static constexpr bool kPairs = true;  ///< two blocks per test where the level has eight lanes
  PT_ALWAYS_INLINE static uint32_t test(const TriangleBlock4& b, const RayConstants& r, const vfloat4& tmax,
                                        BlockHits& h) {
    return intersect_block_mt(b, r, tmax, h);
  }
};

template <class C>
PT_ALWAYS_INLINE void count_block(C& c, const TriangleBlock4& b) {
  if constexpr (C::kEnabled) {
    uint32_t valid = 0;
    for (uint32_t p : b.prim) valid += p != kInvalidId;
    c.primitives_tested(valid);
  }
}

/// A single ray's nearest hit so far, which leaf_hit shortens: t (tmax) as a
/// float and in four lanes, and the hit (closest hit only).
struct LeafHit {
  float& tmax;
  vfloat4& vtmax;
  Hit& hit;
};

/// One ray against the blocks of a leaf within [tmin, tmax). Closest hit: a
/// nearer hit shortens h and fills h.hit; returns false. Any hit: whether a
/// triangle blocks the ray.
template <bool kAnyHit, class Blocks, class C>
PT_ALWAYS_INLINE bool leaf_hit(const TriangleBlock4* blocks, uint32_t count, const typename Blocks::RayConstants& br,
                               const LeafHit& h, C& counters) {
  auto take = [&](const TriangleBlock4& b, const BlockHits& bh) {
    h.tmax = reduce_min(bh.t);
    h.vtmax = vfloat4(h.tmax);
    const uint32_t lane = std::countr_zero(movemask(bh.t == h.vtmax));
    alignas(16) float u[4], v[4];
    bh.u.store_aligned(u);
    bh.v.store_aligned(v);
    h.hit = {h.tmax, u[lane], v[lane], b.prim[lane]};
  };
  uint32_t i = 0;
#if XSIMD_WITH_AVX2
  if constexpr (Blocks::kPairs) {
    if (count >= 2) {
      const MtPairRay wide = widen(br);
      for (; i + 2 <= count; i += 2) {
        count_block(counters, blocks[i]);
        count_block(counters, blocks[i + 1]);
        LaneHits<vfloat8> pair;
        const uint32_t m = intersect_block_pair_mt(blocks + i, wide, vfloat8(h.tmax), pair);
        if constexpr (kAnyHit) {
          if (m != 0) return true;
        } else {
          // When both blocks have hits, the second is tested again under the
          // first one's t (rare: a pair's two blocks hit at nearly one t).
          if (m & 15u) take(blocks[i], block_of_pair(pair, 0));
          if (m >> 4 == 0) continue;
          BlockHits second = block_of_pair(pair, 1);
          if ((m & 15u) == 0 || Blocks::test(blocks[i + 1], br, h.vtmax, second) != 0) take(blocks[i + 1], second);
        }
      }
    }
  }
#endif
  for (; i < count; ++i) {
    count_block(counters, blocks[i]);
    BlockHits bh;
    if (Blocks::test(blocks[i], br, h.vtmax, bh) == 0) continue;
    if constexpr (kAnyHit) return true;
    take(blocks[i], bh);
  }
  return false;
}

#if PT_PER_LEVEL
/// K rays' Moller-Trumbore constants: origins, directions and tmin.
struct TriangleLanes {
  vfloatK org[3], dir[3], tmin;
};

/// K rays' hits so far, which leaf_lanes updates: the nearest t (closest
/// hit: with u, v and the primitive as int32 bits, -1 = kInvalidId) or the
/// end of each ray's segment (any hit).
struct LaneHitState {
  vfloatK t, u, v;
  vintK prim;
};

/// K rays (`lanes` of r) against every triangle of a leaf, in block order.
/// Closest hit: each block's four triangles under the t from before the
/// block, the nearest of them taken (the first on a tie) where nearer than
/// s.t; returns the lanes whose hit changed. Any hit: under s.t, until every
/// lane is blocked; returns the lanes blocked. `terms`, when not null, holds
/// each block's direction terms for the one direction of all the rays
/// (BlockDirectionTerms): the same bits without the direction's share.
template <bool kAnyHit, class C>
PT_ALWAYS_INLINE uint32_t leaf_lanes(const TriangleBlock4* blocks, uint32_t n_blocks, const TriangleLanes& r,
                                     uint32_t lanes, LaneHitState& s, const BlockDirectionTerms* terms, C& counters) {
  uint32_t changed = 0;
  for (uint32_t b = 0; b < n_blocks; ++b) {
    const vfloatK t_block = s.t;
    for (int l = 0; l < 4; ++l) {
      if (blocks[b].prim[l] == kInvalidId) continue;
      const uint32_t open = kAnyHit ? lanes & ~changed : lanes;
      if constexpr (C::kEnabled) counters.primitives_tested(std::popcount(open));
      const TriangleRows<vfloatK> tri(blocks[b], l);
      const MtNumerators<vfloatK> n = terms ? mt_numerators(tri.v0, tri.e1, tri.e2, terms[b].of<vfloatK>(l), r)
                                            : mt_numerators(tri.v0, tri.e1, tri.e2, r);
      LaneHits<vfloatK> h;
      if (!finish_lanes(n.det, n.t_num, n.u_num, n.v_num, n.inside & lanes_of_mask(open), r.tmin, t_block, h,
                        [](vboolK m) { return lane_mask(m) != 0; }))
        continue;
      if constexpr (kAnyHit) {
        changed |= lane_mask(h.hit);
        if (changed == lanes) return changed;
      } else {
        const vboolK nearer = h.hit & (h.t < s.t);
        s.t = xsimd::select(nearer, h.t, s.t);
        s.u = xsimd::select(nearer, h.u, s.u);
        s.v = xsimd::select(nearer, h.v, s.v);
        s.prim = xsimd::select(xsimd::bool_cast(nearer), vintK(static_cast<int32_t>(blocks[b].prim[l])), s.prim);
        changed |= lane_mask(nearer);
      }
    }
  }
  return changed;
}
#endif

}  // namespace PT_ISA_NS
}  // namespace pt
