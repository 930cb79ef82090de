// A whole queue of rays through the 4-wide BVH at once (dynamic ray stream
// traversal, after Barringer and Akenine-Moller 2014): the rays that reach a
// node form a list; each child box is tested against all of them, K rays per
// SIMD instruction, and the rays that enter it are compacted into the child's
// list, each with the constants of its slab test, so that the next level
// loads them as vectors. A leaf that many rays reach tests each of its
// triangles against K rays at a time; a chunk of K/2 rays or fewer takes it
// ray by ray, through the walks' own leaf tests (one or two blocks per test).
// The rays of a list that has thinned
// below kStreamMinRays go on alone from that node: their walks are collected
// and run kWalksInFlight at a time, interleaved (bvh4_interleaved.h), each
// under its ray's nearest hit at the time it starts. For any hit, a part of
// at most 64 rays writes no lists: its rays keep their lanes and a node on
// the stack carries a mask of the rays that enter it (occluded_masked_part).
// An any-hit queue whose rays all have one direction (a directional light's
// shadow rays) computes each leaf triangle's direction terms once per visit
// for all its rays, and tests nodes with the direction's slab constants and
// near and far planes, its lists carrying no reciprocal directions
// (QueueDirection). Every ray gets the hit it gets alone,
// bit for bit: the triangle test does
// the same operations per lane as the block test, and a leaf's triangles are
// taken in the block test's order, each block's four under the nearest t from
// before it, as the block test takes them. Only which of two different
// triangles at exactly the same t is reported may differ, as with packets.
// Moller-Trumbore leaves only.
#pragma once

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "bvh4_interleaved.h"
#include "bvh4_traverse.h"
#include "kernels/math/ray_arrays.h"
#include "queue_prefetch.h"
#include "queue_scratch.h"

#if !PT_PER_LEVEL
#error "bvh4_stream.h is for code compiled once per instruction-set level"
#endif

