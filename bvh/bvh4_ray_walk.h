// One ray's walk through the 4-wide BVH, for closest hit and any hit alike
// (kAnyHit), from the three steps every walk of this tree takes:
//   visit_node  the slab test of a node's four children (bvh4_node_test.h),
//               the child to visit next and the others on the stack: nearest
//               first, by entry distance, for closest hit (one hit child is
//               descended without touching the stack); node order for any hit;
//   test_leaf   the leaf's blocks (bvh4_leaf_test.h);
//   pop         the next entry of the stack, for closest hit skipping those
//               that start beyond the nearest hit.
// walk_step takes one of them for one ray: a single ray's walk is a loop of
// steps (walk_ray), and interleaved walks take turns (bvh4_interleaved.h).
// Prefetch says what starts loading ahead: for a walk that runs alone, the
// children left on the stack and the first child of the node about to be
// tested (nodes are stored depth first); for walks that take turns, the whole
// node or leaf each walk needs next, which has arrived by its next turn.
#pragma once

#include <bit>
#include <cstdint>

#include "bvh2.h"
#include "bvh4.h"
#include "bvh4_leaf_test.h"
#include "bvh4_node_test.h"
#include "kernels/math/ray.h"
#include "kernels/simd/isa_namespace.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Entries a traversal stack needs: at most three pushes per level (a
/// single ray pushes the children it does not visit first; a stream pushes
/// up to four and takes one), and the root's entry.
inline constexpr int kBvh4StackSize = 3 * kBvh2MaxDepth + 4;

/// 8 bytes. A closest-hit walk's deferred subtree and the distance at which
/// the ray enters it.
struct Bvh4StackEntry {
  uint32_t ref;
  float dist;
};

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

