// When a queue's rays are coherent enough for sets: runs of consecutive
// rays from one origin or from origins close together, in nearly one
// direction. A pinhole camera's rays are such runs (a pixel's samples and its
// neighbours'), and so are the shadow rays of a directional light from the
// first hits of neighbouring paths; bounce rays and the shadow rays of later
// vertices are not. The queue tracer (scene_bvh4_queries.h) traces coherent
// queues as sets of 64 rays under a frustum (bvh4_coherent_set.h), whose
// nodes cost two 4-wide tests for the whole set, and the others as streams.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "kernels/simd/isa_namespace.h"
#include "bvh4.h"
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

/// Queues of at most this many rays go as octant sets when they qualify
/// (goes_as_octant_sets): on longer ones the stream shares more work across
/// rays (docs/bvh_and_benchmarks.md: bunny's sky shadow rays as sets, on a
/// Zen 3 at AVX2, in queues of 1024 rays and up 0.79-1.03 of the stream's
/// rate; on a Zen 4 at AVX2, in queues of 256-512 rays 1.04-1.22x).
inline constexpr size_t kOctantSetMaxRays = 512;

/// The widest SIMD level (lanes) at which octant sets pay: their node tests
/// are one ray's four children, while at 16 lanes the stream tests 16 rays'
/// boxes at once (docs/bvh_and_benchmarks.md: on a Zen 4, bunny's short sky
/// shadow queues at AVX2 1.04-1.23x as sets, at AVX-512 0.87-1.13x, 1 and
/// 2 threads).
inline constexpr size_t kOctantSetMaxLanes = 8;

/// Whether an any-hit queue goes as octant sets (bvh4_octant_sets.h) at a
/// level of `lanes` lanes: a short queue whose directions span the sphere, in
/// a tree larger than one core's L2 cache of `l2_bytes` (l2_cache_bytes() in
/// the renderer; a test's own figure elsewhere), where rays wait on nodes and
/// leaves that the set's rays then load once (in a tree the caches hold, the
/// stream's tests across rays win: banana's sky shadow rays 0.72x as sets).
inline bool goes_as_octant_sets(const Bvh4& bvh, const RayArrays& rays, size_t lanes, size_t l2_bytes) {
  return lanes <= kOctantSetMaxLanes && rays.size <= kOctantSetMaxRays && bvh.bytes() > l2_bytes &&
         spans_the_sphere(rays);
}

}  // namespace PT_ISA_NS
}  // namespace pt
