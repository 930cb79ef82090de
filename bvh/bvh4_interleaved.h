// Single-ray walks of the 4-wide BVH with many in flight per thread: K walk
// states are interleaved, each step advances one walk by one node or one leaf,
// and the node or leaf that walk needs next starts loading at the end of its
// step, so that it has arrived by the walk's next turn (asynchronous memory
// access chaining). A walk is a ray below some node under a nearest hit so
// far (the queue tracer's rays that go on alone); each walks the subtree
// exactly as bvh4_traverse.h walks it (same child order, same pruning), so
// it finds the same hit. Pays where a walk waits on memory: subtrees larger
// than the caches.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "bvh4_traverse.h"
#include "kernels/simd/cache_size.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Whether walks of `bvh` prefetch what they need next: trees larger than the
/// L2 cache of one core (nodes and leaf blocks) have their walks load the next node or leaf ahead (prefetch_target):
/// their nodes and leaves come from L3. Smaller ones sit in L1 and L2, where the prefetches cost more than the latency
/// they hide (docs/bvh_and_benchmarks.md: on Zen 4, with 1 MiB of L2, teapot's captured queues 0.89-0.93x with them and
/// CBbunny's bounce rays, 1.3 MB of tree, 0.93-0.97x of the time without them; on Emerald Rapids, with 2 MiB, CBbunny's
/// and bunny's queues, 1.3 and 1.5 MB, 1.01-1.12x faster without them than with a bound of 1 MiB).
inline bool walks_prefetch(const Bvh4& bvh) { return bvh.bytes() > l2_cache_bytes(); }

/// Starts loading a node (both lines) or a whole leaf (every line of its
/// blocks: a walk tests them all unless one blocks it), if `on`.
PT_ALWAYS_INLINE void prefetch_target(const Bvh4& bvh, uint32_t ref, bool on) {
  if (!on) return;
  if (bvh4_ref::is_leaf(ref)) {
    const uintptr_t first = reinterpret_cast<uintptr_t>(bvh.leaf_blocks(ref));
    const uintptr_t last = first + bvh4_ref::leaf_block_count(ref) * sizeof(TriangleBlock4) - 1;
    for (uintptr_t line = first & ~uintptr_t(63); line <= last; line += 64)
      prefetch_l1(reinterpret_cast<const char*>(line));
  } else {
    const char* p = reinterpret_cast<const char*>(&bvh.node(ref));
    prefetch_l1(p);
    prefetch_l1(p + 64);
  }
}

namespace interleaved_detail {

inline constexpr uint32_t kNoRay = 0xFFFFFFFFu;

template <TriangleForm F>
struct ClosestState {
  NodeRay nr;
  typename BlockTest<F>::RayConstants br;
  vfloat4 tmin, vtmax;
  Hit hit;
  float tmax, t_start;
  uint32_t cur;
  uint32_t ray = kNoRay;
  Bvh4StackEntry* sp;
  Bvh4StackEntry stack[kBvh4StackSize];
};

template <TriangleForm F>
struct AnyState {
  NodeRay nr;
  typename BlockTest<F>::RayConstants br;
  vfloat4 tmin, vtmax;
  uint32_t cur;
  uint32_t ray = kNoRay;
  uint32_t* sp;
  uint32_t stack[kBvh4StackSize];
};

/// Sets state s (closest or any hit) to walk ray r from node or leaf `from`
/// under `tmax`, as walk `tag`, and starts loading `from`.
template <class State>
PT_ALWAYS_INLINE void begin_walk(const Bvh4& bvh, State& s, const Ray& r, uint32_t from, uint32_t tag, float tmax,
                                 bool prefetch) {
  s.nr = NodeRay(r);
  s.br = decltype(s.br)(r);
  s.tmin = vfloat4(r.tmin);
  s.vtmax = vfloat4(tmax);
  s.cur = from;
  s.sp = s.stack;
  s.ray = tag;
  prefetch_target(bvh, from, prefetch);
}

/// One closest-hit step of state s: one inner node, or one leaf and the pop
/// after it. False when the ray's walk is over.
template <TriangleForm F, class C>
PT_ALWAYS_INLINE bool closest_step(const Bvh4& bvh, ClosestState<F>& s, bool prefetch, C& counters) {
  uint32_t cur = s.cur;
  if (!bvh4_ref::is_leaf(cur)) {
    counters.node();
    const Bvh4Node& node = bvh.node(cur);
    vfloat4 tnear;
    uint32_t mask = intersect_node(node, s.nr, s.tmin, s.vtmax, tnear);
    if (mask != 0) {
      alignas(16) float d[4];
      tnear.store_aligned(d);
      uint32_t i0 = std::countr_zero(mask);
      mask &= mask - 1;
      if (mask == 0) {
        cur = node.child[i0];
      } else {
        uint32_t i1 = std::countr_zero(mask);
        mask &= mask - 1;
        if (mask == 0) {
          bool first_near = d[i0] <= d[i1];
          *s.sp++ = first_near ? Bvh4StackEntry{node.child[i1], d[i1]} : Bvh4StackEntry{node.child[i0], d[i0]};
          cur = first_near ? node.child[i0] : node.child[i1];
        } else {
          cur = push_sorted_pop_nearest(bvh, node, i0, i1, mask, d, s.sp);
        }
      }
      s.cur = cur;
      prefetch_target(bvh, cur, prefetch);
      return true;
    }
  } else {
    intersect_leaf_closest<F>(bvh.leaf_blocks(cur), bvh4_ref::leaf_block_count(cur), s.br, s.tmax, s.vtmax, s.hit,
                              counters);
  }
  do {
    if (s.sp == s.stack) return false;
    --s.sp;
  } while (s.sp->dist > s.tmax);
  s.cur = s.sp->ref;
  prefetch_target(bvh, s.cur, prefetch);
  return true;
}

/// One any-hit step of state s. False when the walk is over; `blocked` says
/// whether it ended on an occluder.
template <TriangleForm F, class C>
PT_ALWAYS_INLINE bool any_step(const Bvh4& bvh, AnyState<F>& s, bool& blocked, bool prefetch, C& counters) {
  uint32_t cur = s.cur;
  if (!bvh4_ref::is_leaf(cur)) {
    counters.node();
    const Bvh4Node& node = bvh.node(cur);
    vfloat4 tnear;
    uint32_t mask = intersect_node(node, s.nr, s.tmin, s.vtmax, tnear);
    if (mask != 0) {
      for (;;) {
        cur = node.child[std::countr_zero(mask)];
        mask &= mask - 1;
        if (mask == 0) break;
        *s.sp++ = cur;
        if (prefetch) prefetch_ref(bvh, cur);
      }
      s.cur = cur;
      prefetch_target(bvh, cur, prefetch);
      return true;
    }
  } else if (leaf_occludes<F>(bvh.leaf_blocks(cur), bvh4_ref::leaf_block_count(cur), s.br, s.vtmax, counters)) {
    blocked = true;
    return false;
  }
  if (s.sp == s.stack) return false;
  s.cur = *--s.sp;
  prefetch_target(bvh, s.cur, prefetch);
  return true;
}

}  // namespace interleaved_detail

