// Any hit of an incoherent queue as sets of up to 32 rays of one direction
// octant (Embree's incoherent stream, over the BVH4): the queue's rays are
// binned by the signs of their directions, and each bin of 32 rays walks the
// tree together with one stack of (node, mask of the set's rays that enter
// it). A node's planes are loaded once for all its rays (the octant's near
// and far planes, child_planes); each ray in its mask is tested alone
// against the four children (children_entered, the single ray's node test),
// and its hits are ORed into the children's masks. A leaf takes its rays one
// by one through the walks' leaf test. A ray's node and leaf tests are those
// of its single-ray walk, so it visits the leaves it visits alone and is
// blocked exactly when it is alone. queue_coherence.h says which queues go
// this way.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include "bvh4_leaf_test.h"
#include "bvh4_node_test.h"
#include "bvh4_ray_walk.h"
#include "kernels/math/ray_arrays.h"
#include "kernels/simd/isa_namespace.h"

#if !PT_PER_LEVEL
#error "bvh4_octant_sets.h is for code compiled once per instruction-set level"
#endif

namespace pt {
inline namespace PT_ISA_NS {
namespace octant_detail {

/// Rays of one set: the width of a lane of the children's masks.
inline constexpr uint32_t kOctantSetRays = 32;

/// The slab constants of up to kOctantSetRays rays of one octant, and their
/// indices in the queue. 4,800 bytes (4,740 used; eight of them, one per
/// octant, on the tracing thread's stack).
struct OctantSet {
  alignas(64) float rdir[3][kOctantSetRays];
  alignas(64) float org_rdir[3][kOctantSetRays];
  alignas(64) float tmin[kOctantSetRays];
  alignas(64) float tmax[kOctantSetRays];
  uint32_t id[kOctantSetRays];
  uint32_t count = 0;
  MtBlockRay block_ray[kOctantSetRays];

  /// Appends ray `id` with NodeRay's constants.
  PT_ALWAYS_INLINE void add(const Ray& r, uint32_t ray_id) {
    const uint32_t k = count++;
    for (int a = 0; a < 3; ++a) {
      rdir[a][k] = NodeRay::reciprocal(r.dir[a]);
      org_rdir[a][k] = r.org[a] * rdir[a][k];
    }
    tmin[k] = r.tmin;
    tmax[k] = r.tmax;
    id[k] = ray_id;
    block_ray[k] = MtBlockRay(r);
  }
};
static_assert(sizeof(OctantSet) == 4800);

/// The set's rays blocked in the tree (bit k for ray s.id[k]).
template <class C>
[[gnu::noinline]] inline uint32_t occluded_set(const Bvh4& bvh, const OctantSet& s, uint32_t octant, C& counters) {
  uint32_t near[3], far[3];
  OctantPlanes(octant).offsets(near, far);
  struct Entry {
    uint32_t ref, mask;
  };
  Entry stack[kBvh4StackSize];
  Entry* sp = stack;
  uint32_t blocked = 0;
  *sp++ = {bvh.root, s.count == kOctantSetRays ? ~0u : (1u << s.count) - 1};
  while (sp != stack) {
    --sp;
    uint32_t ref = sp->ref;
    uint32_t mask = sp->mask & ~blocked;
    if (mask == 0) continue;
    while (!bvh4_ref::is_leaf(ref)) {
      const Bvh4Node& node = bvh.node(ref);
      counters.nodes_tested(std::popcount(mask));
      const ChildPlanes planes = child_planes(node, near, far);
      vuint4 entered(0u);  // lane c: the rays that enter child c
      for (uint32_t m = mask; m; m &= m - 1) {
        const uint32_t k = std::countr_zero(m);
        const vfloat4 rdir[3] = {vfloat4(s.rdir[0][k]), vfloat4(s.rdir[1][k]), vfloat4(s.rdir[2][k])};
        const vfloat4 org_rdir[3] = {vfloat4(s.org_rdir[0][k]), vfloat4(s.org_rdir[1][k]), vfloat4(s.org_rdir[2][k])};
        vfloat4 tnear;
        entered =
            entered |
            bit_where(children_entered(planes, rdir, org_rdir, vfloat4(s.tmin[k]), vfloat4(s.tmax[k]), tnear), 1u << k);
      }
      uint32_t child_mask[4];
      lanes_of(entered, child_mask);
      // Node order, the last child entered goes on, the others wait (as a
      // single ray's any-hit walk takes them).
      int next = -1;
      for (int c = 0; c < 4; ++c) {
        if (child_mask[c] == 0) continue;
        if (next >= 0) {
          *sp++ = {node.child[next], child_mask[next]};
          prefetch_ref(bvh, node.child[next]);
        }
        next = c;
      }
      if (next < 0) goto pop;
      ref = node.child[next];
      mask = child_mask[next];
      prefetch_first_child(bvh, ref);
    }
    {
      const TriangleBlock4* blocks = bvh.leaf_blocks(ref);
      const uint32_t n_blocks = bvh4_ref::leaf_block_count(ref);
      for (uint32_t m = mask; m; m &= m - 1) {
        const uint32_t k = std::countr_zero(m);
        float t = s.tmax[k];
        vfloat4 vt(t);
        Hit unused;
        if (leaf_hit<true, MtBlocks>(blocks, n_blocks, s.block_ray[k], {t, vt, unused}, counters)) blocked |= m & -m;
      }
    }
  pop:;
  }
  return blocked;
}

}  // namespace octant_detail

/// Sets blocked[i] = 1 for every ray i of the queue that the tree blocks (as
/// bvh4_occluded), tracing the traceable rays not yet blocked (blocked[i] = 0)
/// as octant sets; writes nothing for the others. Moller-Trumbore leaves.
template <class C>
inline void bvh4_occluded_octant_sets(const Bvh4& bvh, const RayArrays& rays, uint8_t* blocked, C& counters) {
  using namespace octant_detail;
  if (bvh.empty()) return;
  OctantSet sets[8];
  auto flush = [&](uint32_t octant) {
    OctantSet& s = sets[octant];
    if (s.count == 0) return;
    for (uint32_t hit = occluded_set(bvh, s, octant, counters); hit; hit &= hit - 1)
      blocked[s.id[std::countr_zero(hit)]] = 1;
    s.count = 0;
  };
  for (size_t i = 0; i < rays.size; ++i) {
    if (blocked[i]) continue;
    const Ray r = rays.ray(i);
    if (!ray_is_traceable(r)) continue;
    const uint32_t octant = octant_of(r);
    sets[octant].add(r, static_cast<uint32_t>(i));
    if (sets[octant].count == kOctantSetRays) flush(octant);
  }
  for (uint32_t octant = 0; octant < 8; ++octant) flush(octant);
}

}  // namespace PT_ISA_NS
}  // namespace pt
