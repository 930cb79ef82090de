// One ray's walk through the 4-wide BVH, for closest hit and any hit alike
// (kAnyHit), from the three steps every walk of this tree takes:
//   visit_node  the slab test of a node's four children (bvh4_node_test.h),
//               the child to visit next and the others on the stack: nearest
//               first, by entry distance, for closest hit (one hit child is
//               descended without touching the stack); node order for any hit;
//   leaf_hit    the leaf's blocks (bvh4_leaf_test.h);
//   pop         the next entry of the stack, for closest hit skipping those
//               that start beyond the nearest hit.
// A single ray's walk (walk_ray) runs them with its state in locals, which
// the compiler keeps in registers; walks that take turns (bvh4_interleaved.h)
// keep theirs in a RayWalk and take one walk_step each turn.
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

/// An entry of a walk's stack: a deferred subtree, with its entry distance
/// for closest hit.
template <bool kAnyHit>
using Bvh4WalkEntry = std::conditional_t<kAnyHit, uint32_t, Bvh4StackEntry>;

/// One ray's walk below some node, for walks that take turns: its slab and
/// block constants, the nearest hit so far (closest hit) and the top of its
/// stack, which lives apart. The block test is Blocks's (MtBlocks,
/// bvh4_leaf_test.h, for the renderer).
template <bool kAnyHit, class Blocks = MtBlocks>
struct RayWalk {
  using Entry = Bvh4WalkEntry<kAnyHit>;
  NodeRay nr;
  typename Blocks::RayConstants br;
  vfloat4 tmin, vtmax;
  float tmax;
  float t_start;  ///< closest hit: tmax when the walk began; a walk found a hit when it ends below it
  Hit hit;        ///< closest hit: the nearest hit so far
  uint32_t cur;   ///< the node or leaf the next step takes
  Entry* bottom;  ///< the walk's stack, kBvh4StackSize entries
  Entry* sp;

  /// Starts a walk of traceable `ray` from node or leaf `start`, under
  /// `nearest` (closest hit: the nearest hit so far, at most ray.tmax; any
  /// hit: only its t counts, the end of the segment), on `stack`.
  PT_ALWAYS_INLINE void begin(const Ray& ray, uint32_t start, const Hit& nearest, Entry* stack) {
    nr = NodeRay(ray);
    br = typename Blocks::RayConstants(ray);
    tmin = vfloat4(ray.tmin);
    tmax = t_start = nearest.t;
    vtmax = vfloat4(tmax);
    if constexpr (!kAnyHit) hit = nearest;
    cur = start;
    bottom = sp = stack;
  }
  /// Closest hit: whether the walk found a hit nearer than it began with.
  bool found() const { return tmax < t_start; }
};

/// Tests the four children of inner node `ref` for a ray (its slab
/// constants, tmin and nearest hit or segment end in four lanes) and returns
/// the one to visit next, having pushed on `sp` the other children the ray
/// enters; kEmptyRef when it enters none.
template <bool kAnyHit, class Prefetch>
PT_ALWAYS_INLINE uint32_t visit_node(const Bvh4& bvh, uint32_t ref, const NodeRay& nr, const vfloat4& tmin,
                                     const vfloat4& tmax, Bvh4WalkEntry<kAnyHit>*& sp, const Prefetch& pf) {
  const Bvh4Node& node = bvh.node(ref);
  vfloat4 tnear;
  uint32_t mask = intersect_node(node, nr, tmin, tmax, tnear);
  if (mask == 0) return bvh4_ref::kEmptyRef;
  uint32_t next;
  if constexpr (kAnyHit) {  // node order: the last child entered goes on, the others wait
    for (;;) {
      next = node.child[std::countr_zero(mask)];
      mask &= mask - 1;
      if (mask == 0) break;
      *sp++ = next;
      pf.pushed(bvh, next);
    }
  } else {
    alignas(16) float d[4];
    tnear.store_aligned(d);
    const uint32_t i0 = std::countr_zero(mask);
    mask &= mask - 1;
    if (mask == 0) {
      next = node.child[i0];
    } else {
      const uint32_t i1 = std::countr_zero(mask);
      mask &= mask - 1;
      if (mask == 0) {  // two: the farther waits
        const bool first_near = d[i0] <= d[i1];
        const uint32_t far = first_near ? i1 : i0;
        *sp++ = {node.child[far], d[far]};
        pf.pushed(bvh, node.child[far]);
        next = node.child[first_near ? i0 : i1];
      } else {  // three or four: all pushed, sorted far first, the nearest popped
        Bvh4StackEntry* top = sp;
        auto order = [](Bvh4StackEntry& a, Bvh4StackEntry& b) {  // the nearer one ends up later (on top)
          if (a.dist < b.dist) std::swap(a, b);
        };
        *sp++ = {node.child[i0], d[i0]};
        *sp++ = {node.child[i1], d[i1]};
        const uint32_t i2 = std::countr_zero(mask);
        *sp++ = {node.child[i2], d[i2]};
        mask &= mask - 1;
        if (mask == 0) {  // sorting networks
          order(top[0], top[1]), order(top[1], top[2]), order(top[0], top[1]);
        } else {
          const uint32_t i3 = std::countr_zero(mask);
          *sp++ = {node.child[i3], d[i3]};
          order(top[0], top[1]), order(top[2], top[3]), order(top[0], top[2]), order(top[1], top[3]);
          order(top[1], top[2]);
        }
        for (Bvh4StackEntry* e = top; e + 1 < sp; ++e) pf.pushed(bvh, e->ref);
        next = (--sp)->ref;
      }
    }
  }
  pf.next(bvh, next);
  return next;
}

