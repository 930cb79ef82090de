// Single-ray traversal of the 4-wide BVH. Closest hit: children visited near
// first (one hit child is descended without touching the stack, two are
// ordered by entry distance, three or four are pushed and sorted), a stack of
// (reference, entry distance) pruned on pop. Any hit: children in node order,
// no distances, first hit ends the walk. On large scenes memory latency
// dominates: deferred children start loading when pushed, and so does the
// first child of the node about to be visited. Templates over the leaf form
// and the counters (NoCounters compiles counting away).
#pragma once

#include <bit>
#include <cmath>

#include "kernels/simd/isa_namespace.h"
#include "bvh2.h"
#include "bvh4.h"
#include "bvh4_node_test.h"
#include "kernels/math/ray.h"
#include "traversal_counters.h"
#include "triangle4_intersect.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Entries a traversal stack needs: at most three pushes per level (a
/// single ray pushes the children it does not visit first; the queue tracer
/// pushes up to four and takes one), and the root's entry.
inline constexpr int kBvh4StackSize = 3 * kBvh2MaxDepth + 4;

/// The block test and its per-ray constants for each leaf form.
template <TriangleForm F>
struct BlockTest;
template <>
struct BlockTest<TriangleForm::kMollerTrumbore> {
  using RayConstants = MtBlockRay;
  PT_ALWAYS_INLINE static uint32_t test(const TriangleBlock4& b, const RayConstants& r, const vfloat4& tmax,
                                        BlockHits& h) {
    return intersect_block_mt(b, r, tmax, h);
  }
};
template <>
struct BlockTest<TriangleForm::kWatertight> {
  using RayConstants = WatertightBlockRay;
  PT_ALWAYS_INLINE static uint32_t test(const TriangleBlock4& b, const RayConstants& r, const vfloat4& tmax,
                                        BlockHits& h) {
    return intersect_block_watertight(b, r, tmax, h);
  }
};

template <class C>
inline void count_block(C& c, const TriangleBlock4& b) {
  if constexpr (C::kEnabled) {
    uint32_t valid = 0;
    for (uint32_t p : b.prim) valid += p != kInvalidId;
    c.primitives_tested(valid);
  }
}

/// Starts loading what a deferred reference points to: a node and the head of
/// the next one, or a leaf's first block.
PT_ALWAYS_INLINE void prefetch_ref(const Bvh4& bvh, uint32_t ref) {
  const char* p = bvh4_ref::is_leaf(ref) ? reinterpret_cast<const char*>(bvh.leaf_blocks(ref))
                                         : reinterpret_cast<const char*>(&bvh.node(ref));
  prefetch_l1(p);
  prefetch_l1(p + 64);
  prefetch_l1(p + 128);
}

/// Starts loading the node after inner node `ref` in memory: its first inner
/// child, as nodes are stored depth first.
PT_ALWAYS_INLINE void prefetch_first_child(const Bvh4& bvh, uint32_t ref) {
  if (bvh4_ref::is_leaf(ref)) return;
  const char* p = reinterpret_cast<const char*>(&bvh.node(ref)) + sizeof(Bvh4Node);
  prefetch_l1(p);
  prefetch_l1(p + 64);
}

struct Bvh4StackEntry {
  uint32_t ref;
  float dist;
};

/// Orders two entries so that the nearer one ends up later (on top).
inline void order_far_first(Bvh4StackEntry& a, Bvh4StackEntry& b) {
  if (a.dist < b.dist) std::swap(a, b);
}

/// Three or four children hit (i0, i1 and those left in `mask`): pushes them
/// all, sorts the pushed entries far first, starts loading them, and pops the
/// nearest, which it returns.
inline uint32_t push_sorted_pop_nearest(const Bvh4& bvh, const Bvh4Node& node, uint32_t i0, uint32_t i1, uint32_t mask,
                                        const float d[4], Bvh4StackEntry*& sp) {
  Bvh4StackEntry* top = sp;
  *sp++ = {node.child[i0], d[i0]};
  *sp++ = {node.child[i1], d[i1]};
  uint32_t i2 = std::countr_zero(mask);
  *sp++ = {node.child[i2], d[i2]};
  mask &= mask - 1;
  if (mask == 0) {  // sorting networks: the nearest entry ends on top
    order_far_first(top[0], top[1]);
    order_far_first(top[1], top[2]);
    order_far_first(top[0], top[1]);
  } else {
    uint32_t i3 = std::countr_zero(mask);
    *sp++ = {node.child[i3], d[i3]};
    order_far_first(top[0], top[1]);
    order_far_first(top[2], top[3]);
    order_far_first(top[0], top[2]);
    order_far_first(top[1], top[3]);
    order_far_first(top[1], top[2]);
  }
  for (Bvh4StackEntry* e = top; e + 1 < sp; ++e) prefetch_ref(bvh, e->ref);
  uint32_t nearest = (--sp)->ref;
  prefetch_first_child(bvh, nearest);
  return nearest;
}