/// Starts loading a node (both lines) or a whole leaf (every line of its
/// blocks: a walk tests them all unless one blocks it).
PT_ALWAYS_INLINE void prefetch_target(const Bvh4& bvh, uint32_t ref) {
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

/// What a walk that runs alone starts loading: deferred children when they
/// are pushed, the first child of the node it descends to.
struct PrefetchAlone {
  PT_ALWAYS_INLINE void pushed(const Bvh4& bvh, uint32_t ref) const { prefetch_ref(bvh, ref); }
  PT_ALWAYS_INLINE void next(const Bvh4& bvh, uint32_t ref) const { prefetch_first_child(bvh, ref); }
  PT_ALWAYS_INLINE void popped(const Bvh4&, uint32_t) const {}
};

/// What walks that take turns start loading, when `on`: deferred children
/// when they are pushed, and the node or leaf each walk takes next.
struct PrefetchTurns {
  bool on;
  PT_ALWAYS_INLINE void pushed(const Bvh4& bvh, uint32_t ref) const {
    if (on) prefetch_ref(bvh, ref);
  }
  PT_ALWAYS_INLINE void next(const Bvh4& bvh, uint32_t ref) const {
    if (on) prefetch_target(bvh, ref);
  }
  PT_ALWAYS_INLINE void popped(const Bvh4& bvh, uint32_t ref) const { next(bvh, ref); }
};

/// One ray's walk below some node: its slab and block constants, the nearest
/// hit so far (closest hit) and its stack. The block test is Blocks's
/// (MtBlocks, bvh4_leaf_test.h, for the renderer).
template <bool kAnyHit, class Blocks = MtBlocks>
struct RayWalk {
  using Entry = std::conditional_t<kAnyHit, uint32_t, Bvh4StackEntry>;
  NodeRay nr;
  typename Blocks::RayConstants br;
  vfloat4 tmin, vtmax;
  float tmax;
  float t_start;  ///< closest hit: tmax when the walk began; a walk found a hit when it ends below it
  Hit hit;        ///< closest hit: the nearest hit so far
  uint32_t cur;   ///< the node or leaf the next step takes
  Entry* sp;
  Entry stack[kBvh4StackSize];

  /// Starts a walk of traceable `ray` from node or leaf `start`, under
  /// `nearest` (closest hit: the nearest hit so far, at most ray.tmax; any
  /// hit: only its t counts, the end of the segment).
  PT_ALWAYS_INLINE void begin(const Ray& ray, uint32_t start, const Hit& nearest) {
    nr = NodeRay(ray);
    br = typename Blocks::RayConstants(ray);
    tmin = vfloat4(ray.tmin);
    tmax = t_start = nearest.t;
    vtmax = vfloat4(tmax);
    if constexpr (!kAnyHit) hit = nearest;
    cur = start;
    sp = stack;
  }
  /// Closest hit: whether the walk found a hit nearer than it began with.
  bool found() const { return tmax < t_start; }
};

/// Tests the four children of inner node `ref` and returns the one to visit
/// next, having pushed the other children the ray enters; kEmptyRef when it
/// enters none.
template <bool kAnyHit, class Blocks, class Prefetch>
PT_ALWAYS_INLINE uint32_t visit_node(const Bvh4& bvh, uint32_t ref, RayWalk<kAnyHit, Blocks>& w, const Prefetch& pf) {
  const Bvh4Node& node = bvh.node(ref);
  vfloat4 tnear;
  uint32_t mask = intersect_node(node, w.nr, w.tmin, w.vtmax, tnear);
  if (mask == 0) return bvh4_ref::kEmptyRef;
  uint32_t next;
  if constexpr (kAnyHit) {  // node order: the last child entered goes on, the others wait
    for (;;) {
      next = node.child[std::countr_zero(mask)];
      mask &= mask - 1;
      if (mask == 0) break;
      *w.sp++ = next;
      pf.pushed(bvh, next);
    }
  } else {
    alignas(16) float d[4];
    tnear.store_aligned(d);
    auto push = [&](uint32_t c) {
      *w.sp++ = {node.child[c], d[c]};
      pf.pushed(bvh, node.child[c]);
    };
    const uint32_t i0 = std::countr_zero(mask);
    mask &= mask - 1;
    if (mask == 0) {
      next = node.child[i0];
    } else {
      const uint32_t i1 = std::countr_zero(mask);
      mask &= mask - 1;
      if (mask == 0) {  // two: the farther waits
        const bool first_near = d[i0] <= d[i1];
        push(first_near ? i1 : i0);
        next = node.child[first_near ? i0 : i1];
      } else {  // three or four: all pushed, sorted far first, the nearest popped
        Bvh4StackEntry* top = w.sp;
        auto order = [](Bvh4StackEntry& a, Bvh4StackEntry& b) {  // the nearer one ends up later (on top)
          if (a.dist < b.dist) std::swap(a, b);
        };
        *w.sp++ = {node.child[i0], d[i0]};
        *w.sp++ = {node.child[i1], d[i1]};
        const uint32_t i2 = std::countr_zero(mask);
        *w.sp++ = {node.child[i2], d[i2]};
        mask &= mask - 1;
        if (mask == 0) {  // sorting networks
          order(top[0], top[1]), order(top[1], top[2]), order(top[0], top[1]);
        } else {
          const uint32_t i3 = std::countr_zero(mask);
          *w.sp++ = {node.child[i3], d[i3]};
          order(top[0], top[1]), order(top[2], top[3]), order(top[0], top[2]), order(top[1], top[3]);
          order(top[1], top[2]);
        }
        for (Bvh4StackEntry* e = top; e + 1 < w.sp; ++e) pf.pushed(bvh, e->ref);
        next = (--w.sp)->ref;
      }
    }
  }
  pf.next(bvh, next);
  return next;
}

/// Tests the blocks of leaf `ref`: closest hit takes a nearer hit into the
/// walk; any hit returns whether one blocks the ray.
template <bool kAnyHit, class Blocks, class C>
PT_ALWAYS_INLINE bool test_leaf(const Bvh4& bvh, uint32_t ref, RayWalk<kAnyHit, Blocks>& w, C& counters) {
  LeafHit h{w.tmax, w.vtmax, w.hit};
  return leaf_hit<kAnyHit, Blocks>(bvh.leaf_blocks(ref), bvh4_ref::leaf_block_count(ref), w.br, h, counters);
}

/// Takes the next entry off the stack into w.cur; false when the stack is
/// empty. Closest hit passes over entries the ray enters beyond its nearest hit.
template <bool kAnyHit, class Blocks>
PT_ALWAYS_INLINE bool pop(RayWalk<kAnyHit, Blocks>& w) {
  if constexpr (kAnyHit) {
    if (w.sp == w.stack) return false;
    w.cur = *--w.sp;
  } else {
    do {
      if (w.sp == w.stack) return false;
      --w.sp;
    } while (w.sp->dist > w.tmax);
    w.cur = w.sp->ref;
  }
  return true;
}

/// One step of a walk: one inner node, or one leaf and the pop after it.
/// False when the walk is over: the stack ran out, or (any hit) `blocked`
/// was set by an occluder. Counters that have visit(ref) hear of every node
/// and leaf the step takes.
template <bool kAnyHit, class Blocks, class Prefetch, class C>
PT_ALWAYS_INLINE bool walk_step(const Bvh4& bvh, RayWalk<kAnyHit, Blocks>& w, bool& blocked, const Prefetch& pf,
                                C& counters) {
  if constexpr (requires { counters.visit(w.cur); }) counters.visit(w.cur);  // a recorder (bvh4_inspect.h)
  if (!bvh4_ref::is_leaf(w.cur)) {
    counters.node();
    const uint32_t next = visit_node(bvh, w.cur, w, pf);
    if (next != bvh4_ref::kEmptyRef) {
      w.cur = next;
      return true;
    }
  } else if (test_leaf(bvh, w.cur, w, counters)) {
    blocked = true;
    return false;
  }
  if (!pop(w)) return false;
  pf.popped(bvh, w.cur);
  return true;
}

/// Walks traceable `ray` below node or leaf `start` (the root, or where a
/// stream leaves the ray alone) under nearest hit `hit` (closest: replaced
/// by a nearer one; any: hit.t is the end of the segment). Returns whether
/// the walk found a nearer hit (closest) or an occluder (any).
template <bool kAnyHit, class Blocks = MtBlocks, class C>
inline bool walk_ray(const Bvh4& bvh, uint32_t start, const Ray& ray, Hit& hit, C& counters) {
  RayWalk<kAnyHit, Blocks> w;
  w.begin(ray, start, hit);
  bool blocked = false;
  while (walk_step(bvh, w, blocked, PrefetchAlone{}, counters)) {}
  if constexpr (kAnyHit) return blocked;
  hit = w.hit;
  return w.found();
}

/// The closest triangle hit with ray.tmin <= t < ray.tmax. On a hit fills
/// `hit` (prim = input triangle index); on a miss leaves hit = {tmax, 0, 0,
/// kInvalidId}.
template <class Blocks = MtBlocks, class C>
inline bool bvh4_intersect(const Bvh4& bvh, const Ray& ray, Hit& hit, C& counters) {
  hit = Hit{ray.tmax, 0.0f, 0.0f, kInvalidId};
  if (bvh.empty() || !ray_is_traceable(ray)) return false;
  return walk_ray<false, Blocks>(bvh, bvh.root, ray, hit, counters);
}

/// Whether a triangle lies on the ray with ray.tmin <= t < ray.tmax.
template <class Blocks = MtBlocks, class C>
inline bool bvh4_occluded(const Bvh4& bvh, const Ray& ray, C& counters) {
  if (bvh.empty() || !ray_is_traceable(ray)) return false;
  Hit end{ray.tmax, 0.0f, 0.0f, kInvalidId};
  return walk_ray<true, Blocks>(bvh, bvh.root, ray, end, counters);
}

}  // namespace PT_ISA_NS
}  // namespace pt