/// Takes the next entry off the stack [bottom, sp) into `cur`; false when the
/// stack is empty. Closest hit passes over entries the ray enters beyond its
/// nearest hit `tmax`.
template <bool kAnyHit>
PT_ALWAYS_INLINE bool pop(Bvh4WalkEntry<kAnyHit>*& sp, const Bvh4WalkEntry<kAnyHit>* bottom, float tmax,
                          uint32_t& cur) {
  if constexpr (kAnyHit) {
    if (sp == bottom) return false;
    cur = *--sp;
  } else {
    do {
      if (sp == bottom) return false;
      --sp;
    } while (sp->dist > tmax);
    cur = sp->ref;
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
    const uint32_t next = visit_node<kAnyHit>(bvh, w.cur, w.nr, w.tmin, w.vtmax, w.sp, pf);
    if (next != bvh4_ref::kEmptyRef) {
      w.cur = next;
      return true;
    }
  } else if (leaf_hit<kAnyHit, Blocks>(bvh.leaf_blocks(w.cur), bvh4_ref::leaf_block_count(w.cur), w.br,
                                       LeafHit{w.tmax, w.vtmax, w.hit}, counters)) {
    blocked = true;
    return false;
  }
  if (!pop<kAnyHit>(w.sp, w.bottom, w.tmax, w.cur)) return false;
  pf.popped(bvh, w.cur);
  return true;
}

/// Walks traceable `ray` below node or leaf `start` (the root, or where a
/// stream leaves the ray alone) under nearest hit `hit` (closest: replaced
/// by a nearer one; any: hit.t is the end of the segment). Returns whether
/// the walk found a nearer hit (closest) or an occluder (any). walk_step's
/// steps, the nodes in an inner loop.
template <bool kAnyHit, class Blocks = MtBlocks, class C>
inline bool walk_ray(const Bvh4& bvh, uint32_t start, const Ray& ray, Hit& hit, C& counters) {
  const NodeRay nr(ray);
  const typename Blocks::RayConstants br(ray);
  const vfloat4 tmin(ray.tmin);
  const float t_start = hit.t;
  float tmax = t_start;
  vfloat4 vtmax(tmax);
  Bvh4WalkEntry<kAnyHit> stack[kBvh4StackSize];
  Bvh4WalkEntry<kAnyHit>* sp = stack;
  const PrefetchAlone pf;
  uint32_t cur = start;
  for (;;) {
    while (!bvh4_ref::is_leaf(cur)) {
      if constexpr (requires { counters.visit(cur); }) counters.visit(cur);
      counters.node();
      cur = visit_node<kAnyHit>(bvh, cur, nr, tmin, vtmax, sp, pf);
      if (cur == bvh4_ref::kEmptyRef) break;
    }
    if (cur != bvh4_ref::kEmptyRef) {
      if constexpr (requires { counters.visit(cur); }) counters.visit(cur);
      if (leaf_hit<kAnyHit, Blocks>(bvh.leaf_blocks(cur), bvh4_ref::leaf_block_count(cur), br,
                                    LeafHit{tmax, vtmax, hit}, counters))
        return true;  // any hit: blocked
    }
    if (!pop<kAnyHit>(sp, stack, tmax, cur)) return tmax < t_start;
  }
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