/// Tests every block of a leaf; a hit nearer than tmax shortens tmax and fills
/// `hit`. With AVX2 and Moller-Trumbore leaves, blocks go two at a time in
/// eight lanes, with the result of testing them one after the other: when
/// both blocks of a pair have hits, the second is tested again under the
/// first one's tmax (rare: a pair's two blocks are hit at nearly one t).
template <TriangleForm F, class C>
inline void intersect_leaf_closest(const TriangleBlock4* blocks, uint32_t count,
                                   const typename BlockTest<F>::RayConstants& br, float& tmax, vfloat4& vtmax, Hit& hit,
                                   C& counters) {
  auto take = [&](const TriangleBlock4& b, const BlockHits& h) {
    tmax = reduce_min(h.t);
    vtmax = vfloat4(tmax);
    uint32_t lane = std::countr_zero(movemask(h.t == vtmax));
    alignas(16) float u[4], v[4];
    h.u.store_aligned(u);
    h.v.store_aligned(v);
    hit = {tmax, u[lane], v[lane], b.prim[lane]};
  };
  uint32_t i = 0;
#if XSIMD_WITH_AVX2
  if constexpr (F == TriangleForm::kMollerTrumbore) {
    if (count >= 2) {
      const MtPairRay wide = widen(br);
      for (; i + 2 <= count; i += 2) {
        count_block(counters, blocks[i]);
        count_block(counters, blocks[i + 1]);
        LaneHits<vfloat8> pair;
        uint32_t m = intersect_block_pair_mt(blocks + i, wide, vfloat8(tmax), pair);
        if (m & 15u) take(blocks[i], block_of_pair(pair, 0));
        if (m >> 4 == 0) continue;
        BlockHits h = block_of_pair(pair, 1);
        if ((m & 15u) == 0 || BlockTest<F>::test(blocks[i + 1], br, vtmax, h) != 0) take(blocks[i + 1], h);
      }
    }
  }
#endif
  for (; i < count; ++i) {
    count_block(counters, blocks[i]);
    BlockHits h;
    if (BlockTest<F>::test(blocks[i], br, vtmax, h) != 0) take(blocks[i], h);
  }
}

/// Whether any triangle of a leaf lies on the ray within [tmin, tmax); blocks
/// go two at a time as in intersect_leaf_closest.
template <TriangleForm F, class C>
inline bool leaf_occludes(const TriangleBlock4* blocks, uint32_t count, const typename BlockTest<F>::RayConstants& br,
                          const vfloat4& tmax, C& counters) {
  uint32_t i = 0;
#if XSIMD_WITH_AVX2
  if constexpr (F == TriangleForm::kMollerTrumbore) {
    if (count >= 2) {
      const MtPairRay wide = widen(br);
      const vfloat8 wide_tmax = repeat_halves(tmax);
      for (; i + 2 <= count; i += 2) {
        count_block(counters, blocks[i]);
        count_block(counters, blocks[i + 1]);
        LaneHits<vfloat8> pair;
        if (intersect_block_pair_mt(blocks + i, wide, wide_tmax, pair) != 0) return true;
      }
    }
  }
#endif
  for (; i < count; ++i) {
    count_block(counters, blocks[i]);
    BlockHits h;
    if (BlockTest<F>::test(blocks[i], br, tmax, h) != 0) return true;
  }
  return false;
}