/// Walks for closest hits, K in flight: next(ray, start, hit, tag) gives the
/// next walk (ray below node `start` under nearest hit `hit`; false when there
/// is none); done(tag, hit, found) receives its end (found: a nearer hit).
template <TriangleForm F, int K, class Next, class Done, class C>
inline void bvh4_intersect_interleaved(const Bvh4& bvh, Next&& next, Done&& done, C& counters) {
  using namespace interleaved_detail;
  ClosestState<F> states[K];
  const bool prefetch = walks_prefetch(bvh);
  auto start = [&](ClosestState<F>& s) {
    Ray r;
    uint32_t from, tag;
    if (!next(r, from, s.hit, tag)) {
      s.ray = kNoRay;
      return false;
    }
    s.tmax = s.t_start = s.hit.t;
    begin_walk(bvh, s, r, from, tag, s.tmax, prefetch);
    return true;
  };
  int live = 0;
  for (ClosestState<F>& s : states) live += start(s);
  while (live > 0) {
    for (ClosestState<F>& s : states) {
      if (s.ray == kNoRay) continue;
      if (closest_step<F>(bvh, s, prefetch, counters)) continue;
      done(s.ray, s.hit, s.tmax < s.t_start);
      if (!start(s)) --live;
    }
  }
}

/// Walks for any hit, K in flight: next(ray, start, tag) gives the next walk
/// (false when there is none); done(tag, blocked) receives its end. A walk
/// whose tag `settled(tag)` says is answered already (its ray blocked in
/// another walk) ends at its next step, without done.
template <TriangleForm F, int K, class Next, class Done, class Settled, class C>
inline void bvh4_occluded_interleaved(const Bvh4& bvh, Next&& next, Done&& done, Settled&& settled, C& counters) {
  using namespace interleaved_detail;
  AnyState<F> states[K];
  const bool prefetch = walks_prefetch(bvh);
  auto start = [&](AnyState<F>& s) {
    Ray r;
    uint32_t from, tag;
    if (!next(r, from, tag)) {
      s.ray = kNoRay;
      return false;
    }
    begin_walk(bvh, s, r, from, tag, r.tmax, prefetch);
    return true;
  };
  int live = 0;
  for (AnyState<F>& s : states) live += start(s);
  while (live > 0) {
    for (AnyState<F>& s : states) {
      if (s.ray == kNoRay) continue;
      bool blocked = false;
      if (!settled(s.ray)) {
        if (any_step<F>(bvh, s, blocked, prefetch, counters)) continue;
        done(s.ray, blocked);
      }
      if (!start(s)) --live;
    }
  }
}

/// The same, every walk run to its end.
template <TriangleForm F, int K, class Next, class Done, class C>
inline void bvh4_occluded_interleaved(const Bvh4& bvh, Next&& next, Done&& done, C& counters) {
  bvh4_occluded_interleaved<F, K>(
      bvh, next, done, [](uint32_t) { return false; }, counters);
}

}  // namespace PT_ISA_NS
}  // namespace pt
