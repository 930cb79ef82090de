// Collapse of a binary BVH into the 4-wide layout, choosing which binary
// nodes become 4-wide nodes and which become leaves by least SAH cost.
// Knows nothing about triangles: it returns, per leaf block lane, which input
// primitive goes there.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bvh2.h"
#include "bvh4.h"

namespace pt {

/// The 4-wide tree before leaf blocks are filled in.
struct Bvh4Topology {
  std::vector<Bvh4Node, HugePageAllocator<Bvh4Node>> nodes;  ///< depth-first, root first (if the root is inner)
  std::vector<uint32_t> block_prims;  ///< 4 lanes per block in BVH order: input primitive or kInvalidId
  uint32_t root = bvh4_ref::kEmptyRef;
  uint32_t leaves = 0;
  int depth = 0;        ///< inner-node levels on the longest root-to-leaf path
  double sah_cost = 0;  ///< sum of area-weighted node visits + block tests, root area = 1
};

/// SAH costs of the collapse, per unit of area relative to the root.
struct CollapseCosts {
  float node = 1.0f;           ///< visiting one 4-wide node
  float leaf = 0.0f;           ///< visiting a leaf, whatever its size
  float block = 1.0f;          ///< testing one block of four triangles (on top of `leaf`)
  uint32_t max_leaf_size = 8;  ///< largest leaf the collapse may form (binary leaves may be larger)
  /// Typical ray length relative to the scene's mean extent; 0: rays from far
  /// outside (classic SAH). Rays of a path tracer start inside the scene: a
  /// segment of length l visits box B with probability ~ (area(B) l / 2 + volume(B)),
  /// so a leaf whose box spans the room costs what it really costs.
  float ray_length = 0.0f;
};

/// Collapses `bvh2` into the 4-wide tree of least SAH cost that keeps its
/// binary subtrees. Every child box is enlarged by `padding` on each side.
/// Binary leaves of more than 4 * kMaxLeafBlocks primitives are not
/// representable: build the binary BVH with max_leaf_size <= 64. With
/// `prim_key` (one per primitive: fragments of one triangle share a key), a
/// leaf keeps only the first of the primitives that share a key.
Bvh4Topology collapse_to_bvh4(const Bvh2& bvh2, float padding, const CollapseCosts& costs = {},
                              std::span<const uint32_t> prim_key = {});

}  // namespace pt
