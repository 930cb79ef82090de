// A whole queue of rays through the 4-wide BVH at once (dynamic ray stream
// traversal, after Barringer and Akenine-Moller 2014), for closest hit and
// any hit alike (kAnyHit): the rays that reach a node form a list; each
// child box is tested against all of them, K rays per SIMD instruction, and
// the rays that enter it are compacted into the child's list, each with the
// constants of its slab test, so that the next level loads them as vectors.
// A leaf tests each of its triangles against K rays at a time (leaf_lanes);
// a chunk of K/2 rays or fewer takes it ray by ray, through the walks' own
// leaf test. The rays of a list that has thinned below kStreamMinRays go on
// alone from that node: their walks are collected and run kWalksInFlight at
// a time, taking turns (bvh4_interleaved.h), each under its ray's nearest
// hit at the time it starts. An any-hit queue whose rays all have one
// direction (a directional light's shadow rays) computes each leaf
// triangle's direction terms once per visit for all its rays, and tests
// nodes with the direction's slab constants and octant planes, its lists
// carrying no reciprocal directions (QueueDirection). Every ray gets the hit
// it gets alone, bit for bit: the node and leaf tests are the single ray's,
// lane by lane. Moller-Trumbore leaves.
#pragma once

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>

#include "bvh4_interleaved.h"
#include "bvh4_leaf_test.h"
#include "bvh4_node_test.h"
#include "bvh4_ray_walk.h"
#include "kernels/math/ray_arrays.h"
#include "kernels/simd/cache_size.h"
#include "kernels/simd/isa_namespace.h"
#include "queue_lanes.h"
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

/// Whether every ray of a queue has one direction, bit for bit (a
/// directional light's shadow rays), and which: then leaves compute each
/// triangle's direction terms once per visit for all its rays, and take the
/// direction as a broadcast instead of each ray's; node tests take the
/// direction's slab constants as broadcasts and its octant's near and far
/// planes, and lists carry no reciprocal directions.
struct QueueDirection {
  bool shared = false;
  float dir[3] = {0.0f, 0.0f, 0.0f};
  float rdir[3] = {0.0f, 0.0f, 0.0f};  ///< NodeRay's reciprocal direction
  OctantPlanes planes;                 ///< the direction's near and far plane rows
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
    const vboolK same = same_bits(load_queue_lanes(rays.dir[0], i, rays.size), rays.dir[0][0]) &
                        same_bits(load_queue_lanes(rays.dir[1], i, rays.size), rays.dir[1][0]) &
                        same_bits(load_queue_lanes(rays.dir[2], i, rays.size), rays.dir[2][0]);
    if (lane_mask(same) != lanes_below(kLanes)) return q;
  }
  q.shared = true;
  uint32_t octant = 0;
  for (int a = 0; a < 3; ++a) {
    q.dir[a] = rays.dir[a][0];
    q.rdir[a] = NodeRay::reciprocal(q.dir[a]);
    octant |= uint32_t(q.rdir[a] < 0.0f) << a;
  }
  q.planes = OctantPlanes(octant);
  return q;
}