namespace pt {
inline namespace PT_ISA_NS {
namespace stream_detail {

/// Rays a list needs for its node or leaf to be tested across rays.
inline constexpr uint32_t kStreamMinRays = kLanes == 16 ? 8 : kLanes == 8 ? 4 : 2;

/// Rays of a leaf's chunk of K (its rays still to be answered: any hit skips
/// the blocked ones) at or below which each ray takes the leaf alone, through
/// a walk's leaf test (four or eight triangles per test), instead of every
/// triangle being tested across the chunk's K lanes, most of them idle.
inline constexpr uint32_t kLeafRaysAlone = kLanes / 2;

/// The fields of a list, each an array of `room` 32-bit words: the ray's index
/// in the queue, then the constants of its slab test (NodeRay's) and its tmin.
/// A queue of one direction leaves the kRdir fields' words unwritten (their
/// room stays reserved, so that every list has one layout).
enum ListField : uint32_t { kId, kRdirX, kRdirY, kRdirZ, kOrgRdirX, kOrgRdirY, kOrgRdirZ, kTminField, kListFields };

/// Room for a list of n rays written K at a time: n rounded up to whole
/// batches of the widest lane count, plus one batch.
constexpr uint32_t list_room(size_t n) {
  return static_cast<uint32_t>((n + 2 * kMaxLanes - 1) / kMaxLanes * kMaxLanes);
}

/// A node or leaf and the list of the rays that enter it, at words
/// [offset, offset + fields * room) of the arena (kListFields fields, or one
/// fewer when the lists carry no tmin). The lists of a node's
/// children are allocated together and end at block_end, where the arena's
/// free space starts again once this entry is taken.
struct ListEntry {
  uint32_t ref, offset, count, room, block_end;
};

/// The lists, one after the other (QueueScratch::ids).
class ListArena {
 public:
  explicit ListArena(QueueScratch& s) : words_(s.ids) {}
  /// Room for `n` more words past `top`.
  void reserve(size_t top, size_t n) {
    if (words_.size() < top + n) words_.resize(std::max(2 * words_.size(), top + n));
  }
  float* field(const ListEntry& e, ListField f) { return field(e.offset, e.room, f); }
  float* field(uint32_t offset, uint32_t room, ListField f) {
    return reinterpret_cast<float*>(words_.data() + offset + size_t(f) * room);
  }
  const uint32_t* ids(const ListEntry& e) const { return words_.data() + e.offset; }

 private:
  LineAlignedArray<uint32_t>& words_;
};

/// K indices of a list; lanes outside `valid` (past the list's end) read index
/// 0, so that gathers stay in bounds.
PT_ALWAYS_INLINE vintK load_ids(const float* p, uint32_t valid) {
  const vintK id = xsimd::bitwise_cast<vintK>(vfloatK::load_unaligned(p));
  return valid == lanes_below(kLanes) ? id : xsimd::select(as_int_mask(lanes_of_mask(valid)), id, vintK(0));
}

/// K indices of a list (load_ids), and whether they run on without a gap:
/// lists keep queue order, and a render's queues put the rays of neighbouring
/// points together, so many chunks of a list are runs of the queue, whose
/// fields then load as vectors instead of being gathered (a gather of K
/// lanes costs several times a load at AVX2).
struct ListedIds {
  vintK id;
  int32_t first;  ///< the first lane's index
  bool run;       ///< all K lanes valid, indices first, first + 1, ...
};
PT_ALWAYS_INLINE ListedIds listed_ids(const float* p, uint32_t valid) {
  ListedIds l{load_ids(p, valid), reinterpret_cast<const int32_t*>(p)[0], false};  // the arena's words
  l.run = valid == lanes_below(kLanes) && lane_mask(as_float_mask(l.id == vintK(l.first) + lane_index())) == valid;
  return l;
}

/// a[id] of the listed rays' lanes.
PT_ALWAYS_INLINE vfloatK listed_lanes(const float* a, const ListedIds& l) {
  return l.run ? vfloatK::load_unaligned(a + l.first) : gather(a, l.id);
}

/// Whether some ray of the part has tmin != 0 (so lists carry tmin).
inline bool has_tmin(const RayArrays& rays) {
  if (!rays.tmin) return false;
  for (size_t i = 0; i < rays.size; ++i)
    if (rays.tmin[i] != 0.0f) return true;
  return false;
}

/// Lane l of K values of a part's array from index i: a[i + l], or the last
/// ray's value for lanes past the part's end.
PT_ALWAYS_INLINE vfloatK load_part_lanes(const float* a, size_t i, size_t size) {
  if (i + kLanes <= size) return vfloatK::load_unaligned(a + i);
  alignas(64) float tail[kLanes];
  for (size_t l = 0; l < kLanes; ++l) tail[l] = a[std::min(i + l, size - 1)];
  return vfloatK::load_aligned(tail);
}

/// K rays of a part from ray i: their slab constants as NodeRay computes
/// them, their tmin, and which of them are traceable (lanes past the end
/// repeat the last ray; the caller masks them off).
struct SlabLanes {
  vfloatK rdir[3], org_rdir[3], tmin;
  vboolK traceable;
};
PT_ALWAYS_INLINE SlabLanes slab_lanes(const RayArrays& rays, size_t i) {
  auto load = [&](const float* a) { return load_part_lanes(a, i, rays.size); };
  SlabLanes r;
  vfloatK org[3], dir[3];
  for (int a = 0; a < 3; ++a) org[a] = load(rays.org[a]), dir[a] = load(rays.dir[a]);
  r.tmin = rays.tmin ? load(rays.tmin) : vfloatK(0.0f);
  r.traceable = r.tmin < load(rays.tmax);  // false for NaN
  for (int a = 0; a < 3; ++a) r.traceable = r.traceable & xsimd::isfinite(org[a]) & xsimd::isfinite(dir[a]);
  const vfloatK min_dir(NodeRay::kMinDir);
  for (int a = 0; a < 3; ++a) {
    const vfloatK safe = xsimd::select(xsimd::abs(dir[a]) < min_dir, xsimd::copysign(min_dir, dir[a]), dir[a]);
    r.rdir[a] = vfloatK(1.0f) / safe;
    r.org_rdir[a] = org[a] * r.rdir[a];
  }
  return r;
}

/// Whether every ray of a queue has one direction, bit for bit (a
/// directional light's shadow rays), and which: then leaves compute each
/// triangle's direction terms once per visit for all its rays, and take the
/// direction as a broadcast instead of each ray's; node tests take the
/// direction's slab constants as broadcasts and each axis's near and far
/// plane (as NodeRay does), and lists carry no reciprocal directions.
struct QueueDirection {
  bool shared = false;
  float dir[3] = {0.0f, 0.0f, 0.0f};
  float rdir[3] = {0.0f, 0.0f, 0.0f};                ///< NodeRay's reciprocal direction
  uint32_t near[3] = {0, 2, 4}, far[3] = {1, 3, 5};  ///< the bounds rows of each axis's near and far planes
  /// The direction repeated over the lanes of V.
  template <class V>
  PT_ALWAYS_INLINE void lanes(V (&d)[3]) const {
    for (int a = 0; a < 3; ++a) d[a] = V(dir[a]);
  }
};
inline QueueDirection direction_of(const RayArrays& rays) {
  QueueDirection q;
  if (rays.size == 0) return q;
  for (size_t i = 0; i < rays.size; i += kLanes) {
    const vboolK same = same_bits(load_part_lanes(rays.dir[0], i, rays.size), rays.dir[0][0]) &
                        same_bits(load_part_lanes(rays.dir[1], i, rays.size), rays.dir[1][0]) &
                        same_bits(load_part_lanes(rays.dir[2], i, rays.size), rays.dir[2][0]);
    if (lane_mask(same) != lanes_below(kLanes)) return q;
  }
  q.shared = true;
  for (int a = 0; a < 3; ++a) {
    const float d = rays.dir[a][0];
    q.dir[a] = d;
    const float safe = std::fabs(d) < NodeRay::kMinDir ? std::copysign(NodeRay::kMinDir, d) : d;
    const float inv = 1.0f / safe;  // slab_lanes' and NodeRay's
    q.rdir[a] = inv;
    q.near[a] = inv >= 0.0f ? 2 * a : 2 * a + 1;
    q.far[a] = inv >= 0.0f ? 2 * a + 1 : 2 * a;
  }
  return q;
}

/// How far ahead of the chunk it lists root_list starts loading the part's
/// arrays: sixteen chunks of 16 rays, which cover the L3 latency. A render's
/// queue is written by shading well before it is traced and no longer sits
/// in the 1 MiB L2 (a CBbunny wave's first-hit shadow queue is 1.2 MB), and
/// the hardware's stream prefetchers fall behind eight arrays read at once.
inline constexpr size_t kRootPrefetchRays = 256;

/// Lists the traceable rays of the part, in queue order, with their slab
/// constants (computed as NodeRay computes them; kShared, a queue of one
/// direction: without the reciprocal directions) and, with kTmin, their tmin;
/// returns the root's entry.
template <bool kTmin, bool kShared = false>
inline ListEntry root_list(const Bvh4& bvh, const RayArrays& rays, ListArena& arena) {
  constexpr uint32_t kFields = kTmin ? kListFields : kListFields - 1;
  const uint32_t room = list_room(rays.size);
  arena.reserve(0, size_t(kFields) * room);
  float* out[kListFields];
  for (uint32_t f = 0; f < kFields; ++f) out[f] = arena.field(0, room, ListField(f));
  uint32_t count = 0;
  for (size_t i = 0; i < rays.size; i += kLanes) {
    if (i % 16 == 0) prefetch_queue_rays(rays, i + kRootPrefetchRays);
    const uint32_t valid = lanes_below(std::min(kLanes, rays.size - i));
    const SlabLanes r = slab_lanes(rays, i);
    const uint32_t m = lane_mask(r.traceable) & valid;
    if (m == 0) continue;
    store_compressed(reinterpret_cast<int32_t*>(out[kId] + count), m, vintK(static_cast<int32_t>(i)) + lane_index());
    for (int a = 0; a < 3; ++a) {
      if constexpr (!kShared) store_compressed(out[kRdirX + a] + count, m, r.rdir[a]);
      store_compressed(out[kOrgRdirX + a] + count, m, r.org_rdir[a]);
    }
    if constexpr (kTmin) store_compressed(out[kTminField] + count, m, r.tmin);
    count += std::popcount(m);
  }
  return {bvh.root, 0, count, room, kFields * room};
}

/// Slab-test constants of K listed rays.
struct NodeLanes {
  vfloatK rdir[3], org_rdir[3], tmin, tmax;
};

/// Entry distances of K rays into child c, and which of them enter it.
PT_ALWAYS_INLINE vboolK child_test(const Bvh4Node& node, int c, const NodeLanes& r, vfloatK& tnear) {
  vfloatK tn = r.tmin, tf = r.tmax;
  for (int a = 0; a < 3; ++a) {
    vfloatK t0 = fused_mul_sub_k(vfloatK(node.bounds[2 * a][c]), r.rdir[a], r.org_rdir[a]);
    vfloatK t1 = fused_mul_sub_k(vfloatK(node.bounds[2 * a + 1][c]), r.rdir[a], r.org_rdir[a]);
    tn = xsimd::max(tn, xsimd::min(t0, t1));
    tf = xsimd::min(tf, xsimd::max(t0, t1));
  }
  tnear = tn;
  return tn <= tf;
}
/// Which of K rays of one direction (`qd`) enter child c: each axis's near
/// and far plane taken as the single ray's node test takes them
/// (intersect_node), so the two planes' distances need no min and max.
PT_ALWAYS_INLINE vboolK child_test(const Bvh4Node& node, int c, const NodeLanes& r, const QueueDirection& qd) {
  auto plane = [&](uint32_t row, int a) {
    return fused_mul_sub_k(vfloatK(node.bounds[row][c]), r.rdir[a], r.org_rdir[a]);
  };
  const vfloatK tn =
      xsimd::max(xsimd::max(plane(qd.near[0], 0), plane(qd.near[1], 1)), xsimd::max(plane(qd.near[2], 2), r.tmin));
  const vfloatK tf =
      xsimd::min(xsimd::min(plane(qd.far[0], 0), plane(qd.far[1], 1)), xsimd::min(plane(qd.far[2], 2), r.tmax));
  return tn <= tf;
}

/// Rays a queue is traced in at most at once: longer queues go in parts of
/// this many (the lists of a part stay in the first levels of the cache).
inline constexpr uint32_t kMaxStreamRays = 4096;

/// Rays of a list whose entry distances order the children for closest hits
/// (the list's first chunks): at levels with 16 vector registers, the
/// distances summed over every chunk spill the chunk test's registers, and a
/// sample of 16 rays orders the children about as well (paired runs in
/// docs/bvh_and_benchmarks.md); AVX-512's 32 registers take every chunk.
inline constexpr uint32_t kOrderSampleChunks = kLanes == 16 ? kMaxStreamRays / kLanes : 16 / kLanes;

/// Splits the list of entry e over the children of its node and pushes the
/// children that rays enter on the stack, the one to visit first on top: by
/// the mean entry distance of the rays of its first kOrderSampleChunks
/// chunks, nearest first (a child none of them enters last), with `kOrdered`
/// (closest hit); in node order, last child first, without (any hit). Two passes: the first tests
/// every chunk of K rays against the four child boxes and keeps the masks;
/// the second compacts each child's rays into a list of its own, allocated
/// at the end of e's block, except for a child that every ray enters, which
/// takes e's list as it is. `live_tmax` is each ray's current tmax (its
/// nearest hit so far, or -inf once blocked). kTmin: the list carries tmin
/// (else every ray's tmin is 0). kShared: the rays have the one direction of
/// `qd`, and the lists carry no reciprocal directions (root_list: their
/// fields' words stay unwritten).
template <bool kOrdered, bool kTmin, bool kShared, class C>
PT_ALWAYS_INLINE void split_node(const Bvh4& bvh, const ListEntry& e, ListArena& arena, const float* live_tmax,
                                 const QueueDirection& qd, ListEntry*& sp, C& counters) {
  static_assert(!(kOrdered && kShared), "queues of one direction are any-hit queues (no entry distances)");
  constexpr uint32_t kFields = kTmin ? kListFields : kListFields - 1;
  assert(e.count <= kMaxStreamRays);  // `masks` holds one part's chunks
  const Bvh4Node& node = bvh.node(e.ref);
  counters.nodes_tested(e.count);
  uint32_t child_ok = 0;  // non-empty slots
  for (int c = 0; c < 4; ++c) child_ok |= uint32_t(node.child[c] != bvh4_ref::kEmptyRef) << c;
  const float* in = arena.field(e, ListField(0));  // field f at in + f * e.room
  const size_t in_room = e.room;
  // Pass 1: the masks of every chunk, the counts and the sample's entry distances.
  alignas(64) uint16_t masks[kMaxStreamRays / kLanes][4];
  uint32_t count[4] = {0, 0, 0, 0};
  vfloatK dist[4] = {vfloatK(0.0f), vfloatK(0.0f), vfloatK(0.0f), vfloatK(0.0f)};
  const uint32_t chunks = (e.count + kLanes - 1) / kLanes;
  auto test_chunk = [&]<bool kDist>(uint32_t j) __attribute__((always_inline)) {
    const uint32_t i = j * kLanes;
    const uint32_t valid = lanes_below(std::min<uint32_t>(kLanes, e.count - i));
    const float* p = in + i;
    const ListedIds id = listed_ids(p + kId * in_room, valid);
    NodeLanes r;
    for (int a = 0; a < 3; ++a) {
      r.rdir[a] = kShared ? vfloatK(qd.rdir[a]) : vfloatK::load_unaligned(p + (kRdirX + a) * in_room);
      r.org_rdir[a] = vfloatK::load_unaligned(p + (kOrgRdirX + a) * in_room);
    }
    r.tmin = kTmin ? vfloatK::load_unaligned(p + kTminField * in_room) : vfloatK(0.0f);
    r.tmax = listed_lanes(live_tmax, id);
    for (int k = 0; k < 4; ++k) {
      vfloatK tnear;
      const uint32_t m = (child_ok >> k & 1)
                             ? lane_mask(kShared ? child_test(node, k, r, qd) : child_test(node, k, r, tnear)) & valid
                             : 0;
      masks[j][k] = static_cast<uint16_t>(m);
      count[k] += std::popcount(m);
      if constexpr (kDist) dist[k] = dist[k] + xsimd::select(lanes_of_mask(m), tnear, vfloatK(0.0f));
    }
  };
  const uint32_t dist_chunks = kOrdered ? std::min<uint32_t>(chunks, kOrderSampleChunks) : 0;
  for (uint32_t j = 0; j < dist_chunks; ++j) test_chunk.template operator()<true>(j);
  uint32_t sampled[4];  // rays whose entry distances the means take: the counts so far
  std::copy(count, count + 4, sampled);
  for (uint32_t j = dist_chunks; j < chunks; ++j) test_chunk.template operator()<false>(j);
  // Pass 2: a list for each child that some rays but not all enter.
  uint32_t top = e.block_end;
  ListEntry hit[4];
  float mean[4];
  int n = 0;
  for (int k = 0; k < 4; ++k) {
    if (count[k] == 0) continue;
    if constexpr (kOrdered) mean[n] = sampled[k] ? xsimd::hadd(dist[k]) / float(sampled[k]) : INFINITY;
    if (count[k] == e.count) {
      hit[n++] = {node.child[k], e.offset, e.count, e.room, 0};
      continue;
    }
    const uint32_t room = list_room(count[k]);
    arena.reserve(top, size_t(kFields) * room);
    // A list's fields lie `room` words apart: two pointers and two strides
    // address them all.
    float* out = arena.field(top, room, ListField(0));
    in = arena.field(e, ListField(0));  // the arena may have moved
    uint32_t written = 0;
    for (uint32_t j = 0; j < chunks; ++j) {
      const uint32_t m = masks[j][k];
      if (m == 0) continue;
      const float* src = in + j * kLanes;
      float* dst = out + written;
      for (uint32_t f = 0; f < kFields; ++f, src += in_room, dst += room)
        if (!kShared || f < kRdirX || f > kRdirZ) store_compressed(dst, m, vfloatK::load_unaligned(src));
      written += std::popcount(m);
      assert(written + kLanes <= room);  // the next K-wide store stays in this list's room
    }
    hit[n++] = {node.child[k], top, count[k], room, 0};
    top += kFields * room;
  }
  for (int i = 0; i < n; ++i) hit[i].block_end = top;
  if constexpr (kOrdered) {
    for (int i = 1; i < n; ++i)  // insertion sort, far first
      for (int j = i; j > 0 && mean[j - 1] < mean[j]; --j) {
        std::swap(mean[j - 1], mean[j]);
        std::swap(hit[j - 1], hit[j]);
      }
  }
  for (int i = 0; i < n; ++i) {
    prefetch_ref(bvh, hit[i].ref);
    *sp++ = hit[i];
  }
}

/// The Moller-Trumbore constants of K listed rays.
struct TriangleLanes {
  vfloatK org[3], dir[3], tmin;
};

/// Rays [i, i + K) of a part, all of direction `dir` (lanes past its end
/// repeat its last ray).
PT_ALWAYS_INLINE TriangleLanes part_triangle_lanes(const RayArrays& rays, size_t i, const vfloatK (&dir)[3],
                                                   vfloatK tmin) {
  TriangleLanes r;
  for (int a = 0; a < 3; ++a) {
    r.org[a] = load_part_lanes(rays.org[a], i, rays.size);
    r.dir[a] = dir[a];
  }
  r.tmin = tmin;
  return r;
}
/// Rays [i, i + K) of a part, each of its own direction.
PT_ALWAYS_INLINE TriangleLanes part_triangle_lanes(const RayArrays& rays, size_t i, vfloatK tmin) {
  const vfloatK dir[3] = {load_part_lanes(rays.dir[0], i, rays.size), load_part_lanes(rays.dir[1], i, rays.size),
                          load_part_lanes(rays.dir[2], i, rays.size)};
  return part_triangle_lanes(rays, i, dir, tmin);
}
/// The listed rays' (listed_lanes), all of direction `dir`.
PT_ALWAYS_INLINE TriangleLanes listed_triangle_lanes(const RayArrays& rays, const ListedIds& id,
                                                     const vfloatK (&dir)[3], vfloatK tmin) {
  TriangleLanes r;
  for (int a = 0; a < 3; ++a) {
    r.org[a] = listed_lanes(rays.org[a], id);
    r.dir[a] = dir[a];
  }
  r.tmin = tmin;
  return r;
}
/// The listed rays', each of its own direction.
PT_ALWAYS_INLINE TriangleLanes listed_triangle_lanes(const RayArrays& rays, const ListedIds& id, vfloatK tmin) {
  const vfloatK dir[3] = {listed_lanes(rays.dir[0], id), listed_lanes(rays.dir[1], id), listed_lanes(rays.dir[2], id)};
  return listed_triangle_lanes(rays, id, dir, tmin);
}

/// Triangle `lane` of block b against K rays (the block test's operations,
/// with the triangle repeated over the rays): the lanes of `active` hit
/// within [tmin, tmax).
PT_ALWAYS_INLINE bool triangle_lanes(const TriangleBlock4& b, int lane, const TriangleLanes& r, vboolK active,
                                     const vfloatK& tmax, LaneHits<vfloatK>& out) {
  const TriangleRows<vfloatK> t(b, lane);
  MtNumerators<vfloatK> n = mt_numerators(t.v0, t.e1, t.e2, r);
  return finish_lanes(n.det, n.t_num, n.u_num, n.v_num, n.inside & active, r.tmin, tmax, out,
                      [](vboolK m) { return lane_mask(m) != 0; });
}
/// triangle_lanes for K rays of the one direction of the block's `terms`.
PT_ALWAYS_INLINE bool triangle_lanes(const TriangleBlock4& b, const BlockDirectionTerms& terms, int lane,
                                     const TriangleLanes& r, vboolK active, const vfloatK& tmax,
                                     LaneHits<vfloatK>& out) {
  const TriangleRows<vfloatK> t(b, lane);
  MtNumerators<vfloatK> n = mt_numerators(t.v0, t.e1, t.e2, terms.of<vfloatK>(lane), r);
  return finish_lanes(n.det, n.t_num, n.u_num, n.v_num, n.inside & active, r.tmin, tmax, out,
                      [](vboolK m) { return lane_mask(m) != 0; });
}

template <class C>
inline void count_leaf(C& counters, const TriangleBlock4* blocks, uint32_t n_blocks, uint32_t rays) {
  if constexpr (C::kEnabled)
    for (uint32_t b = 0; b < n_blocks; ++b)
      for (int l = 0; l < 4; ++l) counters.primitives_tested(blocks[b].prim[l] != kInvalidId ? rays : 0);
}

/// Each of a leaf's triangles against K rays (the rays in `live` not yet in
/// the returned mask), in block order, until every live ray is blocked: the
/// rays blocked. kShared: through the blocks' direction `terms`.
template <bool kShared, class C>
PT_ALWAYS_INLINE uint32_t blocked_lanes(const TriangleBlock4* blocks, uint32_t n_blocks,
                                        const BlockDirectionTerms* terms, const TriangleLanes& r, uint32_t live,
                                        const vfloatK& tmax, C& counters) {
  uint32_t hit = 0;
  for (uint32_t b = 0; b < n_blocks && hit != live; ++b)
    for (int l = 0; l < 4 && hit != live; ++l) {
      if (blocks[b].prim[l] == kInvalidId) continue;
      if constexpr (C::kEnabled) counters.primitives_tested(std::popcount(live & ~hit));
      LaneHits<vfloatK> h;
      const vboolK active = lanes_of_mask(live & ~hit);
      bool any;
      if constexpr (kShared) any = triangle_lanes(blocks[b], terms[b], l, r, active, tmax, h);
      else any = triangle_lanes(blocks[b], l, r, active, tmax, h);
      if (any) hit |= lane_mask(h.hit);
    }
  return hit;
}
/// blocked_lanes for a queue of one direction or not.
template <class C>
PT_ALWAYS_INLINE uint32_t blocked_lanes(const TriangleBlock4* blocks, uint32_t n_blocks, const TriangleLanes& r,
                                        uint32_t live, const vfloatK& tmax, const QueueDirection& qd,
                                        LeafDirectionTerms& leaf_terms, C& counters) {
  if (qd.shared) {
    vfloat4 dir[3];
    qd.lanes(dir);
    return blocked_lanes<true>(blocks, n_blocks, leaf_terms.get(blocks, n_blocks, dir), r, live, tmax, counters);
  }
  return blocked_lanes<false>(blocks, n_blocks, nullptr, r, live, tmax, counters);
}

/// Closest hits of the listed rays in a leaf, K rays at a time, every triangle
/// in block order (a chunk of at most kLeafRaysAlone rays: ray by ray, as a
/// walk tests the leaf); improves `hits` where nearer.
template <bool kTmin, class C>
inline void leaf_closest(const Bvh4& bvh, const ListEntry& e, const RayArrays& rays, const HitArrays& hits,
                         ListArena& arena, C& counters) {
  const TriangleBlock4* blocks = bvh.leaf_blocks(e.ref);
  const uint32_t n_blocks = bvh4_ref::leaf_block_count(e.ref);
  const float* ids = arena.field(e, kId);
  const float* tmins = kTmin ? arena.field(e, kTminField) : nullptr;
  for (uint32_t i = 0; i < e.count; i += kLanes) {
    const uint32_t rays_here = std::min<uint32_t>(kLanes, e.count - i);
    if (rays_here <= kLeafRaysAlone) {  // each ray alone, under its nearest hit so far
      const uint32_t* alone = arena.ids(e) + i;
      for (uint32_t k = 0; k < rays_here; ++k) {
        const MtBlockRay br(rays.ray(alone[k]));
        Hit hit = hits.load(alone[k]);
        const float t_start = hit.t;
        float tmax = t_start;
        vfloat4 vtmax(tmax);
        intersect_leaf_closest<TriangleForm::kMollerTrumbore>(blocks, n_blocks, br, tmax, vtmax, hit, counters);
        if (hit.t < t_start) hits.store(alone[k], hit);
      }
      continue;
    }
    count_leaf(counters, blocks, n_blocks, rays_here);
    const uint32_t valid_lanes = lanes_below(rays_here);
    const ListedIds listed = listed_ids(ids + i, valid_lanes);
    const vintK id = listed.id;
    const vboolK valid = lanes_of_mask(valid_lanes);
    const TriangleLanes r =
        listed_triangle_lanes(rays, listed, kTmin ? vfloatK::load_unaligned(tmins + i) : vfloatK(0.0f));
    vfloatK t = listed_lanes(hits.t, listed), u(0.0f), v(0.0f);
    vintK prim(-1);
    vboolK found(false);
    for (uint32_t b = 0; b < n_blocks; ++b) {
      // A block's four triangles under the nearest t from before the block,
      // as the block test takes them (its tmax also enters the test before
      // the division); the nearest of them wins, the first on a tie.
      const vfloatK t_block = t;
      for (int l = 0; l < 4; ++l) {
        if (blocks[b].prim[l] == kInvalidId) continue;
        LaneHits<vfloatK> h;
        if (!triangle_lanes(blocks[b], l, r, valid, t_block, h)) continue;
        const vboolK nearer = h.hit & (h.t < t);
        t = xsimd::select(nearer, h.t, t);
        u = xsimd::select(nearer, h.u, u);
        v = xsimd::select(nearer, h.v, v);
        prim = xsimd::select(xsimd::bool_cast(nearer), vintK(static_cast<int32_t>(blocks[b].prim[l])), prim);
        found = found | nearer;
      }
    }
    if (uint32_t m = lane_mask(found)) {
      alignas(64) int32_t lane_id[kLanes], lane_prim[kLanes];
      alignas(64) float lane_t[kLanes], lane_u[kLanes], lane_v[kLanes];
      id.store_aligned(lane_id);
      prim.store_aligned(lane_prim);
      t.store_aligned(lane_t);
      u.store_aligned(lane_u);
      v.store_aligned(lane_v);
      for (; m; m &= m - 1) {
        uint32_t l = std::countr_zero(m);
        hits.store(static_cast<uint32_t>(lane_id[l]),
                   Hit{lane_t[l], lane_u[l], lane_v[l], static_cast<uint32_t>(lane_prim[l])});
      }
    }
  }
}

/// Any hit of the listed rays that are not yet blocked in a leaf, K rays at a
/// time (a chunk of at most kLeafRaysAlone live rays: ray by ray); blocked
/// rays get live tmax = -inf and blocked[i] = 1.
template <bool kTmin, bool kShared, class C>
inline void leaf_any(const Bvh4& bvh, const ListEntry& e, const RayArrays& rays, const QueueDirection& qd,
                     ListArena& arena, float* live_tmax, uint8_t* blocked, C& counters) {
  const TriangleBlock4* blocks = bvh.leaf_blocks(e.ref);
  const uint32_t n_blocks = bvh4_ref::leaf_block_count(e.ref);
  LeafDirectionTerms terms;
  vfloat4 dir4[3];
  vfloatK dir[3];
  if constexpr (kShared) qd.lanes(dir4), qd.lanes(dir);
  const float* ids = arena.field(e, kId);
  const float* tmins = kTmin ? arena.field(e, kTminField) : nullptr;
  for (uint32_t i = 0; i < e.count; i += kLanes) {
    const uint32_t valid = lanes_below(std::min<uint32_t>(kLanes, e.count - i));
    const ListedIds listed = listed_ids(ids + i, valid);
    const vintK id = listed.id;
    const vfloatK tmax = listed_lanes(live_tmax, listed);
    const uint32_t live = valid & lane_mask(tmax != vfloatK(-INFINITY));
    if (live == 0) continue;
    if (static_cast<uint32_t>(std::popcount(live)) <= kLeafRaysAlone) {  // each ray alone
      const uint32_t* alone = arena.ids(e) + i;
      for (uint32_t m = live; m; m &= m - 1) {
        const uint32_t r_id = alone[std::countr_zero(m)];
        const MtBlockRay br(rays.ray(r_id));
        if (leaf_occludes<TriangleForm::kMollerTrumbore>(blocks, n_blocks, br, vfloat4(live_tmax[r_id]), counters)) {
          live_tmax[r_id] = -INFINITY;
          blocked[r_id] = 1;
        }
      }
      continue;
    }
    const vfloatK tmin = kTmin ? vfloatK::load_unaligned(tmins + i) : vfloatK(0.0f);
    uint32_t hit;
    if constexpr (kShared) {
      const TriangleLanes r = listed_triangle_lanes(rays, listed, dir, tmin);
      hit = blocked_lanes<true>(blocks, n_blocks, terms.get(blocks, n_blocks, dir4), r, live, tmax, counters);
    } else {
      const TriangleLanes r = listed_triangle_lanes(rays, listed, tmin);
      hit = blocked_lanes<false>(blocks, n_blocks, nullptr, r, live, tmax, counters);
    }
    if (hit == 0) continue;
    alignas(64) int32_t lane_id[kLanes];
    id.store_aligned(lane_id);
    for (; hit; hit &= hit - 1) {
      uint32_t r_id = static_cast<uint32_t>(lane_id[std::countr_zero(hit)]);
      live_tmax[r_id] = -INFINITY;
      blocked[r_id] = 1;
    }
  }
}

/// Walks left to single rays that run at once (in flight, interleaved), and
/// how many are collected before they run.
inline constexpr int kWalksInFlight = 8;
inline constexpr size_t kWalkBatch = 64;

/// Whether `n` collected walks go one after the other rather than
/// interleaved: fewer than there are states in flight (a part's last few),
/// whose turns would mostly pass over empty states, and, in a tree the caches
/// hold (whose walks do not prefetch), fewer than twice that many.
inline bool walks_alone(const Bvh4& bvh, size_t n) {
  return n < size_t(walks_prefetch(bvh) ? kWalksInFlight : 2 * kWalksInFlight);
}

/// Runs the collected closest-hit walks (rays that go on alone below a node)
/// kWalksInFlight at a time; a walk that finds a nearer hit than its ray has
/// by then improves it.
template <class C>
inline void run_closest_walks(const Bvh4& bvh, const RayArrays& rays, const HitArrays& hits, QueueScratch& s,
                              C& counters) {
  if (walks_alone(bvh, s.alone.size())) {
    for (const auto& [id, ref] : s.alone) {
      Hit h = hits.load(id);
      if (bvh4_intersect_below<TriangleForm::kMollerTrumbore>(bvh, ref, rays.ray(id), h, counters)) hits.store(id, h);
    }
    s.alone.clear();
    return;
  }
  size_t next = 0;
  bvh4_intersect_interleaved<TriangleForm::kMollerTrumbore, kWalksInFlight>(
      bvh,
      [&](Ray& r, uint32_t& from, Hit& h, uint32_t& tag) {
        if (next == s.alone.size()) return false;
        const auto [id, ref] = s.alone[next++];
        r = rays.ray(id), from = ref, h = hits.load(id), tag = id;
        return true;
      },
      [&](uint32_t id, const Hit& h, bool found) {
        if (found && h.t < hits.t[id]) hits.store(id, h);
      },
      counters);
  s.alone.clear();
}

/// Runs the collected any-hit walks of rays not yet blocked; a walk whose ray
/// another walk blocks ends there.
template <class C>
inline void run_any_walks(const Bvh4& bvh, const RayArrays& rays, uint8_t* blocked, float* live_tmax, QueueScratch& s,
                          C& counters) {
  auto block = [&](uint32_t id) {
    live_tmax[id] = -INFINITY;
    blocked[id] = 1;
  };
  if (walks_alone(bvh, s.alone.size())) {
    for (const auto& [id, ref] : s.alone)
      if (live_tmax[id] != -INFINITY &&
          bvh4_occluded_below<TriangleForm::kMollerTrumbore>(bvh, ref, rays.ray(id), counters))
        block(id);
    s.alone.clear();
    return;
  }
  size_t next = 0;
  bvh4_occluded_interleaved<TriangleForm::kMollerTrumbore, kWalksInFlight>(
      bvh,
      [&](Ray& r, uint32_t& from, uint32_t& tag) {
        while (next < s.alone.size()) {
          const auto [id, ref] = s.alone[next++];
          if (live_tmax[id] == -INFINITY) continue;
          r = rays.ray(id), from = ref, tag = id;
          return true;
        }
        return false;
      },
      [&](uint32_t id, bool b) {
        if (b) block(id);
      },
      [&](uint32_t id) { return live_tmax[id] == -INFINITY; }, counters);
  s.alone.clear();
}

/// Closest hits of rays [0, rays.size) (at most kMaxStreamRays) into `hits`.
template <bool kTmin, class C>
inline void intersect_part(const Bvh4& bvh, const RayArrays& rays, const HitArrays& hits, ListArena& arena,
                           QueueScratch& s, C& counters) {
  ListEntry stack[kBvh4StackSize];
  ListEntry* sp = stack;
  *sp++ = root_list<kTmin>(bvh, rays, arena);
  while (sp != stack) {
    const ListEntry e = *--sp;
    if (e.count < kStreamMinRays) {
      const uint32_t* ids = arena.ids(e);
      for (uint32_t i = 0; i < e.count; ++i) s.alone.push_back({ids[i], e.ref});
      if (s.alone.size() >= kWalkBatch) run_closest_walks(bvh, rays, hits, s, counters);
    } else if (bvh4_ref::is_leaf(e.ref)) {
      leaf_closest<kTmin>(bvh, e, rays, hits, arena, counters);
    } else {
      split_node<true, kTmin, false>(bvh, e, arena, hits.t, QueueDirection{}, sp, counters);
    }
  }
  run_closest_walks(bvh, rays, hits, s, counters);
}

/// Occlusion of rays [0, rays.size) (at most kMaxStreamRays): blocked rays get
/// live_tmax = -inf and blocked = 1. kShared: rays of the one direction of
/// `qd` (qd.shared).
template <bool kTmin, bool kShared, class C>
inline void occluded_part(const Bvh4& bvh, const RayArrays& rays, const QueueDirection& qd, uint8_t* blocked,
                          float* live_tmax, ListArena& arena, QueueScratch& s, C& counters) {
  ListEntry stack[kBvh4StackSize];
  ListEntry* sp = stack;
  *sp++ = root_list<kTmin, kShared>(bvh, rays, arena);
  while (sp != stack) {
    const ListEntry e = *--sp;
    if (e.count < kStreamMinRays) {
      const uint32_t* ids = arena.ids(e);
      for (uint32_t i = 0; i < e.count; ++i)
        if (live_tmax[ids[i]] != -INFINITY) s.alone.push_back({ids[i], e.ref});
      if (s.alone.size() >= kWalkBatch) run_any_walks(bvh, rays, blocked, live_tmax, s, counters);
    } else if (bvh4_ref::is_leaf(e.ref)) {
      leaf_any<kTmin, kShared>(bvh, e, rays, qd, arena, live_tmax, blocked, counters);
    } else {
      split_node<false, kTmin, kShared>(bvh, e, arena, live_tmax, qd, sp, counters);
    }
  }
  run_any_walks(bvh, rays, blocked, live_tmax, s, counters);
}

/// Rays a part holds at most to go as one masked set (occluded_masked_part).
inline constexpr uint32_t kMaskedRays = 64;

/// Occlusion of the rays of a part of at most kMaskedRays rays, as one set:
/// each ray's slab constants stay in its lane (no lists are written), and a
/// node or leaf on the stack carries a 64-bit mask of the rays that enter it.
/// A node tests each chunk of K rays that has a ray in the mask against its
/// four children, as split_node does; a mask that thins below
/// kStreamMinRays goes on as walks, a leaf as leaf_any takes its chunks.
/// Small queues (a scene's few later shadow rays) pay for no compaction.
template <bool kTmin, class C>
inline void occluded_masked_part(const Bvh4& bvh, const RayArrays& rays, const QueueDirection& qd, uint8_t* blocked,
                                 float* live_tmax, QueueScratch& s, C& counters) {
  assert(rays.size <= kMaskedRays);
  static_assert(kMaskedRays % kLanes == 0 && kMaskedRays <= 64);
  constexpr uint32_t kRoom = kMaskedRays + kMaxLanes;
  alignas(64) float rdir[3][kRoom], org_rdir[3][kRoom], tmin_of[kTmin ? kRoom : 1];
  vfloatK dir[3];  // the one direction (qd.shared)
  if (qd.shared) qd.lanes(dir);
  uint64_t set = 0;  // the rays traced: traceable, not blocked before
  for (size_t i = 0; i < rays.size; i += kLanes) {
    const uint32_t valid = lanes_below(std::min(kLanes, rays.size - i));
    const SlabLanes r = slab_lanes(rays, i);
    const vboolK open = load_part_lanes(live_tmax, i, rays.size) != vfloatK(-INFINITY);
    set |= uint64_t(lane_mask(r.traceable & open) & valid) << i;
    for (int a = 0; a < 3; ++a) {
      if (!qd.shared) r.rdir[a].store_aligned(rdir[a] + i);  // else the node tests broadcast qd.rdir
      r.org_rdir[a].store_aligned(org_rdir[a] + i);
    }
    if constexpr (kTmin) r.tmin.store_aligned(tmin_of + i);
  }
  auto live = [&] {  // the traced rays not blocked yet
    uint64_t m = 0;
    for (uint64_t b = set; b; b &= b - 1)
      if (live_tmax[std::countr_zero(b)] != -INFINITY) m |= b & -b;
    return m;
  };
  struct Entry {
    uint32_t ref;
    uint64_t mask;
  };
  Entry stack[kBvh4StackSize];
  Entry* sp = stack;
  if (set) *sp++ = {bvh.root, set};
  uint64_t alive = set;
  while (sp != stack) {
    const Entry e = *--sp;
    const uint64_t mask = e.mask & alive;
    if (mask == 0) continue;
    if (static_cast<uint32_t>(std::popcount(mask)) < kStreamMinRays) {  // 4 and 2 measured no faster
      for (uint64_t b = mask; b; b &= b - 1) s.alone.push_back({static_cast<uint32_t>(std::countr_zero(b)), e.ref});
      if (s.alone.size() >= kWalkBatch) {
        run_any_walks(bvh, rays, blocked, live_tmax, s, counters);
        alive = live();
      }
      continue;
    }
    if (bvh4_ref::is_leaf(e.ref)) {
      const TriangleBlock4* blocks = bvh.leaf_blocks(e.ref);
      const uint32_t n_blocks = bvh4_ref::leaf_block_count(e.ref);
      LeafDirectionTerms terms;
      for (uint32_t i = 0; i < rays.size; i += kLanes) {
        const uint32_t chunk = static_cast<uint32_t>(mask >> i) & lanes_below(kLanes);
        if (chunk == 0) continue;
        if (static_cast<uint32_t>(std::popcount(chunk)) <= kLeafRaysAlone) {  // each ray alone
          for (uint32_t m = chunk; m; m &= m - 1) {
            const uint32_t r_id = i + std::countr_zero(m);
            const MtBlockRay br(rays.ray(r_id));
            if (leaf_occludes<TriangleForm::kMollerTrumbore>(blocks, n_blocks, br, vfloat4(live_tmax[r_id]),
                                                             counters)) {
              live_tmax[r_id] = -INFINITY;
              blocked[r_id] = 1;
              alive &= ~(uint64_t(1) << r_id);
            }
          }
          continue;
        }
        const vfloatK tmin = kTmin ? vfloatK::load_aligned(tmin_of + i) : vfloatK(0.0f);
        const TriangleLanes r =
            qd.shared ? part_triangle_lanes(rays, i, dir, tmin) : part_triangle_lanes(rays, i, tmin);
        const vfloatK tmax = vfloatK::load_unaligned(live_tmax + i);
        uint32_t hit = blocked_lanes(blocks, n_blocks, r, chunk, tmax, qd, terms, counters);
        for (; hit; hit &= hit - 1) {
          const uint32_t r_id = i + std::countr_zero(hit);
          live_tmax[r_id] = -INFINITY;
          blocked[r_id] = 1;
          alive &= ~(uint64_t(1) << r_id);
        }
      }
      continue;
    }
    const Bvh4Node& node = bvh.node(e.ref);
    counters.nodes_tested(std::popcount(mask));
    uint64_t child_mask[4] = {0, 0, 0, 0};
    auto test_chunks = [&]<bool kShared>() __attribute__((always_inline)) {
      for (uint32_t i = 0; i < rays.size; i += kLanes) {
        const uint32_t chunk = static_cast<uint32_t>(mask >> i) & lanes_below(kLanes);
        if (chunk == 0) continue;
        NodeLanes r;
        for (int a = 0; a < 3; ++a) {
          r.rdir[a] = kShared ? vfloatK(qd.rdir[a]) : vfloatK::load_aligned(rdir[a] + i);
          r.org_rdir[a] = vfloatK::load_aligned(org_rdir[a] + i);
        }
        r.tmin = kTmin ? vfloatK::load_aligned(tmin_of + i) : vfloatK(0.0f);
        r.tmax = vfloatK::load_unaligned(live_tmax + i);
        for (int k = 0; k < 4; ++k) {
          if (node.child[k] == bvh4_ref::kEmptyRef) continue;
          uint32_t m;
          if constexpr (kShared) {
            m = lane_mask(child_test(node, k, r, qd));
          } else {
            vfloatK tnear;
            m = lane_mask(child_test(node, k, r, tnear));
          }
          child_mask[k] |= uint64_t(m & chunk) << i;
        }
      }
    };
    if (qd.shared) test_chunks.template operator()<true>();
    else test_chunks.template operator()<false>();
    for (int k = 0; k < 4; ++k)  // node order, the last child on top (as split_node<false>)
      if (child_mask[k]) {
        prefetch_ref(bvh, node.child[k]);
        *sp++ = {node.child[k], child_mask[k]};
      }
  }
  run_any_walks(bvh, rays, blocked, live_tmax, s, counters);
}

/// Rays [begin, end) of a queue, with indices from 0.
inline RayArrays part_of(const RayArrays& rays, size_t begin, size_t end) {
  RayArrays p = rays;
  for (int a = 0; a < 3; ++a) p.org[a] += begin, p.dir[a] += begin;
  if (p.tmin) p.tmin += begin;
  p.tmax += begin;
  p.size = end - begin;
  return p;
}

}  // namespace stream_detail

/// Closest hits of every ray of the queue into `hits` (each as
/// bvh4_intersect gives it), Moller-Trumbore leaves.
template <class C>
inline void bvh4_intersect_stream(const Bvh4& bvh, const RayArrays& rays, const HitArrays& hits, QueueScratch& s,
                                  C& counters) {
  using namespace stream_detail;
  for (size_t i = 0; i < rays.size; ++i) hits.store(i, Hit{rays.tmax[i], 0.0f, 0.0f, kInvalidId});
  if (bvh.empty()) return;
  ListArena arena(s);
  for (size_t b = 0; b < rays.size; b += kMaxStreamRays) {
    const RayArrays part = part_of(rays, b, std::min(rays.size, b + kMaxStreamRays));
    const HitArrays out{hits.t + b, hits.u + b, hits.v + b, hits.prim + b};
    if (has_tmin(part)) intersect_part<true>(bvh, part, out, arena, s, counters);
    else intersect_part<false>(bvh, part, out, arena, s, counters);
  }
}

/// Sets blocked[i] = 1 for every ray i of the queue that is blocked (as
/// bvh4_occluded), Moller-Trumbore leaves; writes nothing for the others, so
/// the caller zeroes `blocked` first. blocked[i] set to 1 already counts as
/// blocked (and the ray is not traced).
template <class C>
inline void bvh4_occluded_stream(const Bvh4& bvh, const RayArrays& rays, uint8_t* blocked, QueueScratch& s,
                                 C& counters) {
  using namespace stream_detail;
  if (bvh.empty() || rays.size == 0) return;
  s.tmax.resize(rays.size + kMaxLanes);
  float* live_tmax = s.tmax.data();
  for (size_t i = 0; i < rays.size; ++i) live_tmax[i] = blocked[i] ? -INFINITY : rays.tmax[i];
  ListArena arena(s);
  const QueueDirection qd = direction_of(rays);
  for (size_t b = 0; b < rays.size; b += kMaxStreamRays) {
    const RayArrays part = part_of(rays, b, std::min(rays.size, b + kMaxStreamRays));
    if (part.size <= kMaskedRays) {
      if (has_tmin(part)) occluded_masked_part<true>(bvh, part, qd, blocked + b, live_tmax + b, s, counters);
      else occluded_masked_part<false>(bvh, part, qd, blocked + b, live_tmax + b, s, counters);
    } else if (has_tmin(part)) {
      if (qd.shared) occluded_part<true, true>(bvh, part, qd, blocked + b, live_tmax + b, arena, s, counters);
      else occluded_part<true, false>(bvh, part, qd, blocked + b, live_tmax + b, arena, s, counters);
    } else if (qd.shared) {
      occluded_part<false, true>(bvh, part, qd, blocked + b, live_tmax + b, arena, s, counters);
    } else {
      occluded_part<false, false>(bvh, part, qd, blocked + b, live_tmax + b, arena, s, counters);
    }
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt
