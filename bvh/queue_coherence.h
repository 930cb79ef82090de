// How a queue is traced: the rule that picks ray by ray, coherent sets or a
// stream (choose_queue_method), and what it measures of the queue. A queue
// is coherent when it comes in runs of consecutive rays from one origin or
// from origins close together, in nearly one direction: a pinhole camera's
// rays (a pixel's samples and its neighbours') and the shadow rays of a
// directional light from the first hits of neighbouring paths; bounce rays
// and the shadow rays of later vertices are not. Sets of 64 such rays cost
// two 4-wide node tests for the whole set at most nodes, where a stream
// tests every ray.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include "kernels/simd/isa_namespace.h"
#include "bvh4.h"
#include "bvh4_leaf_test.h"
#if PT_PER_LEVEL
#include "bvh4_stream.h"
#endif
#include "kernels/math/ray_arrays.h"
#include "kernels/simd/cache_size.h"

namespace pt {
inline namespace PT_ISA_NS {

/// How close the origins of a coherent run lie: within a 32nd of the scene's
/// extent of the run's first origin.
inline constexpr float kCoherentSpread = 1.0f / 32.0f;

/// The diagonal of the scene's bounds (the BVH root's children's, or its one
/// leaf's triangles'); 0 when it has no triangles. Moller-Trumbore leaves.
inline float scene_extent(const Bvh4& bvh) {
  if (bvh.empty()) return 0.0f;
  float3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  auto take = [&](int a, float v) {
    lo[a] = std::min(lo[a], v);
    hi[a] = std::max(hi[a], v);
  };
  if (!bvh4_ref::is_leaf(bvh.root)) {
    const Bvh4Node& n = bvh.node(bvh.root);
    for (int c = 0; c < 4; ++c)
      if (n.child[c] != bvh4_ref::kEmptyRef)
        for (int a = 0; a < 3; ++a) take(a, n.bounds[2 * a][c]), take(a, n.bounds[2 * a + 1][c]);
    return length(hi - lo);
  }
  for (uint32_t i = 0, count = bvh4_ref::leaf_block_count(bvh.root); i < count; ++i) {
    const TriangleBlock4& b = bvh.leaf_blocks(bvh.root)[i];
    for (int l = 0; l < 4; ++l)
      if (b.prim[l] != kInvalidId)
        for (int a = 0; a < 3; ++a)  // rows v0, e1 = v1 - v0, e2 = v2 - v0
          take(a, b.v0[a][l]), take(a, b.v0[a][l] + b.r1[a][l]), take(a, b.v0[a][l] + b.r2[a][l]);
  }
  return length(hi - lo);
}

/// Whether four runs of `run` rays spread over the queue (its first, and
/// those that start a quarter, half and three quarters of the way through)
/// are coherent: each ray's origin equal to its run's first or within `near`
/// of it, and its direction within 2.5 degrees of the first's. Spread, so
/// that a queue coherent only at its start (sorted later shadow rays, whose
/// first cell's rays may leave from one point) is not taken for one.
inline bool in_coherent_runs(const RayArrays& rays, float near, size_t run) {
  if (rays.size < 4 * run) return false;
  for (size_t k = 0; k < 4; ++k) {
    const size_t p = k * (rays.size / 4) / run * run;
    const Ray first = rays.ray(p);
    const float first_len = length(first.dir);
    for (size_t i = p + 1; i < p + run; ++i) {
      const Ray r = rays.ray(i);
      if (!(r.org == first.org || length(r.org - first.org) <= near) ||
          !(dot(r.dir, first.dir) > 0.999f * length(r.dir) * first_len))
        return false;
    }
  }
  return true;
}

/// How far a sky's directions spread: the ranges of a run's unit directions
/// on the three axes sum to more than this (a sky's samples from the CS184
/// scenes' surfaces 3.7-4.8 over 32 consecutive rays, an area light's 0.9-1.5,
/// a directional light's 0).
inline constexpr float kSphereSpread = 3.0f;

/// Consecutive rays per run that spans_the_sphere measures.
inline constexpr size_t kSpreadRun = 32;

/// The sum of the ranges on the three axes of the unit directions of rays
/// [first, first + n); rays whose direction is not finite or is 0 count for
/// nothing.
inline float direction_spread(const RayArrays& rays, size_t first, size_t n) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = first; i < first + n; ++i) {
    const float3 d{rays.dir[0][i], rays.dir[1][i], rays.dir[2][i]};
    const float len = length(d);
    if (!(len > 0.0f && len < INFINITY)) continue;
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], d[a] / len), hi[a] = std::max(hi[a], d[a] / len);
  }
  float sum = 0.0f;
  for (int a = 0; a < 3; ++a) sum += hi[a] > lo[a] ? hi[a] - lo[a] : 0.0f;
  return sum;
}

/// Whether a queue's directions span the sphere, as a sky's samples do:
/// four runs of kSpreadRun rays spread over the queue (one run of all its
/// rays when it is shorter than four) each spread more than kSphereSpread.
inline bool spans_the_sphere(const RayArrays& rays) {
  if (rays.size < 4 * kSpreadRun) return rays.size >= 2 && direction_spread(rays, 0, rays.size) > kSphereSpread;
  for (size_t k = 0; k < 4; ++k)
    if (!(direction_spread(rays, k * (rays.size / 4) / kSpreadRun * kSpreadRun, kSpreadRun) > kSphereSpread))
      return false;
  return true;
}

/// Whether an any-hit queue goes as octant sets (bvh4_octant_sets.h) at a
/// level of `lanes` lanes, in a tree of `tree_bytes` on a core whose L2
/// holds `l2_bytes`, and with `part_rays` rays in a stream's part. Rays that
/// spread over the sphere part ways at the first nodes, so a stream's lists
/// thin out and each node is tested for few rays; an octant set instead
/// loads each node once for its rays. That pays where
///   - the directions span the sphere (a sky's samples);
///   - the tree is larger than L2, so that rays wait on nodes and leaves the
///     set's rays then share;
///   - the level has at most 8 lanes: an octant set's node test takes one ray
///     against four children, and at 16 lanes a stream's test takes sixteen
///     rays against a child;
///   - the queue is at most an eighth of a stream's part (a set's worth of
///     rays per octant on average): longer queues keep a stream's lists long
///     enough for its tests across rays.
inline bool goes_as_octant_sets(const RayArrays& rays, size_t lanes, size_t tree_bytes, size_t l2_bytes,
                                size_t part_rays) {
  return lanes <= 8 && rays.size <= part_rays / 8 && tree_bytes > l2_bytes && spans_the_sphere(rays);
}

#if PT_PER_LEVEL
/// How a queue is traced (scene_bvh4_queries.h).
enum class QueueMethod {
  kRays,        ///< ray by ray, each its own walk (bvh4_ray_walk.h)
  kSets,        ///< coherent sets of 64 consecutive rays (bvh4_coherent_set.h)
  kOctantSets,  ///< any hit: sets of 32 rays of one direction octant (bvh4_octant_sets.h)
  kStream,      ///< a ray stream (bvh4_stream.h)
};

/// The rule that picks a queue's method (docs/bvh.md, "How a queue is
/// traced"): ray by ray when the leaves are not Moller-Trumbore's (the other
/// methods' triangle tests are) or when the queue has fewer rays than a
/// stream tests across lanes at its root (it would hand them all to walks
/// there); as coherent sets when it comes in coherent runs of K rays
/// (in_coherent_runs, within a 32nd of the scene's extent); for any hit, as
/// octant sets when goes_as_octant_sets says so; else as a stream.
template <class Blocks, bool kAnyHit>
inline QueueMethod choose_queue_method(const Bvh4& bvh, const RayArrays& rays) {
  if (!std::is_same_v<Blocks, MtBlocks> || rays.size < stream_detail::kStreamMinRays) return QueueMethod::kRays;
  if (rays.size >= 4 * kLanes && in_coherent_runs(rays, kCoherentSpread * scene_extent(bvh), kLanes))
    return QueueMethod::kSets;
  if (kAnyHit && goes_as_octant_sets(rays, kLanes, bvh.bytes(), l2_cache_bytes(), stream_detail::kMaxStreamRays))
    return QueueMethod::kOctantSets;
  return QueueMethod::kStream;
}
#endif

}  // namespace PT_ISA_NS
}  // namespace pt