/// How far ahead of the chunk it lists root_list starts loading the part's
/// arrays: as many rays as keep the lines in flight, over the eight arrays it
/// reads, to a quarter of the L1 data cache (256 rays of a 32 KiB L1). A
/// render's queue is written by shading well before it is traced and may no
/// longer sit in L2, and the hardware's stream prefetchers fall behind eight
/// arrays read at once.
inline size_t root_prefetch_rays() { return l1_data_cache_bytes() / 4 / (8 * sizeof(float)); }

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
  const size_t ahead = root_prefetch_rays();
  for (size_t i = 0; i < rays.size; i += kLanes) {
    if (i % 16 == 0) prefetch_queue_rays(rays, i + ahead);
    const QueueLanes r(rays, i);
    const uint32_t m = r.traceable;
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

/// Rays a queue is traced in at most at once: longer queues go in parts of
/// this many (the lists of a part stay in the first levels of the cache).
inline constexpr uint32_t kMaxStreamRays = 4096;

/// Rays of a list whose entry distances order the children for closest hits
/// (the list's first chunks): at levels with 16 vector registers, the
/// distances summed over every chunk spill the chunk test's registers, and a
/// sample of 16 rays orders the children about as well; AVX-512's 32
/// registers take every chunk.
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
      const uint32_t m = (child_ok >> k & 1) ? lane_mask(kShared ? lanes_enter_child(node, k, r, qd.planes, tnear)
                                                                 : lanes_enter_child(node, k, r, tnear)) &
                                                   valid
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

/// What the walk of a part writes. Closest hit: each ray's hit, whose t is
/// its nearest hit so far. Any hit: each ray's tmax, -inf once blocked, and
/// whether it is blocked.
template <bool kAnyHit>
struct PartAnswers;
template <>
struct PartAnswers<false> {
  HitArrays hits;
  const float* tmax() const { return hits.t; }
  bool open(uint32_t) const { return true; }
  Hit nearest(uint32_t i) const { return hits.load(i); }
  /// Takes a walk's or a leaf's hit of ray i where it is nearer.
  void take(uint32_t i, const Hit& h) const {
    if (h.t < hits.t[i]) hits.store(i, h);
  }
};
template <>
struct PartAnswers<true> {
  float* live_tmax;
  uint8_t* blocked;
  const float* tmax() const { return live_tmax; }
  bool open(uint32_t i) const { return live_tmax[i] != -INFINITY; }
  Hit nearest(uint32_t i) const { return {live_tmax[i], 0.0f, 0.0f, kInvalidId}; }
  /// Ray i is blocked.
  void take(uint32_t i, const Hit&) const {
    live_tmax[i] = -INFINITY;
    blocked[i] = 1;
  }
};

/// The triangle-test constants of the listed rays (listed_lanes); `dir`,
/// when not null, is the one direction of them all (QueueDirection).
PT_ALWAYS_INLINE TriangleLanes listed_triangle_lanes(const RayArrays& rays, const ListedIds& id, vfloatK tmin,
                                                     const vfloatK (*dir)[3]) {
  TriangleLanes r;
  for (int a = 0; a < 3; ++a) {
    r.org[a] = listed_lanes(rays.org[a], id);
    r.dir[a] = dir ? (*dir)[a] : listed_lanes(rays.dir[a], id);
  }
  r.tmin = tmin;
  return r;
}

/// The listed rays of a leaf against its triangles, K rays at a time (a
/// chunk of at most kLeafRaysAlone open rays: ray by ray, as a walk tests
/// the leaf); `out` takes what they find.
template <bool kAnyHit, bool kTmin, bool kShared, class C>
inline void test_leaf(const Bvh4& bvh, const ListEntry& e, const RayArrays& rays, const QueueDirection& qd,
                      ListArena& arena, const PartAnswers<kAnyHit>& out, C& counters) {
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
    const vfloatK tmax = listed_lanes(out.tmax(), listed);
    const uint32_t open = kAnyHit ? valid & lane_mask(tmax != vfloatK(-INFINITY)) : valid;
    if (open == 0) continue;
    if (static_cast<uint32_t>(std::popcount(open)) <= kLeafRaysAlone) {  // each ray alone
      const uint32_t* alone = arena.ids(e) + i;
      for (uint32_t m = open; m; m &= m - 1) {
        const uint32_t r_id = alone[std::countr_zero(m)];
        Hit hit = out.nearest(r_id);
        float t = hit.t;
        vfloat4 vt(t);
        const MtBlockRay br(rays.ray(r_id));
        if (leaf_hit<kAnyHit, MtBlocks>(blocks, n_blocks, br, {t, vt, hit}, counters) || !kAnyHit) out.take(r_id, hit);
      }
      continue;
    }
    const vfloatK tmin = kTmin ? vfloatK::load_unaligned(tmins + i) : vfloatK(0.0f);
    const TriangleLanes r = listed_triangle_lanes(rays, listed, tmin, kShared ? &dir : nullptr);
    LaneHitState s{tmax, vfloatK(0.0f), vfloatK(0.0f), vintK(-1)};
    uint32_t changed = leaf_lanes<kAnyHit>(blocks, n_blocks, r, open, s,
                                           kShared ? terms.get(blocks, n_blocks, dir4) : nullptr, counters);
    if (changed == 0) continue;
    alignas(64) int32_t lane_id[kLanes], lane_prim[kLanes];
    alignas(64) float lane_t[kLanes], lane_u[kLanes], lane_v[kLanes];
    listed.id.store_aligned(lane_id);
    if constexpr (!kAnyHit) {
      s.prim.store_aligned(lane_prim);
      s.t.store_aligned(lane_t), s.u.store_aligned(lane_u), s.v.store_aligned(lane_v);
    }
    for (; changed; changed &= changed - 1) {
      const uint32_t l = std::countr_zero(changed);
      out.take(static_cast<uint32_t>(lane_id[l]),
               Hit{lane_t[l], lane_u[l], lane_v[l], static_cast<uint32_t>(lane_prim[l])});
    }
  }
}

/// Walks left to single rays that run at once, taking turns: a turn waits on
/// a node (two lines) or a leaf, so eight walks keep some sixteen lines in
/// flight, within what a core's L1 tracks of its misses (12 to 24 on the
/// x86-64 and Arm cores of its levels).
inline constexpr int kWalksInFlight = 8;
/// Walks collected before they run: eight for each walk in flight, so that
/// the turns stay full until the last few.
inline constexpr size_t kWalkBatch = 8 * kWalksInFlight;

/// Whether `n` collected walks go one after the other rather than taking
/// turns: fewer than there are walks in flight (a part's last few), whose
/// turns would mostly pass over empty ones, and, in a tree the caches hold
/// (whose walks do not prefetch), fewer than twice that many.
inline bool walks_alone(const Bvh4& bvh, size_t n) {
  return n < size_t(walks_prefetch(bvh) ? kWalksInFlight : 2 * kWalksInFlight);
}

/// Runs the collected walks (rays that go on alone below a node) of rays
/// still open, kWalksInFlight at a time; `out` takes what they find (closest
/// hit: a nearer hit than its ray has by then; any hit: the ray blocked,
/// which ends its other walks).
template <bool kAnyHit, class C>
inline void run_walks(const Bvh4& bvh, const RayArrays& rays, const PartAnswers<kAnyHit>& out, QueueScratch& s,
                      C& counters) {
  if (walks_alone(bvh, s.alone.size())) {
    for (const auto& [id, ref] : s.alone) {
      if (!out.open(id)) continue;
      Hit h = out.nearest(id);
      if (walk_ray<kAnyHit>(bvh, ref, rays.ray(id), h, counters)) out.take(id, h);
    }
    s.alone.clear();
    return;
  }
  size_t next = 0;
  walk_interleaved<kAnyHit, kWalksInFlight>(
      bvh,
      [&](Ray& r, uint32_t& from, Hit& nearest, uint32_t& tag) {
        while (next < s.alone.size()) {
          const auto [id, ref] = s.alone[next++];
          if (!out.open(id)) continue;
          r = rays.ray(id), from = ref, nearest = out.nearest(id), tag = id;
          return true;
        }
        return false;
      },
      [&](uint32_t id, const Hit& h, bool found) {
        if (found) out.take(id, h);
      },
      [&](uint32_t id) { return !out.open(id); }, counters);
  s.alone.clear();
}

/// The rays [0, rays.size) of a part (at most kMaxStreamRays) through the
/// tree; `out` takes what they find. kTmin: some ray has tmin != 0. kShared:
/// every ray has the one direction of `qd` (any hit).
template <bool kAnyHit, bool kTmin, bool kShared, class C>
inline void trace_part(const Bvh4& bvh, const RayArrays& rays, const QueueDirection& qd,
                       const PartAnswers<kAnyHit>& out, ListArena& arena, QueueScratch& s, C& counters) {
  ListEntry stack[kBvh4StackSize];
  ListEntry* sp = stack;
  *sp++ = root_list<kTmin, kShared>(bvh, rays, arena);
  while (sp != stack) {
    const ListEntry e = *--sp;
    if (e.count < kStreamMinRays) {
      const uint32_t* ids = arena.ids(e);
      for (uint32_t i = 0; i < e.count; ++i)
        if (out.open(ids[i])) s.alone.push_back({ids[i], e.ref});
      if (s.alone.size() >= kWalkBatch) run_walks(bvh, rays, out, s, counters);
    } else if (bvh4_ref::is_leaf(e.ref)) {
      test_leaf<kAnyHit, kTmin, kShared>(bvh, e, rays, qd, arena, out, counters);
    } else {
      split_node<!kAnyHit, kTmin, kShared>(bvh, e, arena, out.tmax(), qd, sp, counters);
    }
  }
  run_walks(bvh, rays, out, s, counters);
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
inline void occluded_masked_part(const Bvh4& bvh, const RayArrays& rays, const QueueDirection& qd,
                                 const PartAnswers<true>& out, QueueScratch& s, C& counters) {
  float* live_tmax = out.live_tmax;
  assert(rays.size <= kMaskedRays);
  static_assert(kMaskedRays % kLanes == 0 && kMaskedRays <= 64);
  constexpr uint32_t kRoom = kMaskedRays + kMaxLanes;
  alignas(64) float rdir[3][kRoom], org_rdir[3][kRoom], tmin_of[kTmin ? kRoom : 1];
  vfloatK dir[3];  // the one direction (qd.shared)
  if (qd.shared) qd.lanes(dir);
  uint64_t set = 0;  // the rays traced: traceable, not blocked before
  for (size_t i = 0; i < rays.size; i += kLanes) {
    const QueueLanes r(rays, i);
    const vboolK open = load_queue_lanes(live_tmax, i, rays.size) != vfloatK(-INFINITY);
    set |= uint64_t(lane_mask(open) & r.traceable) << i;
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
        run_walks(bvh, rays, out, s, counters);
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
            Hit hit = out.nearest(r_id);
            vfloat4 vt(hit.t);
            if (leaf_hit<true, MtBlocks>(blocks, n_blocks, MtBlockRay(rays.ray(r_id)), {hit.t, vt, hit}, counters)) {
              out.take(r_id, hit);
              alive &= ~(uint64_t(1) << r_id);
            }
          }
          continue;
        }
        const vfloatK tmin = kTmin ? vfloatK::load_aligned(tmin_of + i) : vfloatK(0.0f);
        TriangleLanes r;
        for (int a = 0; a < 3; ++a) {
          r.org[a] = load_queue_lanes(rays.org[a], i, rays.size);
          r.dir[a] = qd.shared ? dir[a] : load_queue_lanes(rays.dir[a], i, rays.size);
        }
        r.tmin = tmin;
        LaneHitState lanes{vfloatK::load_unaligned(live_tmax + i), vfloatK(0.0f), vfloatK(0.0f), vintK(-1)};
        vfloat4 dir4[3];
        qd.lanes(dir4);
        uint32_t hit = leaf_lanes<true>(blocks, n_blocks, r, chunk, lanes,
                                        qd.shared ? terms.get(blocks, n_blocks, dir4) : nullptr, counters);
        for (; hit; hit &= hit - 1) {
          const uint32_t r_id = i + std::countr_zero(hit);
          out.take(r_id, Hit{});
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
          vfloatK tnear;
          const uint32_t m = lane_mask(kShared ? lanes_enter_child(node, k, r, qd.planes, tnear)
                                               : lanes_enter_child(node, k, r, tnear));
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
  run_walks(bvh, rays, out, s, counters);
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
    const PartAnswers<false> out{HitArrays{hits.t + b, hits.u + b, hits.v + b, hits.prim + b}};
    if (has_tmin(part)) trace_part<false, true, false>(bvh, part, QueueDirection{}, out, arena, s, counters);
    else trace_part<false, false, false>(bvh, part, QueueDirection{}, out, arena, s, counters);
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
    const PartAnswers<true> out{live_tmax + b, blocked + b};
    if (part.size <= kMaskedRays) {
      if (has_tmin(part)) occluded_masked_part<true>(bvh, part, qd, out, s, counters);
      else occluded_masked_part<false>(bvh, part, qd, out, s, counters);
    } else if (has_tmin(part)) {
      if (qd.shared) trace_part<true, true, true>(bvh, part, qd, out, arena, s, counters);
      else trace_part<true, true, false>(bvh, part, qd, out, arena, s, counters);
    } else if (qd.shared) {
      trace_part<true, false, true>(bvh, part, qd, out, arena, s, counters);
    } else {
      trace_part<true, false, false>(bvh, part, qd, out, arena, s, counters);
    }
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt
