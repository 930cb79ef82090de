// The binary BVH: one 32-byte node layout (tinybvh's), built by the
// assignment's midpoint split (bvh2_midpoint.cpp) or by binned SAH
// (bvh2_sah.cpp). Builders take spans of primitive boxes and centres and
// return nodes plus the primitive order; callers permute their primitives.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/math/bbox.h"

namespace pt {

/// 32 bytes. Inner node: count == 0, children at left_or_first and
/// left_or_first + 1. Leaf: primitives prim_order[left_or_first .. + count).
struct Bvh2Node {
  float3 lower;
  uint32_t left_or_first = 0;
  float3 upper;
  uint32_t count = 0;

  bool is_leaf() const { return count > 0; }
  BBox bounds() const { return {lower, upper}; }
};
static_assert(sizeof(Bvh2Node) == 32);

struct Bvh2 {
  std::vector<Bvh2Node> nodes;       ///< root at index 0
  std::vector<uint32_t> prim_order;  ///< input primitive index per leaf slot
};

/// Deepest a builder goes before falling back to median splits (so that
/// fixed-size traversal stacks suffice).
inline constexpr int kBvh2MaxDepth = 64;

/// The assignment's build: split at the midpoint of the longest axis of the
/// centroid bounds; leaves of at most `max_leaf_size` primitives.
Bvh2 build_bvh2_midpoint(std::span<const BBox> boxes, std::span<const float3> centers, uint32_t max_leaf_size);

/// Options of the binned SAH build. Costs are in units of one leaf-block test
/// (a block holds `leaf_block` primitives that are tested together).
struct SahBuildOptions {
  uint32_t bins = 32;           ///< bins per axis, 2..kMaxSahBins
  uint32_t max_leaf_size = 8;   ///< larger ranges are always split
  uint32_t leaf_block = 4;      ///< a leaf of n primitives costs ceil(n / leaf_block)
  float traversal_cost = 1.0f;  ///< cost of visiting one inner node
  /// Typical ray length relative to the scene's mean extent; 0: classic SAH
  /// (rays from far outside). A segment of length l starting inside the scene
  /// visits box B with probability ~ area(B) l / 2 + volume(B).
  float ray_length = 0.0f;
};
inline constexpr uint32_t kMaxSahBins = 64;

/// Binned surface-area-heuristic build: at every node, the cheapest of
/// `bins - 1` planes per axis over the centroid bounds, or a leaf when that is
/// cheaper and small enough. Runs in parallel in the calling oneTBB arena and
/// returns the same tree (byte for byte) for any thread count. Nodes are in
/// depth-first order. Depth never exceeds kBvh2MaxDepth.
Bvh2 build_bvh2_sah(std::span<const BBox> boxes, std::span<const float3> centers, const SahBuildOptions& options = {});

/// Depth (root = 1) and leaf count, for statistics and tests.
struct Bvh2Shape {
  int depth = 0;
  uint32_t leaves = 0;
};
Bvh2Shape bvh2_shape(const Bvh2& bvh);

}  // namespace pt