/// The closest hit below reference `start` (the root, or a subtree a packet
/// hands over) of a traceable ray with ray.tmin <= t < hit.t: replaces `hit`
/// when it finds one and says whether it did.
template <TriangleForm F, class C>
inline bool bvh4_intersect_below(const Bvh4& bvh, uint32_t start, const Ray& ray, Hit& hit, C& counters) {
  const NodeRay nr(ray);
  const typename BlockTest<F>::RayConstants br(ray);
  const vfloat4 tmin(ray.tmin);
  const float t_start = hit.t;
  float tmax = t_start;
  vfloat4 vtmax(tmax);
  Bvh4StackEntry stack[kBvh4StackSize];
  Bvh4StackEntry* sp = stack;
  uint32_t cur = start;
  for (;;) {
    while (!bvh4_ref::is_leaf(cur)) {
      counters.node();
      const Bvh4Node& node = bvh.node(cur);
      vfloat4 tnear;
      uint32_t mask = intersect_node(node, nr, tmin, vtmax, tnear);
      if (mask == 0) goto pop;
      alignas(16) float d[4];
      tnear.store_aligned(d);
      uint32_t i0 = std::countr_zero(mask);
      mask &= mask - 1;
      if (mask == 0) {
        cur = node.child[i0];
        prefetch_first_child(bvh, cur);
        continue;
      }
      uint32_t i1 = std::countr_zero(mask);
      mask &= mask - 1;
      if (mask == 0) {
        bool first_near = d[i0] <= d[i1];
        *sp++ = first_near ? Bvh4StackEntry{node.child[i1], d[i1]} : Bvh4StackEntry{node.child[i0], d[i0]};
        prefetch_ref(bvh, sp[-1].ref);
        cur = first_near ? node.child[i0] : node.child[i1];
        prefetch_first_child(bvh, cur);
        continue;
      }
      cur = push_sorted_pop_nearest(bvh, node, i0, i1, mask, d, sp);
    }
    intersect_leaf_closest<F>(bvh.leaf_blocks(cur), bvh4_ref::leaf_block_count(cur), br, tmax, vtmax, hit, counters);
  pop:
    do {
      if (sp == stack) return tmax < t_start;  // every hit taken is strictly nearer
      --sp;
    } while (sp->dist > tmax);
    cur = sp->ref;
  }
}

/// Closest triangle hit with ray.tmin <= t < ray.tmax. On a hit fills `hit`
/// (prim = input triangle index); on a miss leaves hit = {tmax, 0, 0, kInvalidId}.
template <TriangleForm F, class C>
inline bool bvh4_intersect(const Bvh4& bvh, const Ray& ray, Hit& hit, C& counters) {
  hit = Hit{ray.tmax, 0.0f, 0.0f, kInvalidId};
  if (bvh.empty() || !ray_is_traceable(ray)) return false;
  return bvh4_intersect_below<F>(bvh, bvh.root, ray, hit, counters);
}

/// Whether any triangle below reference `start` lies on a traceable ray with
/// ray.tmin <= t < ray.tmax.
template <TriangleForm F, class C>
inline bool bvh4_occluded_below(const Bvh4& bvh, uint32_t start, const Ray& ray, C& counters) {
  const NodeRay nr(ray);
  const typename BlockTest<F>::RayConstants br(ray);
  const vfloat4 tmin(ray.tmin), tmax(ray.tmax);
  uint32_t stack[kBvh4StackSize];
  uint32_t* sp = stack;
  uint32_t cur = start;
  for (;;) {
    while (!bvh4_ref::is_leaf(cur)) {
      counters.node();
      const Bvh4Node& node = bvh.node(cur);
      vfloat4 tnear;
      uint32_t mask = intersect_node(node, nr, tmin, tmax, tnear);
      if (mask == 0) goto pop;
      for (;;) {  // the last child hit continues, the others wait on the stack
        cur = node.child[std::countr_zero(mask)];
        mask &= mask - 1;
        if (mask == 0) break;
        *sp++ = cur;
        prefetch_ref(bvh, cur);
      }
      prefetch_first_child(bvh, cur);
    }
    if (leaf_occludes<F>(bvh.leaf_blocks(cur), bvh4_ref::leaf_block_count(cur), br, tmax, counters)) return true;
  pop:
    if (sp == stack) return false;
    cur = *--sp;
  }
}

/// Whether any triangle lies on the ray with ray.tmin <= t < ray.tmax.
template <TriangleForm F, class C>
inline bool bvh4_occluded(const Bvh4& bvh, const Ray& ray, C& counters) {
  if (bvh.empty() || !ray_is_traceable(ray)) return false;
  return bvh4_occluded_below<F>(bvh, bvh.root, ray, counters);
}

}  // namespace PT_ISA_NS
}  // namespace pt
