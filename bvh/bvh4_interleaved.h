// Single-ray walks of the 4-wide BVH with many in flight per thread: K walks
// take turns, each turn one walk_step of one walk (bvh4_ray_walk.h), and the
// node or leaf a walk needs next starts loading at the end of its step, so
// that it has arrived by the walk's next turn (asynchronous memory access
// chaining). A walk is a ray below some node under a nearest hit so far (the
// rays a stream leaves to go on alone). The steps are a single ray's, so
// each walk finds what it finds alone. Pays where walks wait on memory:
// trees larger than a core's L2 cache, which is where walks prefetch.
#pragma once

#include <cstdint>

#include "bvh4_ray_walk.h"
#include "kernels/simd/cache_size.h"
#include "kernels/simd/isa_namespace.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Whether walks of `bvh` load the node or leaf they take next ahead of
/// time: in a tree larger than one core's L2 cache, whose nodes and leaves
/// come from L3. In a smaller tree they sit in L1 and L2, where prefetches
/// cost more than the latency they hide.
inline bool walks_prefetch(const Bvh4& bvh) { return bvh.bytes() > l2_cache_bytes(); }

/// Runs walks K at a time, taking turns. next(ray, start, nearest, tag)
/// gives the next walk (a traceable ray below node or leaf `start` under
/// `nearest`, as RayWalk::begin takes them; false when there is none);
/// done(tag, hit, found) receives its end (found: a nearer hit, for closest
/// hit; an occluder, for any hit). A walk whose tag settled(tag) says is
/// answered already ends at its next turn, without done.
template <bool kAnyHit, int K, class Next, class Done, class Settled, class C>
inline void walk_interleaved(const Bvh4& bvh, Next&& next, Done&& done, Settled&& settled, C& counters) {
  struct Turn {
    RayWalk<kAnyHit> walk;
    Bvh4WalkEntry<kAnyHit> stack[kBvh4StackSize];
    uint32_t tag;
    bool live = false;
  };
  Turn turns[K];
  const PrefetchTurns prefetch{walks_prefetch(bvh)};
  auto start = [&](Turn& t) {
    Ray r;
    uint32_t from;
    Hit nearest;
    t.live = next(r, from, nearest, t.tag);
    if (!t.live) return false;
    t.walk.begin(r, from, nearest, t.stack);
    prefetch.next(bvh, from);
    return true;
  };
  int live = 0;
  for (Turn& t : turns) live += start(t);
  while (live > 0) {
    for (Turn& t : turns) {
      if (!t.live) continue;
      if (!settled(t.tag)) {
        bool blocked = false;
        if (walk_step(bvh, t.walk, blocked, prefetch, counters)) continue;
        done(t.tag, t.walk.hit, kAnyHit ? blocked : t.walk.found());
      }
      if (!start(t)) --live;
    }
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt
