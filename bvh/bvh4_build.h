// Building the 4-wide triangle BVH: optional pre-splitting (presplit.cpp),
// binned SAH binary build (bvh2_sah.cpp),
// collapse to four children (bvh4_collapse.cpp), then the leaf blocks filled
// with precomputed triangles in BVH order. Reports build statistics.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "bvh2.h"
#include "bvh4.h"
#include "bvh4_collapse.h"
#include "kernels/scene/scene.h"

namespace pt {

/// Scenes of at most this many triangles (build references) make a tree that
/// fits in a 32 KiB L1 data cache, even at the 56 bytes per triangle of the
/// smaller leaves the L1 block cost makes (CBgems: 54.9).
inline constexpr size_t kL1ResidentTriangles = 32 * 1024 / 56;

/// The defaults (tuned with bench_trace on the CS184 scenes): a binary tree
/// down to single primitives, so that the collapse picks the leaves (up to 16
/// primitives); a leaf costs a fixed 0.7 (one memory latency: its blocks are
/// contiguous and load together) plus 0.3 per block, a node 1; and a cost
/// model for rays that start inside the scene with a length of about half its
/// mean extent (path-tracing bounce and shadow rays). A tree that sits in L1
/// (kL1ResidentTriangles) waits for no node, so there a block costs 0.6 of a
/// node visit: smaller leaves (CBgems: 13 -> 2.3 triangles and 1.4 -> 2.9
/// nodes per shadow ray; 1.4-1.8x the shadow rays per second, 1.1-1.3x the
/// others).
struct Bvh4Options {
  int threads = 0;  ///< build threads; 0: all available
  SahBuildOptions sah{.bins = 32, .max_leaf_size = 1, .leaf_block = 4, .traversal_cost = 1.0f, .ray_length = 0.5f};
  /// The collapse's costs. In a scene of at most kL1ResidentTriangles build
  /// references, l1_resident_block_cost (when not 0) replaces `block`: set it
  /// to 0 for `block` to hold in every scene.
  CollapseCosts collapse{.node = 1.0f, .leaf = 0.7f, .block = 0.3f, .max_leaf_size = 16, .ray_length = 0.5f};
  /// collapse.block for scenes of at most kL1ResidentTriangles build
  /// references (the triangles that enter the tree, plus pre-split
  /// fragments); 0: collapse.block for every scene.
  float l1_resident_block_cost = 0.6f;
  /// Extra build references per triangle that pre-splitting may add (presplit.h); 0: none.
  float presplit_budget = 0.0f;
};

struct Bvh4BuildStats {
  uint32_t triangles = 0;   ///< in the BVH: those with a non-finite vertex or zero area are left out
  uint32_t references = 0;  ///< build primitives: triangles plus the fragments pre-splitting added
  uint32_t nodes = 0, leaves = 0, blocks = 0;
  int depth = 0;        ///< inner-node levels
  double sah_cost = 0;  ///< node visits + block tests, area-weighted, root area 1
  size_t bytes = 0;     ///< nodes + leaf blocks
  double bytes_per_triangle = 0;
  double build_ms = 0;  ///< SAH build + collapse + leaf fill
};

/// BVH4 over triangle i = (positions[t.v0], positions[t.v1], positions[t.v2])
/// for t = triangles[i]; hits report prim = i. Triangles with a non-finite
/// vertex or exactly zero area are left out (they can never be hit). The tree
/// does not depend on `options.threads`.
Bvh4 build_bvh4(std::span<const float3> positions, std::span<const TriangleIndices> triangles,
                const Bvh4Options& options, Bvh4BuildStats* stats = nullptr);

/// Absolute padding added to every node box: 2^-20 of the largest coordinate
/// magnitude, several times the rounding error of the FMA slab test for
/// origins within that magnitude, so no box test misses a hit by rounding.
float bvh4_box_padding(float max_abs_coordinate);

}  // namespace pt
